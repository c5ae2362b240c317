#include "rcfd/swaps.hpp"

#include "operator/swap/face_exchange.hpp"

#include <algorithm>
#include <cmath>

namespace rcfd {

CarryOperator::CarryOperator() = default;
CarryOperator::~CarryOperator() = default;

PetscErrorCode CarryOperator::setFromOptions(MPI_Comm comm) {
  PetscFunctionBeginUser;
  char text[32];
  PetscBool set = PETSC_FALSE;
  PetscOptionsBegin(comm, prefix.c_str(), "Carrying the state across jumps between frames", "rcfd");
  PetscCall(PetscOptionsString("-type", "remap (composition onto the next frame's bulk) or level",
                               "", kind.c_str(), text, sizeof text, &set));
  if (set) kind = text;
  PetscCall(PetscOptionsInt("-sweeps", "Levelling sweeps after each jump (0: none)", "", sweeps,
                            &sweeps, nullptr));
  PetscCall(PetscOptionsInt("-sweeps_per_step", "Levelling sweeps after every step", "",
                            sweepsPerStep, &sweepsPerStep, nullptr));
  PetscOptionsEnd();
  PetscCheck(kind == "remap" || kind == "level", comm, PETSC_ERR_USER_INPUT,
             "-%stype %s is not known; use remap or level", prefix.c_str(), kind.c_str());
  PetscCheck(sweeps >= 0 && sweepsPerStep >= 0, comm, PETSC_ERR_USER_INPUT,
             "-%ssweeps and -%ssweeps_per_step must be >= 0", prefix.c_str(), prefix.c_str());
  PetscFunctionReturn(PETSC_SUCCESS);
}

bool CarryOperator::needed(const RunContext &) const {
  return kind == "remap" || sweeps > 0 || sweepsPerStep > 0;
}

PetscErrorCode CarryOperator::setUp(const RunContext &ctx) {
  PetscFunctionBeginUser;
  db = &ctx.db;
  nf = ctx.fractions.size();
  rho = ctx.solidDensity;
  exchange = std::make_unique<FaceExchange>();
  PetscCall(exchange->setUp(ctx.db, nf, {0.0, 0.0, 0.0}, 0.0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode CarryOperator::apply(const StepInfo &step, FractionState &state) {
  PetscFunctionBeginUser;
  if (kind == "remap") {
    if (step.jump) PetscCall(remap(db->alphaS(step.nextFrame), state));
    jumps += step.jump;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  const PetscInt n = step.jump ? sweeps + sweepsPerStep : sweepsPerStep;
  if (n == 0) PetscFunctionReturn(PETSC_SUCCESS);
  std::vector<double> target;
  PetscCall(exchange->gatherScalar(db->alphaS(step.nextFrame), &target));
  for (PetscInt s = 0; s < n; ++s) PetscCall(sweep(target, state));
  ++jumps;
  totalSweeps += n;
  PetscFunctionReturn(PETSC_SUCCESS);
}

// One levelling sweep: the excess e = M - M_target of each cell diffuses to
// its neighbours, carrying the sender's composition.  Across a face from a
// to b (e_a > e_b) the swap moves X = min(theta (e_a - e_b) / 2, theta M_a)
// with theta = 1 / (faces per cell), so no cell gives more than it has: each
// fraction stays non-negative and each fraction's total is unchanged.  The
// mismatch's L1 norm never grows, and it shrinks wherever excess and deficit
// are neighbours.
PetscErrorCode CarryOperator::sweep(const std::vector<double> &targetAlpha, FractionState &state) {
  PetscFunctionBeginUser;
  PetscCall(exchange->gather(state.masses()));
  const double theta = 1.0 / std::max(1, exchange->maxFacesPerCell());
  for (const SwapFace &f : exchange->faces()) {
    const PetscScalar *mA = exchange->massAt(f.lower), *mB = exchange->massAt(f.upper);
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
    PetscScalar *dS = exchange->changeAt(fromA ? f.lower : f.upper);
    PetscScalar *dR = exchange->changeAt(fromA ? f.upper : f.lower);
    for (int i = 0; i < nf; ++i) {
      const double moved = X * ms[i] / Msend;
      dS[i] -= moved;
      dR[i] += moved;
    }
  }
  PetscCall(exchange->endKernel());
  PetscCall(exchange->scatterAdd(state.masses()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// Composition remap.  Each cell's mass shares y_i = m_i / M are kept and
// scaled to the next frame's bulk M* = rho alpha* V; a cell without mass
// takes the mass-weighted composition of its face neighbours, or, with none,
// the bed's.  Factors s_i = (total of fraction i before) / (total after), the
// same in every cell, then conserve every fraction exactly; they differ from 1
// by the difference between the frames, so the bulk is matched up to that.
PetscErrorCode CarryOperator::remap(Vec targetAlpha, FractionState &state) {
  PetscFunctionBeginUser;
  // Neighbour masses summed per owned cell: gather, add each face's other
  // side, and scatter-add into a zeroed work state.
  FractionState neighbours;
  PetscCall(neighbours.create(db->layout(), nf));
  PetscCall(exchange->gather(state.masses()));
  for (const SwapFace &f : exchange->faces()) {
    PetscScalar *sumLower = exchange->changeAt(f.lower), *sumUpper = exchange->changeAt(f.upper);
    const PetscScalar *mLower = exchange->massAt(f.lower), *mUpper = exchange->massAt(f.upper);
    for (int i = 0; i < nf; ++i) {
      sumLower[i] += mUpper[i];
      sumUpper[i] += mLower[i];
    }
  }
  PetscCall(exchange->endKernel());
  PetscCall(exchange->scatterAdd(neighbours.masses()));

  std::vector<double> before, bed;
  PetscCall(state.totals(&before));
  double bedTotal = 0.0;
  for (double b : before) bedTotal += b;
  PetscScalar *m;
  const PetscScalar *nb, *a;
  const auto &vol = db->localVolumes();
  PetscCall(VecGetArray(state.masses(), &m));
  PetscCall(VecGetArrayRead(neighbours.masses(), &nb));
  PetscCall(VecGetArrayRead(targetAlpha, &a));
  for (size_t c = 0; c < vol.size(); ++c) {
    PetscScalar *mc = m + c * nf;
    const PetscScalar *source = mc;
    double M = 0.0;
    for (int i = 0; i < nf; ++i) M += mc[i];
    if (!(M > 0.0)) { // empty cell: the neighbours' composition
      source = nb + c * nf;
      for (int i = 0; i < nf; ++i) M += source[i];
    }
    const double target = rho * a[c] * vol[c];
    for (int i = 0; i < nf; ++i)
      mc[i] = M > 0.0 ? target * source[i] / M : target * before[i] / bedTotal;
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
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode CarryOperator::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  if (kind == "remap") {
    PetscCall(PetscViewerASCIIPrintf(viewer, "carry: composition remap at %ld jumps\n", jumps));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(PetscViewerASCIIPrintf(viewer,
                                   "carry: %d levelling sweeps per jump, %d per step; %ld sweeps in %ld applications\n",
                                   (int)sweeps, (int)sweepsPerStep, totalSweeps, jumps));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
