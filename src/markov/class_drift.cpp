#include "markov/class_drift.hpp"
#include "base/petsc_compat.hpp"

#include "rcfd/run_context.hpp"

#include <algorithm>

namespace rcfd {

PetscErrorCode ClassDrift::setFromOptions(MPI_Comm comm) {
  PetscFunctionBeginUser;
  drift_.setOptionsPrefix("drift_");
  PetscCall(drift_.setFromOptions(comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClassDrift::setUp(const FrameChain &chain, const FractionSet &fractions, double solidDensity) {
  const Database &db = chain.database();
  PetscFunctionBeginUser;
  chain_ = &chain;
  fractions_ = &fractions;
  rho_ = solidDensity;
  frame_ = -1;
  class_ = 0;
  // One scalar per distribution moved together: the drift carries a scalar's
  // amounts with the shares its swaps send.
  names_.clear();
  for (PetscInt c = 0; c < kWidth; ++c) names_.push_back("chain" + std::to_string(c));
  PetscCall(state_.create(db.layout(), fractions.size()));
  PetscCall(state_.createScalars(names_));
  // The cells outside the chain hold no solid: the drift never swaps there,
  // so they stay zero and apply() writes the chain's cells only.
  PetscCall(VecSet(state_.masses(), 0.0));
  PetscCall(VecSet(state_.amounts(), 0.0));
  RunContext ctx{db, fractions, solidDensity};
  ctx.numScalars = static_cast<int>(kWidth);
  ctx.scalarNames = &names_;
  moves_ = drift_.needed(ctx);
  PetscCall(drift_.setUp(ctx));
  PetscCall(chain.chainVector(alpha_.put()));
  PetscCall(VecDuplicate(alpha_, bulk_.put()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The bulk masses the drift of step k sees: frame k's shift applied to frame
// k's solid, alpha_k rho V (as a replay started on frame k has them after the
// shift), on the chain's cells; the other cells hold none.
PetscErrorCode ClassDrift::background(int k) {
  const Database &db = chain_->database();
  const std::vector<PetscInt> &cells = chain_->chainCells();
  PetscFunctionBeginUser;
  if (frame_ == k) PetscFunctionReturn(PETSC_SUCCESS);
  const PetscScalar *pa;
  PetscScalar *px;
  PetscCall(VecGetArrayRead(db.alphaS(k), &pa));
  PetscCall(VecGetArrayWrite(alpha_, &px));
  for (size_t c = 0; c < cells.size(); ++c) px[c] = pa[cells[c]] * rho_ * db.localVolumes()[cells[c]];
  PetscCall(VecRestoreArrayWrite(alpha_, &px));
  PetscCall(VecRestoreArrayRead(db.alphaS(k), &pa));
  PetscCall(MatMult(chain_->transfer(k), alpha_, bulk_));
  frame_ = k;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClassDrift::apply(long long n, Vec x, PetscInt width) {
  const MPI_Comm comm = chain_->database().layout().comm();
  const std::vector<PetscInt> &cells = chain_->chainCells();
  const int nf = fractions_->size(), K = chain_->numFrames(), k = static_cast<int>(n % K);
  const PetscInt w = kWidth * nf; // amounts per cell: [scalar][class]
  PetscFunctionBeginUser;
  PetscCheck(width >= 1 && width <= kWidth, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "ClassDrift::apply moves 1 to %d distributions at once, not %d", static_cast<int>(kWidth),
             static_cast<int>(width));
  PetscCall(background(k));
  // The bed at its mean composition, and the distributions as amounts of
  // the current class.  The other classes' amounts are zero, and so stay:
  // their shares are moved, but they hold nothing (a class's amounts of an
  // earlier call were copied back and are overwritten below or zeroed).
  const PetscScalar *pb;
  PetscScalar *pm, *pq, *px;
  PetscCall(VecGetArrayRead(bulk_, &pb));
  PetscCall(VecGetArrayWrite(state_.masses(), &pm));
  PetscCall(VecGetArrayWrite(state_.amounts(), &pq));
  PetscCall(VecGetArray(x, &px));
  for (size_t c = 0; c < cells.size(); ++c) {
    const PetscInt i = cells[c];
    for (int f = 0; f < nf; ++f) pm[i * nf + f] = pb[c] * fractions_->massShare(f);
    std::fill(pq + i * w, pq + (i + 1) * w, 0.0);
    for (PetscInt s = 0; s < width; ++s) pq[i * w + s * nf + class_] = px[static_cast<PetscInt>(c) * width + s];
  }
  PetscCall(VecRestoreArray(x, &px));
  PetscCall(VecRestoreArrayWrite(state_.amounts(), &pq));
  PetscCall(VecRestoreArrayWrite(state_.masses(), &pm));
  PetscCall(VecRestoreArrayRead(bulk_, &pb));
  StepInfo step;
  step.step = static_cast<long>(n);
  step.dt = chain_->dt();
  step.time = static_cast<double>(n) * step.dt;
  step.frame = k;
  step.nextFrame = (k + 1) % K;
  step.jump = step.nextFrame != k + 1;
  PetscCall(drift_.apply(step, state_));
  const PetscScalar *pr;
  PetscCall(VecGetArrayRead(state_.amounts(), &pr));
  PetscCall(VecGetArray(x, &px));
  for (size_t c = 0; c < cells.size(); ++c)
    for (PetscInt s = 0; s < width; ++s)
      px[static_cast<PetscInt>(c) * width + s] = pr[cells[c] * w + s * nf + class_];
  PetscCall(VecRestoreArray(x, &px));
  PetscCall(VecRestoreArrayRead(state_.amounts(), &pr));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClassDrift::view(PetscViewer viewer) const { return drift_.view(viewer); }

} // namespace rcfd
