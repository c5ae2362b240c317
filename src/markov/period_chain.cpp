#include "markov/period_chain.hpp"
#include "base/petsc_compat.hpp"

#include "markov/chain_block.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace rcfd {

namespace {
// A cell is kept for ever by the period chain when one period returns all of
// its solid to it (P(i, i) = 1) to round-off.
constexpr double kAbsorbing = 1e-12;
} // namespace

double centreHeight(const Mesh &mesh, const Vec3 &gravity, const std::vector<double> &share) {
  const double g = std::sqrt(gravity[0] * gravity[0] + gravity[1] * gravity[1] + gravity[2] * gravity[2]);
  double sum = 0.0, moment = 0.0;
  for (int c = 0; c < mesh.numCells(); ++c) {
    const Vec3 &x = mesh.cellCentre[static_cast<size_t>(c)];
    sum += share[static_cast<size_t>(c)];
    moment -= share[static_cast<size_t>(c)] * (x[0] * gravity[0] + x[1] * gravity[1] + x[2] * gravity[2]) / g;
  }
  return sum > 0 ? moment / sum : 0.0;
}

PetscErrorCode PeriodChain::setUp(const FrameChain &chain, const std::vector<char> &absorbing) {
  const Database &db = chain.database();
  const MPI_Comm comm = db.layout().comm();
  const std::vector<PetscInt> &cells = chain.chainCells();
  PetscFunctionBeginUser;
  chain_ = &chain;
  held_.clear();
  candidates_.clear();
  const PetscScalar *pa;
  PetscCall(VecGetArrayRead(db.alphaS(0), &pa));
  for (size_t c = 0; c < cells.size(); ++c) {
    const PetscInt i = cells[c];
    if (pa[i] <= 0) continue;
    const bool candidate = static_cast<size_t>(i) < absorbing.size() && absorbing[static_cast<size_t>(i)];
    (candidate ? candidates_ : held_).push_back(static_cast<PetscInt>(c));
  }
  PetscCall(VecRestoreArrayRead(db.alphaS(0), &pa));
  PetscInt counts[2] = {static_cast<PetscInt>(held_.size()), static_cast<PetscInt>(candidates_.size())};
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, counts, 2, MPIU_INT, MPI_SUM, comm));
  PetscCheck(counts[0] + counts[1] > 0, comm, PETSC_ERR_USER_INPUT,
             "Database '%s': no cell holds solid at frame 0, so the period chain has no state", db.path().c_str());
  // This rank's candidates are the block's columns from firstCandidate_ on
  // (MPI_Exscan leaves rank 0's undefined).
  {
    PetscMPIInt rank;
    PetscCallMPI(MPI_Comm_rank(comm, &rank));
    const PetscInt mine = static_cast<PetscInt>(candidates_.size());
    PetscInt before = 0;
    PetscCallMPI(MPI_Exscan(&mine, &before, 1, MPIU_INT, MPI_SUM, comm));
    firstCandidate_ = rank == 0 ? 0 : before;
  }
  numCandidates_ = counts[1];
  PetscCall(chain.blockVector(1, x_.put()));
  PetscCall(VecDuplicate(x_, y_.put()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The candidates this chain keeps for ever: each started alone (a column of
// a block) and followed through one period; kept whole (to 1e-12), the cell
// is an eigenvector of P of eigenvalue 1 of its own and no state.  The bulk's
// dead corner stays dead with the frames alone, but a class's drift may swap
// with it (then it is a state of the class's chain like any other).
PetscErrorCode PeriodChain::chooseStates(const std::vector<ChainStep *> &steps) {
  const MPI_Comm comm = chain_->database().layout().comm();
  const std::vector<PetscInt> &cells = chain_->chainCells();
  PetscFunctionBeginUser;
  std::vector<char> kept(candidates_.size(), 0);
  if (numCandidates_ > 0) {
    ChainBlock block;
    PetscCall(block.setUp(*chain_, numCandidates_, steps));
    PetscCall(block.getArrays());
    for (size_t j = 0; j < candidates_.size(); ++j)
      block.at(candidates_[j], firstCandidate_ + static_cast<PetscInt>(j)) = 1.0;
    PetscCall(block.restoreArrays());
    for (int k = 0; k < chain_->numFrames(); ++k) PetscCall(block.step(k));
    PetscCall(block.getArrays());
    for (size_t j = 0; j < candidates_.size(); ++j)
      kept[j] = block.at(candidates_[j], firstCandidate_ + static_cast<PetscInt>(j)) >= 1.0 - kAbsorbing;
    PetscCall(block.restoreArrays());
  }
  states_ = held_;
  double left[2] = {0.0, 0.0}; // states, frame 0's share of the cells kept for ever
  const PetscScalar *pm;
  PetscCall(VecGetArrayRead(chain_->massShare(0), &pm));
  for (size_t j = 0; j < candidates_.size(); ++j)
    if (kept[j])
      left[1] += pm[cells[static_cast<size_t>(candidates_[j])]];
    else
      states_.push_back(candidates_[j]);
  PetscCall(VecRestoreArrayRead(chain_->massShare(0), &pm));
  std::sort(states_.begin(), states_.end());
  left[0] = static_cast<double>(states_.size());
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, left, 2, MPI_DOUBLE, MPI_SUM, comm));
  numStates_ = static_cast<int>(left[0]);
  leftOut_ = left[1];
  {
    PetscInt n = 0;
    for (char k : kept) n += k;
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &n, 1, MPIU_INT, MPI_SUM, comm));
    absorbing_ = static_cast<int>(n);
  }
  PetscCheck(numStates_ > 0, comm, PETSC_ERR_USER_INPUT,
             "Database '%s': every cell holding solid at frame 0 keeps it for ever, so the period chain has no state",
             chain_->database().path().c_str());
  PetscFunctionReturn(PETSC_SUCCESS);
}

