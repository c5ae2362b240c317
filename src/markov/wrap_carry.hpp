// The wrap from the last frame to the first as the run's carry does it
// (docs/markov.md, "The wrap"): a chain over a replay longer than the
// database steps from frame K - 1 back to frame 0, where the bed the last
// frame's shift leaves is not frame 0's (the database's end does not meet its
// start).  Without a carry the chain treats the frames as periodic, and solid
// that lands in a cell frame 0 holds empty stays there (its column is the
// identity's); with it, the distributions are carried onto frame 0's bed as
// the run carries its state across the same jump (-carry_type, the column
// kind by default), the bed at its mean composition (OperatorStep).
#pragma once

#include "markov/operator_step.hpp"
#include "rcfd/carry.hpp"

namespace rcfd {

class WrapCarry : public OperatorStep {
public:
  /// Collective.  Reads the carry's options (-carry_type and the kind's, as
  /// rcfd run reads them).
  PetscErrorCode setFromOptions(MPI_Comm comm);
  /// Collective.  Sets the carry up on the chain's database (one class: the
  /// bed's composition is the same in every cell, so every class is carried
  /// alike).  chain must outlive this object.
  PetscErrorCode setUp(const FrameChain &chain, double solidDensity);
  /// Only the step from the last frame to the first.
  bool acts(long long n) const override { return frames_ > 0 && n % frames_ == frames_ - 1; }
  const std::string &kind() const { return carry_.kindName(); }

private:
  CarryOperator carry_;
  FractionSet one_;
  int frames_ = 0;
};

} // namespace rcfd
