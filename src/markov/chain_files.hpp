// The text of the chain's output files that both `rcfd markov` and the run's
// `markov` monitor write (docs/markov.md): a zone's distributions and Kac's
// share of time.
#pragma once

#include "markov/zone_passages.hpp"

#include <string>

namespace rcfd {

/// A number as the chain's CSV files write it (%.10g).
std::string chainNumber(double v);
/// zone_NAME.csv: time,residence,away; `what` follows the zone's name in the
/// header line (e.g. ", size class d1.459mm").
std::string zoneFileText(const ZonePassages &p, const std::string &what, size_t departures, double dt);
/// Kac's relation E[visit] / (E[visit] + E[away]): the share of time in the zone (0 without visits).
double kacShare(const ZonePassages &p);

} // namespace rcfd
