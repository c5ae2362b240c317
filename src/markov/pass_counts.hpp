// The number of passes through a zone in a given time, exactly from the chain
// (docs/markov.md, "Passes in a given time"): the chain is extended by a pass
// counter, states (cell, j) for j = 0 .. max passes, and propagated with the
// frames; a step that carries solid from outside the zone into it moves that
// solid from counter j to j + 1 (the last counter keeps "max or more").
#pragma once

#include "markov/frame_chain.hpp"
#include "markov/operator_step.hpp"
#include "rcfd/zone.hpp"

#include <vector>

namespace rcfd {

struct PassCountSettings {
  double time = 1.0;           ///< count the entries into the zone within this time [s]
  int maxPasses = 20;          ///< the last counter holds this many passes or more
  std::vector<int> departures; ///< the frames the count starts at (mixed with equal weight)
};

struct PassCounts {
  std::string zone;
  int steps = 0; ///< the time in steps of dt_rec
  /// probability[j]: j entries within the time (j = maxPasses: that many or
  /// more), for a particle drawn from the solid at a departure frame, mixed
  /// over the departures.
  std::vector<double> probability;
  double mean = 0.0;         ///< mean number of entries (the last counter counted as maxPasses)
  double conservation = 0.0; ///< largest |sum_j P_j - 1| of a departure
};

/// Collective.  The pass counts of every zone (set up on the database's
/// layout); each step is the frame's shift followed by `after` (the carry at
/// the wrap).
PetscErrorCode passCounts(const FrameChain &chain, const std::vector<const Zone *> &zones,
                          const PassCountSettings &settings, std::vector<PassCounts> *out,
                          const std::vector<ChainStep *> &after = {});

} // namespace rcfd
