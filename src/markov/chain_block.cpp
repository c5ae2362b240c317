#include "markov/chain_block.hpp"
#include "base/petsc_compat.hpp"

namespace rcfd {

PetscErrorCode ChainBlock::setUp(const FrameChain &chain, PetscInt columns, const std::vector<ChainStep *> &steps) {
  PetscFunctionBeginUser;
  PetscCheck(a_.empty(), chain.database().layout().comm(), PETSC_ERR_ARG_WRONGSTATE,
             "ChainBlock::setUp between getArrays and restoreArrays");
  chain_ = &chain;
  after_ = steps;
  columns_ = columns;
  if (step_.empty()) PetscCall(chain.blockTransfers(kWidth, &step_));
  x_.clear();
  y_.clear();
  for (PetscInt c = 0; c < columns; c += kWidth) {
    OwnedVec x, y;
    PetscCall(chain.blockVector(kWidth, x.put()));
    PetscCall(VecDuplicate(x, y.put()));
    x_.push_back(std::move(x));
    y_.push_back(std::move(y));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ChainBlock::keepColumns(const std::vector<PetscInt> &keep) {
  PetscFunctionBeginUser;
  ChainBlock kept;
  kept.step_ = std::move(step_);
  PetscCall(kept.setUp(*chain_, static_cast<PetscInt>(keep.size()), after_));
  const PetscInt n = chain_->numChainCells();
  PetscCall(getArrays());
  PetscCall(kept.getArrays());
  for (PetscInt i = 0; i < n; ++i)
    for (size_t c = 0; c < keep.size(); ++c) kept.at(i, static_cast<PetscInt>(c)) = at(i, keep[c]);
  PetscCall(kept.restoreArrays());
  PetscCall(restoreArrays());
  *this = std::move(kept);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ChainBlock::step(long long k) {
  PetscFunctionBeginUser;
  const Mat T = step_[static_cast<size_t>(k % chain_->numFrames())];
  for (size_t b = 0; b < x_.size(); ++b) {
    PetscCall(MatMult(T, x_[b], y_[b]));
    for (ChainStep *s : after_) PetscCall(s->apply(k, y_[b], kWidth));
    std::swap(x_[b], y_[b]);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ChainBlock::getArrays() {
  PetscFunctionBeginUser;
  a_.resize(x_.size());
  for (size_t b = 0; b < x_.size(); ++b) PetscCall(VecGetArray(x_[b], &a_[b]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ChainBlock::restoreArrays() {
  PetscFunctionBeginUser;
  for (size_t b = 0; b < x_.size(); ++b) PetscCall(VecRestoreArray(x_[b], &a_[b]));
  a_.clear();
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
