// Many distributions over the cells stepping together with the frames: the
// block the tracer mixing, the zone passages and the pass counts propagate.
// Stored as chunks of kWidth interleaved columns, each moved by the frame's
// MAIJ matrix of kWidth components: PETSc's MAIJ product has unrolled kernels
// for up to 18 components (16 among them) and a generic one beyond, which on
// the default bed took 0.19 ms per column and step at 64 columns against
// 0.084 ms at 16 (docs/markov.md, "Cost").  The padding columns stay zero.
#pragma once

#include "markov/frame_chain.hpp"
#include "markov/operator_step.hpp"

#include <vector>

namespace rcfd {

class ChainBlock {
public:
  static constexpr PetscInt kWidth = ChainStep::kWidth;

  /// Collective.  `columns` zeroed distributions; the frames' MAIJ matrices
  /// are made on the first call and kept by later ones (resize).  Each step
  /// is the frame's shift followed by `steps` in order (a size class's drift,
  /// the carry at the wrap; none: the bulk's chain).
  PetscErrorCode setUp(const FrameChain &chain, PetscInt columns, const std::vector<ChainStep *> &steps = {});
  PetscInt columns() const { return columns_; }
  /// Collective.  Keeps the columns `keep` (old indices, in their new order)
  /// and drops the others.
  PetscErrorCode keepColumns(const std::vector<PetscInt> &keep);
  /// Collective.  Moves every column from t_k to t_{k+1} with frame k's
  /// transfer and the steps after it.
  PetscErrorCode step(long long k);
  /// Access to the values, column c of chain cell k (FrameChain::chainCells:
  /// this rank's k-th, whose local cell index is chainCells()[k]) as at(k, c),
  /// between getArrays and restoreArrays (no step in between).  The other
  /// cells hold nothing of a distribution started on the solid.
  PetscErrorCode getArrays();
  PetscErrorCode restoreArrays();
  PetscScalar &at(PetscInt i, PetscInt c) { return a_[static_cast<size_t>(c / kWidth)][i * kWidth + c % kWidth]; }

private:
  const FrameChain *chain_ = nullptr;
  std::vector<ChainStep *> after_;
  PetscInt columns_ = 0;
  std::vector<OwnedMat> step_;
  std::vector<OwnedVec> x_, y_;
  std::vector<PetscScalar *> a_;
};

} // namespace rcfd
