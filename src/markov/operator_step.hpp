// A run's operator as a step of the chain (docs/markov.md, "Size classes" and
// "The wrap"): after a frame's shift, the chain's distributions are handed to
// one of the run's own operators (the drift, the carry) as the amounts of
// scalars of one class, in a bed at its mean composition.
//
// The run's face swaps and carries are not linear in the masses, but they
// move a scalar's amounts with the shares they send of the masses (a moved
// mass takes its sending cell's value, docs/scalars.md): with the masses
// fixed, what they do to the amounts is linear, a column-stochastic step of a
// chain.  The masses are fixed at the bed's mean composition: every cell holds
// the bulk the frame's shift gives it (T_k alpha_k rho V) with the
// inventory's mass shares.  Each distribution of a chunk is one scalar, so
// one call of the operator moves ChainStep::kWidth distributions.
#pragma once

#include "markov/frame_chain.hpp"
#include "rcfd/fractions.hpp"
#include "rcfd/operator.hpp"

#include <string>
#include <vector>

namespace rcfd {

/// What the propagations apply after each frame's shift (ChainBlock).
class ChainStep {
public:
  /// Distributions moved per call at most (ChainBlock's width).
  static constexpr PetscInt kWidth = 16;
  virtual ~ChainStep() = default;
  /// Collective.  Moves `width` <= kWidth interleaved distributions over the
  /// chain's cells (FrameChain::blockVector of `width` columns) at step n
  /// (frame n mod K), after that frame's shift.
  virtual PetscErrorCode apply(long long n, Vec x, PetscInt width) = 0;
};

/// One of the run's operators (set from options by its owner) as a ChainStep.
class OperatorStep : public ChainStep {
public:
  /// Collective.  Sets `op` up on the chain's database for `fractions`, with
  /// kWidth scalars.  chain, op and fractions must outlive this object.
  PetscErrorCode setUp(const FrameChain &chain, Operator &op, const FractionSet &fractions, double solidDensity);
  /// The class whose amounts hold the distributions (0 .. fractions - 1).
  void setClass(int i) { class_ = i; }
  int currentClass() const { return class_; }
  /// The bed the operator sees after frame k's shift: per frame, per chain
  /// cell of this rank, the classes' mass shares (nf each, summing to 1;
  /// ClassBackground).  Empty (the default): the inventory's shares in every
  /// cell, the bed at its mean composition.
  void setComposition(std::vector<std::vector<double>> shares) {
    composition_ = std::move(shares);
  }
  bool hasComposition() const { return !composition_.empty(); }
  /// Whether the operator acts at step n (all steps, unless a derived step says).
  virtual bool acts(long long n) const { return n >= 0; }
  PetscErrorCode apply(long long n, Vec x, PetscInt width) override;

private:
  PetscErrorCode background(int k);

  const FrameChain *chain_ = nullptr;
  Operator *op_ = nullptr;
  const FractionSet *fractions_ = nullptr;
  FractionState state_;
  std::vector<std::string> names_;
  int class_ = 0;
  double rho_ = 0.0;
  int frame_ = -1;        // the frame whose bulk bulk_ holds
  OwnedVec alpha_, bulk_; // over the chain cells: alpha_k rho V, and T_k of it
  std::vector<std::vector<double>> composition_; // per frame, chain cell and class (empty: the inventory's)
};

} // namespace rcfd
