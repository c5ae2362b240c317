// The chain of one size class (docs/markov.md, "Size classes"): the frame's
// shift followed by that class's drift, the run's drift operator with its
// swaps linearised on the bed's mean composition.
//
// The drift's face swaps are not linear in the masses: what a face swaps
// depends on the sums over all classes in both cells (the top-up that keeps
// the bulk, the face limiter, the local d32, hindrance), so one particle's
// next cell depends on where the others are, and there is no chain of a class
// without fixing them.  They are fixed at the bed's mean composition: at every
// step the cells hold the bulk the frame's shift gives them (T_k alpha_k rho V)
// with the inventory's mass shares w_i, and the swaps are worked out from
// those masses.  A class's particles then move with the share of its mass the
// swaps send from each cell, which is linear in where they are: the run's
// drift carries a scalar's amounts with exactly these shares (a swapped mass
// takes its sending cell's value, docs/scalars.md), so the class's
// distributions are handed to the run's own DriftOperator as amounts of
// scalars, one scalar per distribution, and the drift code is not repeated.
// The chain is the one a tagged particle of the class follows in a bed kept at
// the inventory's composition: exact for a tracer in a mixed bed, an
// approximation where the bed has segregated (the real swaps then differ).
// Every step conserves each distribution (what a face sends one cell the
// other receives), so the class chain is column-stochastic like the bulk's.
#pragma once

#include "markov/frame_chain.hpp"
#include "rcfd/drift.hpp"
#include "rcfd/fractions.hpp"

#include <string>
#include <vector>

namespace rcfd {

class ClassDrift {
public:
  /// Distributions moved per call at most (ChainBlock's width).
  static constexpr PetscInt kWidth = 16;

  /// Collective.  Reads the drift's options (-drift_*, as rcfd run reads them).
  PetscErrorCode setFromOptions(MPI_Comm comm);
  /// Collective.  Sets the drift up on the chain's database for `fractions`
  /// (the run's -fractions_diameters, -fractions_mass_shares).  chain and
  /// fractions must outlive this object.
  PetscErrorCode setUp(const FrameChain &chain, const FractionSet &fractions, double solidDensity);
  int numClasses() const { return fractions_ ? fractions_->size() : 0; }
  /// The class the following apply() calls move (0 .. numClasses() - 1).
  void setClass(int i) { class_ = i; }
  int currentClass() const { return class_; }
  /// Whether the drift moves anything (a k_d of 0 or one class: it does not,
  /// and every class's chain is the bulk's to the bit).
  bool moves() const { return moves_; }

  /// Collective.  Applies the current class's linearised drift of step n
  /// (frame n mod K, after that frame's shift) to `width` <= kWidth
  /// interleaved distributions over the chain's cells (FrameChain::blockVector
  /// of `width` columns).
  PetscErrorCode apply(long long n, Vec x, PetscInt width);
  PetscErrorCode view(PetscViewer viewer) const;

private:
  PetscErrorCode background(int k);

  const FrameChain *chain_ = nullptr;
  const FractionSet *fractions_ = nullptr;
  DriftOperator drift_;
  FractionState state_;
  std::vector<std::string> names_;
  int class_ = 0;
  bool moves_ = false;
  double rho_ = 0.0;
  int frame_ = -1;             // the frame whose bulk bulk_ holds
  OwnedVec alpha_, bulk_;      // over the chain cells: alpha_k rho V, and T_k of it
};

} // namespace rcfd
