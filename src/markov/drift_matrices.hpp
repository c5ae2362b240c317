// A size class's linearised drift as one sparse matrix per frame
// (docs/markov.md, "Size classes: the cost").
//
// With the bed held at its mean composition, the class's drift at frame k is a
// fixed linear map D_k of the class's distribution (markov/class_drift.hpp),
// the same in every period.  Handing 16 distributions to the run's drift
// operator at every step of every propagation costs eight times the frame's
// shift; D_k, read off the operator once per frame and applied as a sparse
// product, costs a fraction of it.
//
// D_k is read off exactly by probing: the drift swaps only across faces with
// a component along gravity, one face per sub-step, so what it does to cell i
// reaches no further than s faces (s, its sub-steps) along those faces.  The
// cells are coloured so that two of one colour are more than 2 s such faces
// apart; a unit amount in every cell of one colour then comes out with each
// cell's share holding the share of the one cell of that colour within s
// faces of it.  Sixteen colours go through the operator at once, so a frame
// with one sub-step (3 colours) takes one call of the operator.  Should a
// frame take more sub-steps than the colouring allows, the cells are coloured
// again for the new reach and the frame probed again.
#pragma once

#include "markov/class_drift.hpp"

#include <map>
#include <vector>

namespace rcfd {

class DriftMatrices : public ChainStep {
public:
  /// Collective.  Reads D_k off `drift` (set to its class, sameEveryPeriod())
  /// at every frame of `chain`.  The chain must outlive this object.
  PetscErrorCode setUp(const FrameChain &chain, ClassDrift &drift);
  /// Collective.  x <- D_{n mod K} x for `width` interleaved distributions.
  PetscErrorCode apply(long long n, Vec x, PetscInt width) override;
  /// D_k over the chain cells (k modulo the number of frames).
  Mat matrix(long long k) const { return d_[static_cast<size_t>(k % static_cast<long long>(d_.size()))]; }
  /// The most faces a step moved solid across (the drift's largest sub-step count).
  int reach() const { return reach_; }

private:
  // The colouring for reach r: colour_ per mesh cell, and per chain cell of
  // this rank the chain cells within r faces along gravity (CSR, with their colours).
  PetscErrorCode colour(int r);
  PetscErrorCode probe(int k, ClassDrift &drift, Mat D, bool *explained);

  const FrameChain *chain_ = nullptr;
  int reach_ = 0, colours_ = 0;
  std::vector<std::vector<int>> vertical_; // per mesh cell, its neighbours across faces along gravity
  std::vector<int> colour_;
  std::vector<PetscInt> ballStart_, ballCell_; // ballCell_: chain indices (all ranks' numbering)
  std::vector<int> ballColour_, localColour_;  // localColour_: each chain cell of this rank's
  std::vector<PetscInt> diagCount_, offCount_; // each row's ball on and off this rank (preallocation)
  PetscInt first_ = 0;                         // this rank's first chain index
  std::vector<OwnedMat> d_;
  std::map<PetscInt, std::vector<OwnedMat>> blocks_; // per width, each frame's MAIJ
  std::map<PetscInt, OwnedVec> work_;
};

} // namespace rcfd
