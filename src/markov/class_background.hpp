// The bed a size class's chain is linearised on, taken from the classes'
// own chains (docs/markov.md, "The background: the bed segregated as the
// chains say").
//
// Each class's drift is linear only once the bed it drifts in is fixed
// (markov/class_drift.hpp).  Fixed at the inventory's composition in every
// cell, the chains keep pushing at the mixed bed's rate where the real bed,
// once segregated, drives itself less (a cell full of large particles has a
// local d32 near theirs; one full of small ones finds few large to swap with),
// and their stationary distributions come out more segregated than a run's.
// Here the bed is the one the chains themselves predict: each class living at
// frame 0 as its period chain's stationary distribution, followed through the
// frames with its own steps, gives its mass in every cell after every frame's
// shift, and the classes' shares of those masses are the next background.
// Repeated, this is a fixed-point iteration for a background consistent with
// the chains it produces.
#pragma once

#include "markov/class_drift.hpp"
#include "markov/drift_matrices.hpp"
#include "markov/frame_chain.hpp"
#include "markov/period_chain.hpp"

#include <cmath>
#include <vector>

namespace rcfd {

class ClassBackground {
public:
  /// Starts a new sum for `numClasses` classes over the chain's frames.
  void reset(const FrameChain &chain, int numClasses);
  /// Collective.  Adds class i, `share` of the inventory, at frame 0 as
  /// `atFrame0` (a distribution over all cells of the layout, summing to 1),
  /// moved through the frames by each transfer and then `steps` (its drift).
  PetscErrorCode add(int i, double share, Vec atFrame0, const std::vector<ChainStep *> &steps);
  /// The classes' mass shares after each frame's shift, per chain cell of
  /// this rank (OperatorStep::setComposition); where no class arrives, the
  /// inventory's `shares`.
  std::vector<std::vector<double>> composition(const std::vector<double> &shares) const;

private:
  const FrameChain *chain_ = nullptr;
  int classes_ = 0;
  std::vector<std::vector<double>> mass_; // per frame: chain cell x class
};

/// Collective.  Class i's steps as rcfd markov and the run's monitor take
/// them: `drift` set to class i, read off into `matrices` when `asMatrices`
/// and the drift acts at every step (else the operator itself), then `after`
/// (the carry at the wrap; null: nothing).
PetscErrorCode classSteps(const FrameChain &chain, ClassDrift &drift, int i, bool asMatrices, ChainStep *after,
                          DriftMatrices *matrices, std::vector<ChainStep *> *steps);

struct BackgroundSettings {
  int iterations = 8;      ///< at most this many rounds of the classes' period chains
  double tolerance = 1e-4; ///< [m] stop when no class's stationary centre moves more than this
};

struct BackgroundIterations {
  /// Per round, each class's period stationary centre [m] on the background
  /// the round before left (round 0: the mean composition's).
  std::vector<std::vector<double>> centres;
  double lastChange = std::nan(""); ///< [m] the largest change of a centre in the last round
  bool converged(const BackgroundSettings &s) const { return lastChange < s.tolerance; }
};

/// Collective.  Finds the background (docs/markov.md, "The background"): each
/// round solves every class's period chain with its classSteps(asMatrices,
/// after), and unless the
/// centres moved less than the tolerance sets the bed they give on `drift`
/// (OperatorStep::setComposition) for the next.  `drift` keeps the last
/// background set, the one the last round's chains were linearised on.
PetscErrorCode findBackground(const FrameChain &chain, PeriodChain &period, ChainEigensolver &solver,
                              ClassDrift &drift, const FractionSet &fractions, bool asMatrices, ChainStep *after,
                              const BackgroundSettings &settings, BackgroundIterations *out);

} // namespace rcfd
