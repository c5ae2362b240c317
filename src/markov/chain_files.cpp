#include "markov/chain_files.hpp"

#include <algorithm>
#include <cstdio>
#include <sstream>

namespace rcfd {

std::string chainNumber(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", v);
  return text;
}

std::string zoneFileText(const ZonePassages &p, const std::string &what, size_t departures, double dt) {
  std::ostringstream z;
  z << "# zone " << p.zone << what << ": probability that a visit lasts t (residence) and that the time outside "
    << "between leaving and entering again is t (away), from " << departures
    << " departure frames; tails left after the horizon: residence " << p.residence.tail << ", away "
    << p.away.tail << "\ntime,residence,away\n";
  const size_t rows = std::max(p.residence.probability.size(), p.away.probability.size());
  for (size_t n = 0; n < rows; ++n)
    z << chainNumber((n + 1) * dt) << ','
      << chainNumber(n < p.residence.probability.size() ? p.residence.probability[n] : 0.0) << ','
      << chainNumber(n < p.away.probability.size() ? p.away.probability[n] : 0.0) << '\n';
  return z.str();
}

double kacShare(const ZonePassages &p) {
  const double sum = p.residence.mean + p.away.mean;
  return sum > 0 ? p.residence.mean / sum : 0.0;
}

} // namespace rcfd
