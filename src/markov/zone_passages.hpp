// Time in a zone per visit and time away between visits, exactly from the
// chain (docs/markov.md, "Zones"): the solid that crosses the zone's boundary
// during frame k is followed with the frames in order, the side it left
// absorbing, and the probability of reaching it after n steps is recorded.
#pragma once

#include "markov/frame_chain.hpp"
#include "markov/operator_step.hpp"
#include "rcfd/zone.hpp"

#include <vector>

namespace rcfd {

struct PassageSettings {
  double horizon = 20.0;     ///< follow each crossing this long [s]
  double tail = 1e-6;        ///< stop when less than this is left unabsorbed
  std::vector<int> departures; ///< the frames whose crossings are followed
};

/// One duration's distribution: probability[n - 1] that it lasts n dt_rec,
/// mixed over the departures weighted by the mass that crosses in each.
struct PassageDistribution {
  std::vector<double> probability;
  double tail = 0.0;       ///< left unabsorbed at the end (the weighted mean)
  double conservation = 0.0; ///< largest |absorbed + left - 1| of a departure
  double mean = 0.0;       ///< mean duration over the absorbed part [s]
  double flux = 0.0;       ///< mean mass share crossing per step over the departures
};

struct ZonePassages {
  std::string zone;
  double stationaryShare = 0.0; ///< stationary distribution's mass in the zone (set by the caller)
  double databaseShare = 0.0;   ///< mean mass share in the zone over the frames
  PassageDistribution residence; ///< time in the zone per visit (from the inflow)
  PassageDistribution away;      ///< time outside between leaving and entering again (from the outflow)
};

/// Collective.  The passages of every zone (set up on the database's layout);
/// every step (the crossings' too) is the frame's shift followed by `steps`
/// (a size class's drift: the class's chain; the carry at the wrap).
PetscErrorCode zonePassages(const FrameChain &chain, const std::vector<const Zone *> &zones,
                            const PassageSettings &settings, std::vector<ZonePassages> *out,
                            const std::vector<ChainStep *> &steps = {});

/// `count` departure frames spread evenly over K frames: floor(j K / count).
std::vector<int> evenFrames(int K, int count);

} // namespace rcfd
