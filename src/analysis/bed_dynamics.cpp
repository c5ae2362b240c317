#include "analysis/bed_dynamics.hpp"

#include <cmath>
#include <stdexcept>

namespace rcfd {

double bedDynamics(const std::vector<double> &zCog) {
  if (zCog.empty()) throw std::invalid_argument("bed dynamics need at least one centre of gravity");
  double mean = 0.0;
  for (double z : zCog) {
    if (!std::isfinite(z)) throw std::invalid_argument("bed dynamics: a centre of gravity is not finite");
    mean += z;
  }
  mean /= static_cast<double>(zCog.size());
  double deviation = 0.0;
  for (double z : zCog) deviation += std::fabs(z - mean);
  return deviation / static_cast<double>(zCog.size());
}

double databaseDistance(double a, double b) {
  if (!(b > 0.0) || !std::isfinite(b) || !std::isfinite(a))
    throw std::invalid_argument("the database distance needs a positive, finite bed dynamics of the "
                                "second (denominator) database");
  return std::fabs(a - b) / b;
}

} // namespace rcfd
