// The `remap` carry kind (the default before `column`): composition kept, bulk from the next frame.
#include "operator/swap/carry_kinds.hpp"
#include "base/petsc_compat.hpp"

#include <vector>

namespace rcfd {
namespace {

class RemapCarry : public CarryKind {
public:
  std::string type() const override { return "remap"; }
  PetscErrorCode apply(const CarryContext &ctx, const StepInfo &step, FractionState &state) override;
  PetscErrorCode view(PetscViewer viewer) const override;
  bool carriesScalars() const override { return true; }

private:
  PetscErrorCode remap(const CarryContext &ctx, Vec targetAlpha, FractionState &state);
  long jumps = 0;
};

PetscErrorCode RemapCarry::apply(const CarryContext &ctx, const StepInfo &step, FractionState &state) {
  PetscFunctionBeginUser;
  if (step.jump) PetscCall(remap(ctx, ctx.db.alphaS(step.nextFrame), state));
  jumps += step.jump;
  PetscFunctionReturn(PETSC_SUCCESS);
}

// Composition remap.  Each cell's mass shares y_i = m_i / M are kept and
// scaled to the next frame's bulk M* = rho alpha* V; a cell without mass
// takes the mass-weighted composition of its face neighbours, or, with none,
// the bed's.  Factors s_i = (total of fraction i before) / (total after), the
// same in every cell, then conserve every fraction exactly; they differ from 1
// by the difference between the frames, so the bulk is matched up to that.
// With scalars a cell's amounts take the factor M* / M of its masses (a mass
// keeps its value; an empty cell takes its neighbours' amounts with their
// masses, so their mass-weighted values, or the bed's), and each scalar and
// fraction its own factor sigma = (amount before) / (after), the masses' rule on
// the amounts, so that every total is kept; for a uniform value sigma = s_i to
// round-off, so it stays uniform (docs/scalars.md).
PetscErrorCode RemapCarry::remap(const CarryContext &ctx, Vec targetAlpha, FractionState &state) {
  PetscFunctionBeginUser;
  FaceExchange &x = ctx.exchange;
  FaceExchange *ax = state.numScalars() > 0 ? ctx.amountExchange : nullptr;
  const int nf = ctx.numFractions, na = nf * state.numScalars();
  PetscCheck(!ax == !(na > 0), ctx.db.layout().comm(), PETSC_ERR_ARG_WRONGSTATE,
             "The remap carry was set up without the state's scalars");
  const double rho = ctx.solidDensity;
  // Neighbour masses (and amounts) summed per owned cell: gather, add each
  // face's other side, and add the sums into a zeroed work state.
  FractionState neighbours;
  PetscCall(neighbours.create(ctx.db.layout(), nf));
  Vec neighbourAmounts = ax ? state.amountsScratch() : nullptr; // the scratch is free between operators
  if (ax) {
    PetscCall(VecZeroEntries(neighbourAmounts));
    PetscCall(ax->gatherBegin(state.amounts()));
    PetscCall(ax->gatherEnd());
  }
  PetscCall(x.sweep(
      state.masses(),
      [&] {
        for (const SwapFace &f : x.faces()) {
          PetscScalar *sumLower = x.changeAt(f.lower), *sumUpper = x.changeAt(f.upper);
          const PetscScalar *mLower = x.massAt(f.lower), *mUpper = x.massAt(f.upper);
          for (int i = 0; i < nf; ++i) {
            sumLower[i] += mUpper[i];
            sumUpper[i] += mLower[i];
          }
          if (!ax) continue;
          PetscScalar *aSumLower = ax->changeAt(f.lower), *aSumUpper = ax->changeAt(f.upper);
          const PetscScalar *aLower = ax->massAt(f.lower), *aUpper = ax->massAt(f.upper);
          for (int k = 0; k < na; ++k) {
            aSumLower[k] += aUpper[k];
            aSumUpper[k] += aLower[k];
          }
        }
      },
      neighbours.masses()));
  if (ax) {
    PetscCall(ax->endKernel());
    PetscCall(ax->addChanges(neighbourAmounts));
  }

  std::vector<double> before, amountsBefore;
  PetscCall(state.totals(&before));
  if (ax) PetscCall(state.amountTotals(&amountsBefore));
  double bedTotal = 0.0;
  for (double b : before) bedTotal += b;
  PetscScalar *m, *am = nullptr;
  const PetscScalar *nb, *a, *nba = nullptr;
  const auto &vol = ctx.db.localVolumes();
  PetscCall(VecGetArray(state.masses(), &m));
  PetscCall(VecGetArrayRead(neighbours.masses(), &nb));
  PetscCall(VecGetArrayRead(targetAlpha, &a));
  if (ax) {
    PetscCall(VecGetArray(state.amounts(), &am));
    PetscCall(VecGetArrayRead(neighbourAmounts, &nba));
  }
  for (size_t c = 0; c < vol.size(); ++c) {
    PetscScalar *mc = m + c * nf;
    const PetscScalar *source = mc;
    double M = 0.0;
    for (int i = 0; i < nf; ++i) M += mc[i];
    const bool own = M > 0.0;
    if (!own) { // empty cell: the neighbours' composition
      source = nb + c * nf;
      for (int i = 0; i < nf; ++i) M += source[i];
    }
    const double target = rho * a[c] * vol[c];
    for (int i = 0; i < nf; ++i)
      mc[i] = M > 0.0 ? target * source[i] / M : target * before[i] / bedTotal;
    if (!ax) continue;
    PetscScalar *ac = am + c * na;
    const PetscScalar *amountSource = own ? ac : nba + c * na;
    for (int k = 0; k < na; ++k)
      ac[k] = M > 0.0 ? target * amountSource[k] / M : target * amountsBefore[k] / bedTotal;
  }
  if (ax) {
    PetscCall(VecRestoreArrayRead(neighbourAmounts, &nba));
    PetscCall(VecRestoreArray(state.amounts(), &am));
  }
  PetscCall(VecRestoreArrayRead(targetAlpha, &a));
  PetscCall(VecRestoreArrayRead(neighbours.masses(), &nb));
  PetscCall(VecRestoreArray(state.masses(), &m));
  std::vector<double> after;
  PetscCall(state.totals(&after));
  std::vector<double> factor(nf, 1.0);
  for (int i = 0; i < nf; ++i) factor[i] = after[i] > 0 ? before[i] / after[i] : 1.0;
  PetscInt n;
  PetscCall(VecGetLocalSize(state.masses(), &n));
  PetscCall(VecGetArray(state.masses(), &m));
  for (PetscInt k = 0; k < n; ++k) m[k] *= factor[k % nf];
  PetscCall(VecRestoreArray(state.masses(), &m));
  if (ax) {
    std::vector<double> amountsAfter;
    PetscCall(state.amountTotals(&amountsAfter));
    std::vector<double> sigma(na, 1.0);
    for (int k = 0; k < na; ++k) sigma[k] = amountsAfter[k] > 0 ? amountsBefore[k] / amountsAfter[k] : 1.0;
    PetscCall(state.scaleAmounts(sigma));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode RemapCarry::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer, "carry: composition remap at %ld jumps\n", jumps));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

std::unique_ptr<CarryKind> makeRemapCarry() { return std::make_unique<RemapCarry>(); }

} // namespace rcfd
