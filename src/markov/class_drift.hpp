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
// scalars, one scalar per distribution (OperatorStep), and the drift code is
// not repeated.
// The chain is the one a tagged particle of the class follows in a bed kept at
// the inventory's composition: exact for a tracer in a mixed bed, an
// approximation where the bed has segregated (the real swaps then differ).
// Every step conserves each distribution (what a face sends one cell the
// other receives), so the class chain is column-stochastic like the bulk's.
#pragma once

#include "markov/operator_step.hpp"
#include "rcfd/drift.hpp"

namespace rcfd {

class ClassDrift : public OperatorStep {
public:
  /// Collective.  Reads the drift's options (-drift_*, as rcfd run reads them;
  /// -drift_view prints the drift once set up).
  PetscErrorCode setFromOptions(MPI_Comm comm);
  /// Collective.  Sets the drift up on the chain's database for `fractions`
  /// (the run's -fractions_diameters, -fractions_mass_shares); refuses what
  /// the drift lacks (e.g. u_sup for -drift_excess_gas).  chain and fractions
  /// must outlive this object.  setClass() chooses the class moved.
  PetscErrorCode setUp(const FrameChain &chain, const FractionSet &fractions, double solidDensity);
  int numClasses() const { return classes_; }
  /// Whether the drift moves anything (a k_d of 0 or one class: it does not,
  /// and every class's chain is the bulk's to the bit).
  bool moves() const { return moves_; }
  /// Whether the drift acts at every step with what the frame alone sets
  /// (not -drift_every N > 1): its step is then one matrix per frame
  /// (markov/drift_matrices.hpp).
  bool sameEveryPeriod() const { return drift_.applyEvery() == 1; }
  /// The most sub-steps one application of the drift has taken so far: how
  /// many faces a particle can cross in a step.
  int mostSubsteps() const { return drift_.maxSubsteps(); }

private:
  DriftOperator drift_;
  OwnedViewer viewer_; // -drift_view
  int classes_ = 0;
  bool moves_ = false;
};

} // namespace rcfd
