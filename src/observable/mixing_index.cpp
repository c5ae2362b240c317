#include "observable/mixing_index.hpp"

#include <cmath>
#include <limits>

namespace rcfd {

void LaceySums::addCell(double fractionMass, double solidMass, double particles) {
  if (!(solidMass > 0.0) || !(particles > 0.0)) return;
  const double share = fractionMass / solidMass;
  sums[0] += solidMass;
  sums[1] += solidMass * share;
  sums[2] += solidMass * share * share;
  sums[3] += solidMass / particles;
}

double LaceySums::index(double p) const {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (!(p > 0.0 && p < 1.0) || !(sums[0] > 0.0)) return nan;
  // Variance about the inventory share p, not about the sample mean: the two
  // agree when the cells hold the whole inventory, and p is what "mixed" means.
  const double w = sums[0];
  const double variance = sums[2] / w - 2.0 * p * sums[1] / w + p * p;
  const double segregated = p * (1.0 - p);
  const double random = segregated * sums[3] / w;
  return (segregated - variance) / (segregated - random);
}

} // namespace rcfd
