// The `level` carry kind: levelling sweeps after a jump.
#include "operator/swap/carry_kinds.hpp"
#include "base/checked_options.hpp"
#include "base/petsc_compat.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace rcfd {
namespace {

class LevelCarry : public CarryKind {
public:
  std::string type() const override { return "level"; }
  PetscErrorCode setFromOptions(MPI_Comm comm) override;
  bool needed() const override { return sweeps > 0 || sweepsPerStep > 0; }
  PetscErrorCode apply(const CarryContext &ctx, const StepInfo &step, FractionState &state) override;
  PetscErrorCode view(PetscViewer viewer) const override;
  bool carriesScalars() const override { return true; }

private:
  PetscErrorCode sweep(const CarryContext &ctx, const std::vector<double> &targetAlpha,
                       FractionState &state);
  PetscInt sweeps = 20, sweepsPerStep = 0;
  long applications = 0, totalSweeps = 0;
};

PetscErrorCode LevelCarry::setFromOptions(MPI_Comm comm) {
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, prefix.c_str(), "Levelling carry (-carry_type level)", "rcfd");
  PetscCall(checkedInt(PetscOptionsObject, "-sweeps",
                       "Levelling sweeps after each jump (0: none)", &sweeps, 0, 1000000));
  PetscCall(checkedInt(PetscOptionsObject, "-sweeps_per_step",
                       "Levelling sweeps after every step", &sweepsPerStep, 0, 1000000));
  PetscOptionsEnd();
  PetscCheck(sweeps >= 0 && sweepsPerStep >= 0, comm, PETSC_ERR_USER_INPUT,
             "-%ssweeps and -%ssweeps_per_step must be >= 0", prefix.c_str(), prefix.c_str());
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode LevelCarry::apply(const CarryContext &ctx, const StepInfo &step, FractionState &state) {
  PetscFunctionBeginUser;
  const PetscInt n = step.jump ? sweeps + sweepsPerStep : sweepsPerStep;
  if (n == 0) PetscFunctionReturn(PETSC_SUCCESS);
  std::vector<double> target;
  PetscCall(ctx.exchange.gatherScalar(ctx.db.alphaS(step.nextFrame), &target));
  for (PetscInt s = 0; s < n; ++s) PetscCall(sweep(ctx, target, state));
  ++applications;
  totalSweeps += n;
  PetscFunctionReturn(PETSC_SUCCESS);
}

// One levelling sweep: the excess e = M - M_target of each cell diffuses to
// its neighbours, carrying the sender's composition.  Across a face from a
// to b (e_a > e_b) the swap moves X = min(theta (e_a - e_b) / 2, theta M_a)
// with theta = 1 / (faces per cell), so no cell gives more than it has: each
// fraction stays non-negative and each fraction's total is unchanged.  The
// mismatch's L1 norm never grows, and it shrinks wherever excess and deficit
// are neighbours.  With scalars the moved mixture takes its sender's amounts
// in the same share X / M as its masses (a moved mass keeps its value), so
// every amount's total is kept too and values stay within their range.
PetscErrorCode LevelCarry::sweep(const CarryContext &ctx, const std::vector<double> &targetAlpha,
                                 FractionState &state) {
  PetscFunctionBeginUser;
  FaceExchange &x = ctx.exchange;
  const int nf = ctx.numFractions;
  const double rho = ctx.solidDensity;
  const double theta = 1.0 / std::max(1, x.maxFacesPerCell());
  FaceExchange *ax = state.numScalars() > 0 ? ctx.amountExchange : nullptr;
  const int na = nf * state.numScalars();
  PetscCheck(!ax == !(na > 0), ctx.db.layout().comm(), PETSC_ERR_ARG_WRONGSTATE,
             "The level carry was set up without the state's scalars");
  if (ax) {
    PetscCall(ax->gatherBegin(state.amounts()));
    PetscCall(ax->gatherEnd());
  }
  PetscCall(x.sweep(state.masses(), [&] {
    for (const SwapFace &f : x.faces()) {
      const PetscScalar *mA = x.massAt(f.lower), *mB = x.massAt(f.upper);
      double MA = 0.0, MB = 0.0;
      for (int i = 0; i < nf; ++i) MA += mA[i], MB += mB[i];
      const double eA = MA - rho * targetAlpha[f.lower] * f.volumeLower;
      const double eB = MB - rho * targetAlpha[f.upper] * f.volumeUpper;
      if (eA == eB) continue;
      const bool fromA = eA > eB;
      const double Msend = fromA ? MA : MB;
      const double X = std::min(0.5 * theta * std::fabs(eA - eB), theta * Msend);
      if (!(X > 0.0)) continue;
      const PetscScalar *ms = fromA ? mA : mB;
      PetscScalar *dS = x.changeAt(fromA ? f.lower : f.upper);
      PetscScalar *dR = x.changeAt(fromA ? f.upper : f.lower);
      for (int i = 0; i < nf; ++i) {
        const double moved = X * ms[i] / Msend;
        dS[i] -= moved;
        dR[i] += moved;
      }
      if (!ax) continue;
      const PetscScalar *as = ax->massAt(fromA ? f.lower : f.upper);
      PetscScalar *eS = ax->changeAt(fromA ? f.lower : f.upper), *eR = ax->changeAt(fromA ? f.upper : f.lower);
      for (int k = 0; k < na; ++k) {
        const double moved = X * as[k] / Msend;
        eS[k] -= moved;
        eR[k] += moved;
      }
    }
  }));
  if (ax) {
    PetscCall(ax->endKernel());
    PetscCall(ax->addChanges(state.amounts()));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode LevelCarry::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer,
                                   "carry: %d levelling sweeps per jump, %d per step; %ld sweeps in %ld applications\n",
                                   (int)sweeps, (int)sweepsPerStep, totalSweeps, applications));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

std::unique_ptr<CarryKind> makeLevelCarry() { return std::make_unique<LevelCarry>(); }

} // namespace rcfd
