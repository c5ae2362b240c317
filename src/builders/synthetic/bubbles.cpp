// Sub-step 1 of the kinematic bed: bubbles nucleate at the distributor, rise,
// wander, grow with height and merge when they touch.
#include "builders/synthetic/kinematic_bed.hpp"

namespace rcfd::synthetic {
namespace {

/// Cube root of v > 0 by Newton's method started above the root (from `upper`),
/// where it decreases monotonically; avoids libm so results are portable.
double cubeRoot(double v, double upper) {
  double x = upper;
  for (int it = 0; it < 100; ++it) {
    const double next = x - (x * x * x - v) / (3.0 * x * x);
    if (!(next < x)) break;
    x = next;
  }
  return x;
}

} // namespace

// Bubbles nucleate steadily (the default; two-phase theory: the excess gas
// flows into bubbles at a steady rate, so the bubble flow at the distributor
// has no Poisson shot noise, which made the bed height wander over the
// recorded span, docs/synthetic.md), or as a Poisson process sampled as
// several Bernoulli trials per substep (the bed before; no logarithms, so no
// libm dependence).
void SyntheticBed::nucleate(double dt) {
  const double expected = opt_.nucleationRate * lx_ * ly_ * dt;
  if (opt_.nucleation == SyntheticBedOptions::Nucleation::poisson) {
    const int trials = std::max(1, static_cast<int>(std::ceil(expected / 0.05)));
    const double p = expected / trials;
    for (int t = 0; t < trials; ++t)
      if (rng_.uniform() < p) {
        const double u = rng_.uniform(); // x before y (argument order is unspecified)
        openBubble(u, rng_.uniform());
      }
    return;
  }
  // Steady: a bubble each time the released gas has reached one more bubble
  // (the first after a random share of the interval, so that seeds differ in
  // phase), into the strips of the distributor along x in a fresh random
  // order every round.
  if (!nucleationStarted_) {
    nucleationDue_ = rng_.uniform();
    nucleationStarted_ = true;
  }
  nucleationDue_ -= expected;
  for (; nucleationDue_ <= 0.0; nucleationDue_ += 1.0) {
    if (stripCursor_ == 0) // Fisher-Yates shuffle of the strips
      for (int z = opt_.nucleationStrips - 1; z > 0; --z)
        std::swap(stripOrder_[z], stripOrder_[std::min(z, static_cast<int>(rng_.uniform() * (z + 1)))]);
    const double u = (stripOrder_[stripCursor_] + rng_.uniform()) / opt_.nucleationStrips;
    stripCursor_ = (stripCursor_ + 1) % opt_.nucleationStrips;
    openBubble(u, rng_.uniform());
  }
}

// A new bubble at the distributor, at the shares (u, v) of the allowed centre
// range in x and y.
void SyntheticBed::openBubble(double u, double v) {
  const double r = 0.5 * opt_.initialDiameter;
  const double mx = centreMargin(r, lx_, hx_), my = centreMargin(r, ly_, hy_);
  Bubble b;
  b.x = mx + u * (lx_ - 2.0 * mx);
  b.y = my + v * (ly_ - 2.0 * my);
  b.z = r; // resting on the distributor
  // The void opens gradually (see moveBubbles), so the bed above is lifted
  // smoothly rather than by a whole bubble at once.
  b.diameter = 0.3 * opt_.initialDiameter;
  b.target = opt_.initialDiameter;
  bubbles_.push_back(b);
  ++nucleated;
}

void SyntheticBed::moveBubbles(double dt) {
  constexpr double wanderTime = 0.1; // correlation time of the lateral wander
  const double relax = std::min(1.0, dt / wanderTime);
  // Uniform kicks with unit variance (sqrt 3) keep the wander's rms at bubbleWander.
  const double kick = opt_.bubbleWander * std::sqrt(2.0 * relax) * std::sqrt(3.0);
  const double d0 = opt_.initialDiameter, dMax = opt_.maxDiameter;
  for (auto &b : bubbles_) {
    if (b.absorbed) { // keeps its motion while its void closes
      b.x += b.ux * dt;
      b.y += b.uy * dt;
      b.z += b.uz * dt;
      b.diameter -= b.shrinkRate * dt;
      continue;
    }
    const double u = riseVelocity(b.diameter);
    b.wanderX += -b.wanderX * relax + kick * rng_.symmetric();
    b.wanderY += -b.wanderY * relax + kick * rng_.symmetric();
    b.ux = b.wanderX + opt_.centreDrift * u * (0.5 * lx_ - b.x) / (0.5 * lx_);
    b.uy = b.wanderY;
    b.uz = u;
    b.x += b.ux * dt;
    b.y += b.uy * dt;
    b.z += b.uz * dt;
    const double h = std::max(b.z, 0.0);
    const double grown = d0 + (dMax - d0) * h / (h + opt_.growthLength);
    b.target = std::min(diameterCap_, std::max(b.target, grown));
    // A sphere grows no faster than a bubble of its final size rises, so
    // that solids are displaced over several substeps.
    const double growth = riseVelocity(std::max(b.target, d0)) * dt;
    b.diameter = std::min(b.target, b.diameter + growth);
    keepCentreInside(b);
  }
  const double gone = 0.05 * d0;
  bubbles_.erase(std::remove_if(bubbles_.begin(), bubbles_.end(),
                                [&](const Bubble &b) { return b.absorbed && b.diameter <= gone; }),
                 bubbles_.end());
}

// Overlapping bubbles coalesce: the larger one grows (gradually, see
// moveBubbles) to the diameter of their combined volume while the smaller one
// shrinks away at the same rate, so no void vanishes at once.
void SyntheticBed::mergeBubbles() {
  for (bool merged = true; merged;) {
    merged = false;
    for (size_t a = 0; a < bubbles_.size() && !merged; ++a)
      for (size_t b = a + 1; b < bubbles_.size() && !merged; ++b) {
        Bubble &p = bubbles_[a], &q = bubbles_[b];
        if (p.absorbed || q.absorbed) continue;
        const double dx = p.x - q.x, dy = p.y - q.y, dz = p.z - q.z;
        const double reach = p.radius() + q.radius(); // as soon as the spheres touch
        if (dx * dx + dy * dy + dz * dz >= reach * reach) continue;
        const double vp = p.target * p.target * p.target;
        const double vq = q.target * q.target * q.target;
        // Keep the larger (ties: the upper) bubble's place and motion.
        if (vq > vp || (vq == vp && q.z > p.z)) std::swap(p, q);
        p.target = std::min(diameterCap_, cubeRoot(vp + vq, p.target + q.target));
        q.absorbed = true;
        q.newborn = false;
        q.target = 0.0;
        q.shrinkRate = riseVelocity(std::max(q.diameter, opt_.initialDiameter));
        merged = true;
      }
  }
}

} // namespace rcfd::synthetic