// One pass through the frames from frame 0: each frame's transfer, then the
// steps after it at step k (the carry acts at k = K - 1, the wrap).
PetscErrorCode PeriodChain::applyPeriod() {
  PetscFunctionBeginUser;
  for (int k = 0; k < chain_->numFrames(); ++k) {
    PetscCall(MatMult(chain_->transfer(k), x_, y_));
    for (ChainStep *s : steps_) PetscCall(s->apply(k, y_, 1));
    std::swap(x_, y_);
  }
  ++products_;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PeriodChain::mult(Mat P, Vec in, Vec out) {
  PeriodChain *self;
  const PetscScalar *pi;
  PetscScalar *px;
  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(P, &self));
  // Onto the chain's cells (zero off the states), one period, back onto the states.
  PetscCall(VecSet(self->x_, 0.0));
  PetscCall(VecGetArrayRead(in, &pi));
  PetscCall(VecGetArray(self->x_, &px));
  for (size_t s = 0; s < self->states_.size(); ++s) px[self->states_[s]] = pi[s];
  PetscCall(VecRestoreArray(self->x_, &px));
  PetscCall(VecRestoreArrayRead(in, &pi));
  PetscCall(self->applyPeriod());
  PetscScalar *po;
  const PetscScalar *pr;
  PetscCall(VecGetArrayRead(self->x_, &pr));
  PetscCall(VecGetArrayWrite(out, &po));
  for (size_t s = 0; s < self->states_.size(); ++s) po[s] = pr[self->states_[s]];
  PetscCall(VecRestoreArrayWrite(out, &po));
  PetscCall(VecRestoreArrayRead(self->x_, &pr));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PeriodChain::solve(ChainEigensolver &solver, const std::vector<ChainStep *> &steps, const char *what,
                                  PeriodSpectrum *out) {
  const Database &db = chain_->database();
  const MPI_Comm comm = db.layout().comm();
  const std::vector<PetscInt> &cells = chain_->chainCells();
  const double t0 = MPI_Wtime();
  PetscFunctionBeginUser;
  PetscCall(chooseStates(steps));
  steps_ = steps;
  products_ = 0;
  out->states = numStates_;
  out->absorbing = absorbing_;
  out->leftOut = leftOut_;
  // The database's check at frame 0: one period of frame 0's share over all
  // the chain's cells (what the states would lose is counted too).
  {
    const PetscScalar *pm;
    PetscScalar *px;
    PetscCall(VecGetArrayRead(chain_->massShare(0), &pm));
    PetscCall(VecGetArrayWrite(x_, &px));
    for (size_t c = 0; c < cells.size(); ++c) px[c] = pm[cells[c]];
    PetscCall(VecRestoreArrayWrite(x_, &px));
    OwnedVec m0;
    PetscCall(VecDuplicate(x_, m0.put()));
    PetscCall(VecCopy(x_, m0));
    PetscCall(applyPeriod());
    PetscCall(VecAXPY(m0, -1.0, x_));
    PetscReal r;
    PetscCall(VecNorm(m0, NORM_1, &r));
    out->residual = r;
  }
  OwnedMat P;
  PetscCall(MatCreateShell(comm, static_cast<PetscInt>(states_.size()), static_cast<PetscInt>(states_.size()),
                           PETSC_DETERMINE, PETSC_DETERMINE, this, P.put()));
  PetscCall(MatShellSetOperation(P, MATOP_MULT, reinterpret_cast<void (*)(void)>(&PeriodChain::mult)));
  LargestEigenpairs pairs;
  PetscCall(solver.largest(P, what, &pairs));
  out->lambda1 = pairs.lambda1;
  out->lambda2 = pairs.lambda2;
  out->lambda2Re = pairs.lambda2Re;
  out->lambda2Im = pairs.lambda2Im;
  out->iterations = pairs.iterations;
  const double period = chain_->numFrames() * chain_->dt();
  out->relaxationTime = out->lambda2 > 0 && out->lambda2 < 1 ? -period / std::log(out->lambda2)
                                                            : std::numeric_limits<double>::infinity();
  // Back onto all cells.
  PetscCall(VecDuplicate(chain_->massShare(0), out->stationary.put()));
  PetscCall(VecSet(out->stationary, 0.0));
  {
    const PetscScalar *pf;
    PetscScalar *ps;
    PetscCall(VecGetArrayRead(pairs.first, &pf));
    PetscCall(VecGetArray(out->stationary, &ps));
    for (size_t s = 0; s < states_.size(); ++s) ps[cells[static_cast<size_t>(states_[s])]] = pf[s];
    PetscCall(VecRestoreArray(out->stationary, &ps));
    PetscCall(VecRestoreArrayRead(pairs.first, &pf));
  }
  // Against frame 0's share on the states, renormalised: the absorbing cells'
  // solid is no part of the chain (each is a stationary distribution of its
  // own), and counted it would put twice its share into the L1.
  {
    OwnedVec reference;
    PetscCall(VecDuplicate(out->stationary, reference.put()));
    PetscCall(VecSet(reference, 0.0));
    const PetscScalar *pm;
    PetscScalar *pr;
    PetscCall(VecGetArrayRead(chain_->massShare(0), &pm));
    PetscCall(VecGetArray(reference, &pr));
    for (PetscInt s : states_) pr[cells[static_cast<size_t>(s)]] = pm[cells[static_cast<size_t>(s)]];
    PetscCall(VecRestoreArray(reference, &pr));
    PetscCall(VecRestoreArrayRead(chain_->massShare(0), &pm));
    PetscCall(VecScale(reference, 1.0 / (1.0 - leftOut_)));
    PetscCall(distributionDistance(out->stationary, reference, &out->l1, &out->max));
  }
  out->products = products_;
  out->seconds = MPI_Wtime() - t0;
  steps_.clear();
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
