#include "markov/operator_step.hpp"
#include "base/petsc_compat.hpp"

#include "rcfd/operator_context.hpp"
#include "rcfd/run_context.hpp"

#include <algorithm>

namespace rcfd {

PetscErrorCode OperatorStep::setUp(const FrameChain &chain, Operator &op, const FractionSet &fractions,
                                   double solidDensity) {
  const Database &db = chain.database();
  PetscFunctionBeginUser;
  chain_ = &chain;
  op_ = &op;
  fractions_ = &fractions;
  rho_ = solidDensity;
  frame_ = -1;
  class_ = 0;
  composition_.clear(); // a background set for another chain does not carry over
  names_.clear();
  for (PetscInt c = 0; c < kWidth; ++c) names_.push_back("chain" + std::to_string(c));
  PetscCall(state_.create(db.layout(), fractions.size()));
  PetscCall(state_.createScalars(names_));
  // The cells outside the chain hold no solid: the operators move nothing
  // there, so they stay zero and apply() writes the chain's cells only.
  PetscCall(VecSet(state_.masses(), 0.0));
  PetscCall(VecSet(state_.amounts(), 0.0));
  RunContext ctx{db, fractions, solidDensity};
  ctx.numScalars = static_cast<int>(kWidth);
  ctx.scalarNames = &names_;
  PetscCall(op.setUp(ctx));
  PetscCall(chain.chainVector(alpha_.put()));
  PetscCall(VecDuplicate(alpha_, bulk_.put()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The bulk masses the operator of step k sees: frame k's shift applied to
// frame k's solid, alpha_k rho V (as a replay on frame k has them after the
// shift), on the chain's cells; the other cells hold none.
PetscErrorCode OperatorStep::background(int k) {
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

PetscErrorCode OperatorStep::apply(long long n, Vec x, PetscInt width) {
  const MPI_Comm comm = chain_->database().layout().comm();
  const std::vector<PetscInt> &cells = chain_->chainCells();
  const int nf = fractions_->size(), K = chain_->numFrames(), k = static_cast<int>(n % K);
  const PetscInt w = kWidth * nf; // amounts per cell: [scalar][class]
  PetscFunctionBeginUser;
  PetscCheck(width >= 1 && width <= kWidth, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "A chain step moves 1 to %d distributions at once, not %d", static_cast<int>(kWidth),
             static_cast<int>(width));
  if (!acts(n)) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCheck(composition_.empty() || (static_cast<int>(composition_.size()) == K &&
                                      composition_[static_cast<size_t>(k)].size() == cells.size() * static_cast<size_t>(nf)),
             comm, PETSC_ERR_ARG_SIZ, "The background set on a chain step is not one of its chain's frames and cells");
  PetscCall(background(k));
  // The bed at its mean composition (or the one set), and the distributions
  // as amounts of the current class; the other classes' amounts are zeroed and hold nothing.
  const PetscScalar *pb;
  const PetscScalar *pd;
  PetscScalar *pm, *pq, *px;
  PetscCall(VecGetArrayRead(bulk_, &pb));
  PetscCall(VecGetArrayWrite(state_.masses(), &pm));
  PetscCall(VecGetArrayWrite(state_.amounts(), &pq));
  PetscCall(VecGetArrayRead(x, &pd));
  for (size_t c = 0; c < cells.size(); ++c) {
    const PetscInt i = cells[c];
    const double *shares = composition_.empty() ? nullptr : &composition_[static_cast<size_t>(k)][c * static_cast<size_t>(nf)];
    for (int f = 0; f < nf; ++f) pm[i * nf + f] = pb[c] * (shares ? shares[f] : fractions_->massShare(f));
    std::fill(pq + i * w, pq + (i + 1) * w, 0.0);
    for (PetscInt s = 0; s < width; ++s) pq[i * w + s * nf + class_] = pd[static_cast<PetscInt>(c) * width + s];
  }
  PetscCall(VecRestoreArrayRead(x, &pd));
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
  PetscCall(op_->apply(step, state_));
  const PetscScalar *pr;
  PetscCall(VecGetArrayRead(state_.amounts(), &pr));
  PetscCall(VecGetArrayWrite(x, &px));
  for (size_t c = 0; c < cells.size(); ++c)
    for (PetscInt s = 0; s < width; ++s)
      px[static_cast<PetscInt>(c) * width + s] = pr[cells[c] * w + s * nf + class_];
  PetscCall(VecRestoreArrayWrite(x, &px));
  PetscCall(VecRestoreArrayRead(state_.amounts(), &pr));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
