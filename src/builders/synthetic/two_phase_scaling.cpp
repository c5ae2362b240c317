#include "builders/synthetic/two_phase_scaling.hpp"

#include <cmath>
#include <stdexcept>

namespace rcfd {
namespace {

/// v^(1/n) for v > 0 by Newton's method from above (from max(1, v), where
/// x^n - v is convex and the iterates decrease monotonically to the root).
double nthRoot(double v, int n) {
  double x = v > 1.0 ? v : 1.0;
  for (int it = 0; it < 400; ++it) {
    double power = 1.0; // x^(n-1)
    for (int m = 1; m < n; ++m) power *= x;
    const double next = x - (power * x - v) / (n * power);
    if (!(next < x)) break;
    x = next;
  }
  return x;
}

} // namespace

TwoPhaseScaling twoPhaseScaling(double r) {
  if (!(r > 0.0) || !std::isfinite(r))
    throw std::invalid_argument("synthetic bed: the excess gas U - U_mf must be positive.");
  TwoPhaseScaling s;
  s.excessRatio = r;
  if (r == 1.0) return s;
  const double fifth = nthRoot(r, 5); // r^0.2
  s.diameterFactor = fifth * fifth;
  s.nucleationFactor = 1.0 / fifth;
  s.holdUpFactor = s.diameterFactor * s.diameterFactor;
  return s;
}

void applyTwoPhaseScaling(const TwoPhaseScaling &s, SyntheticBedOptions *o) {
  if (s.diameterFactor != 1.0) {
    o->initialDiameter *= s.diameterFactor;
    o->maxDiameter *= s.diameterFactor;
  }
  if (s.nucleationFactor != 1.0) o->nucleationRate *= s.nucleationFactor;
}

} // namespace rcfd
