// Kinematic stand-in for a bubbling fluidized bed (see docs/synthetic-bed.md).
//
// State: equal-volume parcels.  A parcel is either *dense* (part of the
// emulsion) or *airborne* (thrown up by an erupting bubble, or falling into a
// crater).  Dense parcels are stacked per column of cells on a lattice of
// "slots", ppc slots per cell height, one parcel per slot, so no cell ever
// holds more than ppc parcels (alpha_s <= packing) and the emulsion is exactly
// incompressible.  One kinematic substep:
//   1. bubbles nucleate at the distributor, rise at U = c sqrt(g D), wander,
//      grow with height (at a limited rate) and merge when they touch;
//   2. dense parcels move sideways with the potential flow around each bubble
//      sphere (a dipole with mirror images in the floor and walls), or with
//      the bubble when inside its sphere (the wake); their advected height,
//      plus a vertical random walk, is only a sort key;
//   3. airborne parcels fly ballistically;
//   4. the surface is levelled: parcels slide from higher to lower columns;
//   5. every column is restacked: dense parcels sorted by key are laid from
//      the floor, one per slot, jumping over the part of each bubble chord
//      above the bubble's wake (the void); airborne parcels that reach the
//      surface land on it;
//   6. horizontal dispersion swaps parcels between neighbouring columns;
//   7. gaps under voids are filled from neighbouring columns, balanced by
//      pushing as many parcels out from above the void (flow around bubbles);
//   8. bubbles with a thin roof erupt: the roof is thrown up and the void
//      closes gradually.
// Randomness comes from one xoshiro256** stream and only IEEE-exact operations
// (+ - * / sqrt floor ceil) shape the state, so a seed gives the same frames
// with any standard library (given IEEE doubles without FMA contraction).
#include "builders/synthetic/synthetic_bed.hpp"

#include "base/random.hpp"

#include <algorithm>
#include <numeric>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace rcfd {
namespace {

/// The project's xoshiro256** (src/path/frame_path.hpp) with the draws the
/// kinematics use.
class Rng {
public:
  explicit Rng(std::uint64_t seed) : generator(seed) {}
  std::uint64_t next() { return generator.next(); }
  /// Uniform in [0, 1).
  double uniform() { return generator.uniform(); }
  /// Uniform in [-1, 1).
  double symmetric() { return 2.0 * uniform() - 1.0; }

private:
  Xoshiro256 generator;
};

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

/// Height s (in radii, from the centre) below which the share f of a sphere's
/// volume lies: (1 + s)^2 (2 - s) / 4 = f, solved by bisection.
double levelBelowShare(double f) {
  double lo = -1.0, hi = 1.0;
  for (int it = 0; it < 80; ++it) {
    const double s = 0.5 * (lo + hi);
    ((1.0 + s) * (1.0 + s) * (2.0 - s) / 4.0 < f ? lo : hi) = s;
  }
  return 0.5 * (lo + hi);
}

/// Keep a coordinate inside [0, L): reflect at the walls, then clamp.
inline double keepInside(double v, double length) {
  if (v < 0.0) v = -v;
  if (v >= length) v = 2.0 * length - v;
  return std::min(std::max(v, 0.0), length * (1.0 - 1e-12));
}

struct Bubble {
  double x, y, z;    // centre, from the box origin
  double diameter;   // current diameter of the sphere
  double target;     // diameter it grows towards: growth law, merged volume
  double wanderX = 0.0, wanderY = 0.0; // lateral random-walk velocity
  double ux = 0.0, uy = 0.0, uz = 0.0; // current velocity
  bool newborn = true;
  bool absorbed = false; // merged or erupted: shrinks away at shrinkRate
  bool erupted = false;
  double shrinkRate = 0.0;
  int centreColumn = 0;
  int roof = 0;      // dense parcels above the void in the centre column
  double radius() const { return 0.5 * diameter; }
};

/// Potential flow around a sphere moving with velocity V, or one of its mirror
/// images: u = R^3 / (2 r^3) (3 (V.e_r) e_r - V) for r > R.
struct Dipole {
  double cx, cy, cz;
  double vx, vy, vz;
  double halfR3;
  double cut2;
  double r2;
  int bubble; // index of the real bubble, -1 for an image
};

/// The part of a bubble's chord through one column that is void: parcels
/// whose advected height is above zCentre are laid from topSlot up.
struct VoidChord {
  double zCentre;
  int topSlot;
  int wakeTopSlot; // the wake (solid) should reach this slot from below
  int bubble;
  int belowTop;    // slot where the solid below the void ended at the last restack, -1: no solid above
  int aboveStart;  // slot where the solid above the void starts
};

class SyntheticBed {
public:
  explicit SyntheticBed(const SyntheticBedOptions &options);

  void advance(double dt);
  /// Natural cell index of every parcel.
  void cellsOf(std::vector<int32_t> &cells) const;
  double meanSurfaceHeight() const;
  long numParcels() const { return static_cast<long>(x_.size()); }
  double alphaPerParcel() const { return opt_.packing / opt_.parcelsPerCell; }
  long nucleated = 0, erupted = 0;

private:
  void nucleate(double dt);
  void openBubble(double u, double v);
  void moveBubbles(double dt);
  void mergeBubbles();
  void buildDipoles();
  void buildVoids();
  void advectDense(double dt);
  void advectAirborne(double dt);
  void levelSurface(double dt);
  void slideParcels(int from, int to, int count);
  void restack();
  void stackColumn(int c);
  int layColumn(int c);
  void disperse(double dt);
  int32_t parcelAtSlot(int c, int slot) const;
  void fillWakeGaps(double dt);
  int neighboursByAxisDistance(int c, const Bubble &b, bool backward,
                               std::pair<double, int> *out) const;
  void queuePushes(int c, int fromSlot, int target, int count);
  void applyPushes();
  int pullFrom(int donor, int receiver, int fromSlot, int toSlot, int most);
  void renumber();
  void settleAirborne(std::vector<int32_t> &dense, int &cursor);
  void eruptBubbles();
  void eject(int k);
  void compactColumn(int c);

  int columnOf(double x, double y) const {
    const int i = std::min(nx_ - 1, static_cast<int>(x * invHx_));
    const int j = std::min(ny_ - 1, static_cast<int>(y * invHy_));
    return i + nx_ * j;
  }
  int binOf(int i, int j, int k) const { return i / 2 + bx_ * (j / 2 + by_ * k); }
  int layerOf(double z) const {
    return std::min(nz_ - 1, std::max(0, static_cast<int>(std::floor(z / hz_))));
  }
  double riseVelocity(double d) const {
    return opt_.riseCoefficient * std::sqrt(opt_.gravity * d);
  }
  /// Lowest allowed centre coordinate of a sphere of radius r between walls
  /// `length` apart: one cell clear of the walls (a sphere touching a wall
  /// spoils the flow there), and held in the middle when it cannot be.
  double centreMargin(double r, double length, double h) const {
    return std::min(r + h, 0.5 * length);
  }
  void keepCentreInside(Bubble &b) const {
    const double mx = centreMargin(b.radius(), lx_, hx_), my = centreMargin(b.radius(), ly_, hy_);
    b.x = std::min(std::max(b.x, mx), lx_ - mx);
    b.y = std::min(std::max(b.y, my), ly_ - my);
  }

  SyntheticBedOptions opt_;
  Rng rng_;
  int nx_, ny_, nz_, ncol_, ppc_, maxSlots_;
  double lx_, ly_, lz_, hx_, hy_, hz_, invHx_, invHy_;
  double slotHeight_;   // height of one parcel in a dense stack
  double wakeLevel_;    // new bubbles keep parcels below centre + wakeLevel * R as wake
  double diameterCap_;  // merged bubbles stay narrower than the bed

  // Parcels.
  std::vector<double> x_, y_, z_, zKey_, vx_, vy_, vz_;
  std::vector<int32_t> slot_, id_;
  std::vector<uint8_t> airborne_, pulled_;
  long substeps_ = 0;
  // Steady nucleation: bubbles still due (a bubble when it drops to 0), and
  // the strips of the distributor in this round's order.
  double nucleationDue_ = 0.0;
  bool nucleationStarted_ = false;
  std::vector<int> stripOrder_;
  int stripCursor_ = 0;
  // Parcels grouped by column: dense in slot order, then airborne.
  std::vector<int32_t> order_, colStart_, denseEnd_, top_;
  std::vector<Bubble> bubbles_;
  std::vector<Dipole> dipoles_;
  int bx_, by_;                              // dipole bins: 2 x 2 columns x 1 layer
  std::vector<int32_t> binStart_, binDipoles_;
  std::vector<VoidChord> voids_;
  std::vector<int32_t> voidStart_;
  // Scratch.
  std::vector<int32_t> column_, previousColumn_, voidColumn_, fill_, scratch_, dense_, air_, keys_, keyCount_, cellCount_;
  std::vector<int32_t> received_, given_, largestDrop_;
  struct Transfer {
    int from, to;
    double amount;
  };
  std::vector<Transfer> transfers_;
  std::vector<std::pair<int32_t, int32_t>> pushes_; // (parcel, target column), see fillWakeGaps
  std::vector<double> wantedBy_;
};

SyntheticBed::SyntheticBed(const SyntheticBedOptions &options) : opt_(options), rng_(options.seed) {
  const BoxSpec &box = opt_.box;
  nx_ = box.nx;
  ny_ = box.ny;
  nz_ = box.nz;
  ncol_ = nx_ * ny_;
  ppc_ = opt_.parcelsPerCell;
  maxSlots_ = nz_ * ppc_;
  lx_ = box.length[0];
  ly_ = box.length[1];
  lz_ = box.length[2];
  const Vec3 h = box.spacing();
  hx_ = h[0];
  hy_ = h[1];
  hz_ = h[2];
  invHx_ = nx_ / lx_;
  invHy_ = ny_ / ly_;
  slotHeight_ = hz_ / ppc_;
  wakeLevel_ = levelBelowShare(opt_.wakeFraction);
  stripOrder_.resize(opt_.nucleationStrips);
  std::iota(stripOrder_.begin(), stripOrder_.end(), 0);
  bx_ = (nx_ + 1) / 2;
  by_ = (ny_ + 1) / 2;
  // Coalescence may not grow a bubble beyond half the wider side of the bed.
  diameterCap_ = std::max(opt_.initialDiameter, 0.5 * std::max(lx_, ly_));

  // Settled bed: every column holds the same number of parcels, stacked from
  // the floor, at random horizontal positions inside the column.
  const int perColumn = static_cast<int>(std::lround(opt_.bedHeight / slotHeight_));
  const size_t n = static_cast<size_t>(perColumn) * ncol_;
  for (auto *v : {&x_, &y_, &z_, &zKey_, &vx_, &vy_, &vz_}) v->assign(n, 0.0);
  slot_.assign(n, 0);
  id_.resize(n);
  airborne_.assign(n, 0);
  pulled_.assign(n, 0);
  order_.resize(n);
  colStart_.assign(ncol_ + 1, 0);
  denseEnd_.assign(ncol_, 0);
  top_.assign(ncol_, perColumn);
  int32_t p = 0;
  for (int c = 0; c < ncol_; ++c) {
    colStart_[c] = p;
    const int i = c % nx_, j = c / nx_;
    for (int s = 0; s < perColumn; ++s, ++p) {
      x_[p] = (i + rng_.uniform()) * hx_;
      y_[p] = (j + rng_.uniform()) * hy_;
      slot_[p] = s;
      z_[p] = zKey_[p] = (s + 0.5) * slotHeight_;
      order_[p] = id_[p] = p;
    }
    denseEnd_[c] = p;
  }
  colStart_[ncol_] = p;
}

void SyntheticBed::advance(double dt) {
  nucleate(dt);
  moveBubbles(dt);
  mergeBubbles();
  buildDipoles();
  buildVoids();
  advectDense(dt);
  advectAirborne(dt);
  applyPushes();
  levelSurface(dt);
  restack();
  // Parcels change columns slowly; keeping their storage in column order
  // makes the column sweeps cache-friendly.
  if (substeps_ % 8 == 0) renumber();
  disperse(dt);
  fillWakeGaps(dt);
  eruptBubbles();
  for (auto &b : bubbles_) b.newborn = false;
  ++substeps_;
}

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

// Each bubble's sphere and its mirror images in the floor and the four side
// walls (the normal component of the sphere's velocity flips), so that the
// flow nearly respects the walls.
void SyntheticBed::buildDipoles() {
  dipoles_.clear();
  for (size_t k = 0; k < bubbles_.size(); ++k) {
    const Bubble &b = bubbles_[k];
    const double r = b.radius(), cut = opt_.dipoleCutoff * r;
    const Dipole real{b.x, b.y, b.z, b.ux, b.uy, b.uz, 0.5 * r * r * r, cut * cut, r * r,
                      static_cast<int>(k)};
    dipoles_.push_back(real);
    auto image = [&](int axis, double wall) {
      Dipole d = real;
      d.bubble = -1;
      double *c[3] = {&d.cx, &d.cy, &d.cz};
      double *v[3] = {&d.vx, &d.vy, &d.vz};
      *c[axis] = 2.0 * wall - *c[axis];
      *v[axis] = -*v[axis];
      dipoles_.push_back(d);
    };
    if (b.z < cut) image(2, 0.0);
    if (b.x < cut) image(0, 0.0);
    if (lx_ - b.x < cut) image(0, lx_);
    if (b.y < cut) image(1, 0.0);
    if (ly_ - b.y < cut) image(1, ly_);
  }
  // Bin the dipoles by the 2 x 2-column blocks and layers that their cutoff
  // sphere touches, so a parcel only visits the few dipoles that can reach it.
  const int numBins = bx_ * by_ * nz_;
  binStart_.assign(numBins + 1, 0);
  auto forBins = [&](const Dipole &d, auto &&visit) {
    const double cut = std::sqrt(d.cut2);
    auto range = [](double lo, double hi, double h, int n, int &a, int &b) {
      a = std::max(0, static_cast<int>(std::floor(lo / h)));
      b = std::min(n - 1, static_cast<int>(std::floor(hi / h)));
    };
    int i0, i1, j0, j1, k0, k1;
    range(d.cx - cut, d.cx + cut, hx_, nx_, i0, i1);
    range(d.cy - cut, d.cy + cut, hy_, ny_, j0, j1);
    range(d.cz - cut, d.cz + cut, hz_, nz_, k0, k1);
    for (int k = k0; k <= k1; ++k)
      for (int j = j0 / 2; j <= j1 / 2 && j1 >= j0; ++j)
        for (int i = i0 / 2; i <= i1 / 2 && i1 >= i0; ++i) visit(i + bx_ * (j + by_ * k));
  };
  for (const Dipole &d : dipoles_) forBins(d, [&](int bin) { ++binStart_[bin + 1]; });
  for (int b = 0; b < numBins; ++b) binStart_[b + 1] += binStart_[b];
  binDipoles_.resize(binStart_[numBins]);
  fill_.assign(binStart_.begin(), binStart_.end() - 1);
  for (size_t i = 0; i < dipoles_.size(); ++i)
    forBins(dipoles_[i], [&](int bin) { binDipoles_[fill_[bin]++] = static_cast<int32_t>(i); });
}

// Void chords per column, evaluated at the column's centre line and sorted by
// bubble centre height.  The bubble's own centre column always gets an entry
// so that its roof can be measured.
void SyntheticBed::buildVoids() {
  voids_.clear();
  voidColumn_.clear();
  for (size_t k = 0; k < bubbles_.size(); ++k) {
    Bubble &b = bubbles_[k];
    b.centreColumn = columnOf(b.x, b.y);
    b.roof = 0;
    const double r = b.radius();
    const int i0 = std::max(0, static_cast<int>((b.x - r) / hx_));
    const int i1 = std::min(nx_ - 1, static_cast<int>((b.x + r) / hx_));
    const int j0 = std::max(0, static_cast<int>((b.y - r) / hy_));
    const int j1 = std::min(ny_ - 1, static_cast<int>((b.y + r) / hy_));
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const int c = i + nx_ * j;
        const double dx = (i + 0.5) * hx_ - b.x, dy = (j + 0.5) * hy_ - b.y;
        const double rho2 = dx * dx + dy * dy;
        if (rho2 >= r * r && c != b.centreColumn) continue;
        const double half = std::sqrt(std::max(0.0, r * r - rho2));
        const int topSlot = std::min(
            maxSlots_, static_cast<int>(std::ceil((b.z + half) / slotHeight_)));
        // The wake fills the sphere from its bottom up to the split level.
        const double wakeTop = std::max(b.z - half, std::min(b.z + wakeLevel_ * r, b.z + half));
        const int wakeTopSlot = static_cast<int>(std::floor(wakeTop / slotHeight_));
        voids_.push_back({b.z, topSlot, wakeTopSlot, static_cast<int>(k), -1, -1});
        voidColumn_.push_back(c);
      }
  }
  voidStart_.assign(ncol_ + 1, 0);
  for (int32_t c : voidColumn_) ++voidStart_[c + 1];
  for (int c = 0; c < ncol_; ++c) voidStart_[c + 1] += voidStart_[c];
  std::vector<VoidChord> sorted(voids_.size());
  std::vector<int32_t> fill(voidStart_.begin(), voidStart_.end() - 1);
  for (size_t v = 0; v < voids_.size(); ++v) sorted[fill[voidColumn_[v]]++] = voids_[v];
  for (int c = 0; c < ncol_; ++c)
    std::stable_sort(sorted.begin() + voidStart_[c], sorted.begin() + voidStart_[c + 1],
                     [](const VoidChord &a, const VoidChord &b) { return a.zCentre < b.zCentre; });
  voids_.swap(sorted);
}

// Dense parcels: velocity from the dipoles, or the bubble's own velocity when
// inside its sphere (the wake is carried along).  Only the horizontal position
// is kept; the advected height zKey, with a vertical random walk, just orders
// the column for restacking.  (A horizontal random walk would change the
// number of parcels per column at random and shake whole columns; horizontal
// dispersion is done by swaps instead, see disperse().)  A newborn bubble
// pushes the parcels in its upper part above its centre, so that only
// wakeFraction of its sphere stays as wake.
void SyntheticBed::advectDense(double dt) {
  const double step = std::sqrt(6.0 * opt_.dispersion * dt); // uniform walk, variance 2 D dt
  double maxSpeed2 = 0.0;
  for (const Bubble &b : bubbles_)
    maxSpeed2 = std::max(maxSpeed2, 2.25 * (b.ux * b.ux + b.uy * b.uy + b.uz * b.uz));
  const size_t n = x_.size();
  for (size_t p = 0; p < n; ++p) {
    if (airborne_[p]) continue;
    const double px = x_[p], py = y_[p], pz = z_[p];
    double u[3] = {0.0, 0.0, 0.0};
    bool keyDone = false;
    const int bin = binOf(std::min(nx_ - 1, static_cast<int>(px * invHx_)),
                          std::min(ny_ - 1, static_cast<int>(py * invHy_)), slot_[p] / ppc_);
    if (binStart_[bin] == binStart_[bin + 1]) { // no bubble nearby: only the walk
      zKey_[p] = pz + step * rng_.symmetric();
      continue;
    }
    for (int32_t e = binStart_[bin]; e < binStart_[bin + 1]; ++e) {
      const Dipole &d = dipoles_[binDipoles_[e]];
      const double dx = px - d.cx, dy = py - d.cy, dz = pz - d.cz;
      const double r2 = dx * dx + dy * dy + dz * dz;
      if (r2 >= d.cut2) continue;
      if (d.bubble >= 0 && r2 < d.r2) {
        const Bubble &b = bubbles_[d.bubble];
        u[0] = b.ux;
        u[1] = b.uy;
        u[2] = b.uz;
        if (b.newborn && pz >= b.z + wakeLevel_ * b.radius()) {
          zKey_[p] = b.z;
          keyDone = true;
        }
        break;
      }
      // Points inside an image sphere (next to a wall that cuts a big
      // bubble) see the field of the image's surface, not its singular core.
      const double re2 = std::max(r2, d.r2);
      const double inv3 = d.halfR3 / (re2 * std::sqrt(re2));
      const double along = 3.0 * (d.vx * dx + d.vy * dy + d.vz * dz) / re2;
      // Images cancel the wall-normal flow only roughly when the sphere is
      // near or across a wall; damping it within a radius of the wall keeps
      // solids from piling up there (a bubble spanning a thin bed gives a
      // nearly two-dimensional flow, as it should).
      const double radius = std::sqrt(d.r2);
      const double damp[2] = {std::min(1.0, std::min(px, lx_ - px) / radius),
                              std::min(1.0, std::min(py, ly_ - py) / radius)};
      u[0] += inv3 * (along * dx - d.vx) * damp[0];
      u[1] += inv3 * (along * dy - d.vy) * damp[1];
      u[2] += inv3 * (along * dz - d.vz);
    }
    // Superposed fields can exceed the potential-flow maximum 1.5 U; cap them.
    const double speed2 = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
    if (speed2 > maxSpeed2) {
      const double scale = std::sqrt(maxSpeed2 / speed2);
      for (double &c : u) c *= scale;
    }
    x_[p] = keepInside(px + u[0] * dt, lx_);
    y_[p] = keepInside(py + u[1] * dt, ly_);
    const double walk = rng_.symmetric();
    if (!keyDone) zKey_[p] = pz + u[2] * dt + step * walk;
  }
}

// Ballistic flight.  Walls and the side of a taller column (a parcel that
// would end up more than a cell below that column's surface) bounce the
// parcel back with restitution 1/2; landing on a surface is done at restacking.
void SyntheticBed::advectAirborne(double dt) {
  constexpr double restitution = 0.5;
  const size_t n = x_.size();
  for (size_t p = 0; p < n; ++p) {
    if (!airborne_[p]) continue;
    const double x0 = x_[p], y0 = y_[p];
    vz_[p] -= opt_.gravity * dt;
    double v[3] = {vx_[p], vy_[p], vz_[p]};
    double *pos[3] = {&x_[p], &y_[p], &z_[p]};
    const double len[3] = {lx_, ly_, lz_};
    for (int a = 0; a < 3; ++a) {
      double s = *pos[a] + v[a] * dt;
      if (s < 0.0 && a < 2) { // side walls bounce; the floor is handled by landing
        s = -s;
        v[a] = restitution * std::fabs(v[a]);
      } else if (s >= len[a]) {
        s = 2.0 * len[a] - s;
        v[a] = -restitution * std::fabs(v[a]);
      }
      *pos[a] = std::min(std::max(s, 0.0), len[a] * (1.0 - 1e-12));
    }
    const int c = columnOf(x_[p], y_[p]);
    if (c != columnOf(x0, y0) && z_[p] < top_[c] * slotHeight_ - hz_) {
      x_[p] = x0;
      y_[p] = y0;
      v[0] = -restitution * v[0];
      v[1] = -restitution * v[1];
    }
    vx_[p] = v[0];
    vy_[p] = v[1];
    vz_[p] = v[2];
    zKey_[p] = z_[p];
  }
}

// The emulsion behaves like a liquid: surface height differences between
// neighbouring columns relax as dh/dt = D lap(h).  Discretely, parcels of the
// higher column slide to the lower one (at most 1/8 of a difference per
// neighbour and substep, for explicit stability; rounded stochastically).
void SyntheticBed::levelSurface(double dt) {
  const double fx = std::min(0.125, opt_.surfaceDiffusivity * dt / (hx_ * hx_));
  const double fy = std::min(0.125, opt_.surfaceDiffusivity * dt / (hy_ * hy_));
  received_.assign(ncol_, 0);
  std::fill(pulled_.begin(), pulled_.end(), 0);
  // A column sinks at most at the speed sqrt(g dh) of a collapsing step of
  // height dh (its largest drop to a neighbour), so a crater wall slumps
  // rather than drops.  Each donor's wanted transfers are scaled down together
  // to that budget (spending it in sweep order would drift solids towards low
  // indices).
  std::vector<Transfer> &wanted = transfers_;
  wanted.clear();
  wantedBy_.assign(ncol_, 0.0);
  largestDrop_.assign(ncol_, 0);
  auto want = [&](int a, int b, double f) {
    const int diff = top_[a] - top_[b];
    if (std::abs(diff) < 2) return; // ignore one-slot roughness
    const int from = diff > 0 ? a : b;
    wanted.push_back({from, diff > 0 ? b : a, f * std::abs(diff)});
    wantedBy_[from] += wanted.back().amount;
    largestDrop_[from] = std::max(largestDrop_[from], std::abs(diff));
  };
  for (int j = 0; j < ny_; ++j)
    for (int i = 0; i < nx_; ++i) {
      const int c = i + nx_ * j;
      if (i + 1 < nx_) want(c, c + 1, fx);
      if (j + 1 < ny_) want(c, c + nx_, fy);
    }
  for (const Transfer &t : wanted) {
    const double slump = std::sqrt(opt_.gravity * largestDrop_[t.from] * slotHeight_);
    const double budget = std::max(1.0, std::floor(slump * dt / slotHeight_));
    const double amount = t.amount * std::min(1.0, budget / wantedBy_[t.from]);
    int count = static_cast<int>(amount);
    if (rng_.uniform() < amount - count) ++count; // stochastic rounding
    if (count > 0) slideParcels(t.from, t.to, count);
  }
}

// Move `count` parcels from column `from` to the lower column `to`.  The
// parcels taken are those of `from` at the height of the surface of `to` (the
// foot of the step, not its top), so nothing jumps vertically: the parcel
// slides sideways onto the lower surface and `from` settles by one slot.  If
// `from` has a void at that height (a bulge over a bubble), its top parcel
// slides off instead and falls.
void SyntheticBed::slideParcels(int from, int to, int count) {
  const int ti = to % nx_, tj = to / nx_;
  int32_t topPos = denseEnd_[from] - 1;
  for (int m = 0; m < count; ++m) {
    const int level = top_[to] + received_[to];
    int32_t lowest = -1;
    for (int32_t e = denseEnd_[from] - 1; e >= colStart_[from]; --e) {
      const int32_t p = order_[e];
      if (slot_[p] < level) break;
      if (!pulled_[p] && !airborne_[p]) lowest = p;
    }
    if (lowest >= 0 && slot_[lowest] < level + ppc_) {
      pulled_[lowest] = 1;
      x_[lowest] = (ti + rng_.uniform()) * hx_;
      y_[lowest] = (tj + rng_.uniform()) * hy_;
      zKey_[lowest] = (level + 0.5) * slotHeight_;
      ++received_[to];
      continue;
    }
    while (topPos >= colStart_[from] && (pulled_[order_[topPos]] || airborne_[order_[topPos]]))
      --topPos;
    if (topPos < colStart_[from]) return;
    const int32_t p = order_[topPos--];
    pulled_[p] = 1;
    airborne_[p] = 1;
    x_[p] = (ti + rng_.uniform()) * hx_;
    y_[p] = (tj + rng_.uniform()) * hy_;
    zKey_[p] = z_[p];
    vx_[p] = vy_[p] = vz_[p] = 0.0;
  }
}

// Regroup parcels by their new column (a stable counting sort, so each column
// keeps its previous order as far as possible), then stack every column.
void SyntheticBed::restack() {
  const size_t n = x_.size();
  column_.resize(n);
  fill_.assign(ncol_ + 1, 0); // new column sizes, then starts
  for (size_t p = 0; p < n; ++p) {
    column_[p] = columnOf(x_[p], y_[p]);
    ++fill_[column_[p] + 1];
  }
  for (int c = 0; c < ncol_; ++c) fill_[c + 1] += fill_[c];
  scratch_.resize(n);
  previousColumn_.resize(n);
  for (int c = 0; c < ncol_; ++c)
    for (int32_t e = colStart_[c]; e < colStart_[c + 1]; ++e) {
      const int32_t p = order_[e];
      previousColumn_[p] = c;
      scratch_[fill_[column_[p]]++] = p;
    }
  // fill_[c] now ends column c, i.e. starts column c + 1.
  colStart_[0] = 0;
  std::copy(fill_.begin(), fill_.end() - 1, colStart_.begin() + 1);
  order_.swap(scratch_);
  for (int c = 0; c < ncol_; ++c) stackColumn(c);
}

// Sort the column's dense parcels by advected height (counting sort on a
// half-slot grid; ties keep the previous order) and lay them one per slot
// from the floor (see layColumn), then let airborne parcels land.
void SyntheticBed::stackColumn(int c) {
  dense_.clear();
  air_.clear();
  for (int32_t e = colStart_[c]; e < colStart_[c + 1]; ++e)
    (airborne_[order_[e]] ? air_ : dense_).push_back(order_[e]);

  // Keys on a half-slot grid (truncation is floor here: keys are clamped >= 0).
  const double perKey = 2.0 / slotHeight_;
  const double maxKey = 2.0 * maxSlots_ + 1.0;
  const size_t nd = dense_.size();
  keys_.resize(nd);
  int lo = static_cast<int>(maxKey), hi = 0;
  for (size_t r = 0; r < nd; ++r) {
    const double k = std::min(std::max(zKey_[dense_[r]] * perKey, 0.0), maxKey);
    keys_[r] = static_cast<int>(k);
    lo = std::min(lo, keys_[r]);
    hi = std::max(hi, keys_[r]);
  }
  if (nd > 1 && lo < hi) {
    keyCount_.assign(hi - lo + 2, 0);
    for (size_t r = 0; r < nd; ++r) ++keyCount_[keys_[r] - lo + 1];
    for (size_t k = 1; k < keyCount_.size(); ++k) keyCount_[k] += keyCount_[k - 1];
    scratch_.resize(nd);
    for (size_t r = 0; r < nd; ++r) scratch_[keyCount_[keys_[r] - lo]++] = dense_[r];
    std::copy(scratch_.begin(), scratch_.begin() + static_cast<long>(nd), dense_.begin());
  }

  int cursor = layColumn(c);
  // Parcels that moved in sideways over a lower surface (a crater, a lower
  // neighbour) would drop onto it at once: they fall instead, from where
  // they are, and the rest of the column is laid again.  "Lower" is counted
  // beyond the settling of the column itself, seen at its highest own parcel.
  double settling = 0.0;
  for (auto it = dense_.rbegin(); it != dense_.rend(); ++it)
    if (previousColumn_[*it] == c) {
      settling = std::max(0.0, zKey_[*it] - z_[*it]);
      break;
    }
  const size_t laid = dense_.size();
  while (!dense_.empty() && previousColumn_[dense_.back()] != c &&
         zKey_[dense_.back()] > z_[dense_.back()] + settling + hz_) {
    const int32_t p = dense_.back();
    dense_.pop_back();
    airborne_[p] = 1;
    z_[p] = std::min(zKey_[p], lz_ * (1.0 - 1e-12));
    vx_[p] = vy_[p] = vz_[p] = 0.0;
    air_.push_back(p);
  }
  if (dense_.size() != laid) cursor = layColumn(c);
  settleAirborne(dense_, cursor);

  int32_t e = colStart_[c];
  for (int32_t p : dense_) order_[e++] = p;
  denseEnd_[c] = e;
  for (int32_t p : air_) order_[e++] = p;
  top_[c] = cursor;
}

// Lay the sorted dense parcels of column c (dense_) one per slot from the
// floor.  The first parcel at or above a bubble's centre jumps to the top of
// the bubble's chord, so the void is the chord above the bubble centre and
// whatever the wake below has not filled.  Records where the solid below each
// void ended and above it starts, and each bubble's roof.  Slots never exceed
// the box: voids give way first.  Returns the top slot.
// Near a bubble's rim the void part of a chord is short and the sideways flow
// that should fill in below it is weak; there, solid slides past the chord:
// while the solid below has not reached the wake level, parcels from just
// above are laid below (a drop of at most two cells).
int SyntheticBed::layColumn(int c) {
  const int passLimit = 2 * ppc_;
  const int32_t vBegin = voidStart_[c], vEnd = voidStart_[c + 1];
  for (int32_t v = vBegin; v < vEnd; ++v) {
    voids_[v].belowTop = voids_[v].aboveStart = -1;
    Bubble &b = bubbles_[voids_[v].bubble];
    if (b.centreColumn == c) b.roof = 0;
  }
  int cursor = 0;
  int32_t v = vBegin;
  const int n = static_cast<int>(dense_.size());
  // A bubble's roof is the solid between it and the surface or the next
  // erupted void above (a crater): a bubble rising into a crater erupts.
  int openRoof[8], numOpen = 0;
  for (int r = 0; r < n; ++r) {
    const int32_t p = dense_[r];
    for (; v < vEnd && zKey_[p] >= voids_[v].zCentre; ++v) {
      const VoidChord &chord = voids_[v];
      const bool shortChord = chord.topSlot - chord.wakeTopSlot <= passLimit;
      const bool nearby = zKey_[p] - cursor * slotHeight_ <= passLimit * slotHeight_;
      if (cursor < chord.wakeTopSlot && shortChord && nearby) break; // p passes the chord
      const int jump = std::min(voids_[v].topSlot, maxSlots_ - (n - r));
      voids_[v].belowTop = cursor;
      cursor = std::max(cursor, jump);
      voids_[v].aboveStart = cursor;
      Bubble &b = bubbles_[voids_[v].bubble];
      if (b.erupted)
        for (; numOpen > 0; --numOpen) bubbles_[openRoof[numOpen - 1]].roof -= n - r;
      if (b.centreColumn == c) {
        b.roof = n - r;
        if (numOpen < 8) openRoof[numOpen++] = voids_[v].bubble;
      }
    }
    // (Only a column holding more parcels than the box has slots could
    // overflow; it then crowds the top cell rather than leave the mesh.)
    slot_[p] = std::min(cursor, maxSlots_ - 1);
    z_[p] = (slot_[p] + 0.5) * slotHeight_;
    ++cursor;
  }
  return std::min(cursor, maxSlots_);
}

// Airborne parcels of the column being stacked (air_) that are inside the
// stack, or falling onto its surface, land on top.  The rest stay airborne; if
// a cell would then hold more than ppc parcels the extra ones are lifted to
// the next free cell (a guard that dense splashes practically never need).
void SyntheticBed::settleAirborne(std::vector<int32_t> &dense, int &cursor) {
  if (air_.empty()) return;
  std::sort(air_.begin(), air_.end(), [&](int32_t a, int32_t b) {
    return z_[a] != z_[b] ? z_[a] < z_[b] : a < b;
  });
  size_t kept = 0;
  for (int32_t p : air_) {
    const double surface = cursor * slotHeight_;
    const bool lands = z_[p] < surface || (vz_[p] <= 0.0 && z_[p] < surface + 0.5 * hz_);
    if (lands && cursor < maxSlots_) {
      airborne_[p] = 0;
      vx_[p] = vy_[p] = vz_[p] = 0.0;
      slot_[p] = cursor;
      z_[p] = zKey_[p] = (cursor + 0.5) * slotHeight_;
      ++cursor;
      dense.push_back(p);
    } else {
      air_[kept++] = p;
    }
  }
  air_.resize(kept);
  if (air_.empty()) return;
  cellCount_.assign(nz_, 0);
  for (int32_t p : dense) ++cellCount_[slot_[p] / ppc_];
  const int surfaceLayer = cursor / ppc_;
  for (int32_t p : air_) {
    const int k0 = layerOf(z_[p]);
    int k = k0;
    if (vz_[p] <= 0.0) // falling: to a free cell below, if any above the surface
      while (cellCount_[k] >= ppc_ && k > surfaceLayer) --k;
    if (cellCount_[k] >= ppc_) k = k0;
    while (k + 1 < nz_ && cellCount_[k] >= ppc_) ++k;
    while (cellCount_[k] >= ppc_ && k > 0) --k; // full up to the lid: look below
    if (k != k0) { // it hit the parcels there: moved, and no longer rising
      z_[p] = zKey_[p] = (k + 0.5) * hz_;
      vz_[p] = std::min(vz_[p], 0.0);
    }
    ++cellCount_[k];
  }
}

// Horizontal dispersion that keeps every column's content: two parcels at the
// same slot of neighbouring columns swap their horizontal positions.  A random
// walk with hop rate D / h^2 across each face gives D dt / h^2 swaps per pair
// of facing parcels and substep.
void SyntheticBed::disperse(double dt) {
  const double rateX = opt_.dispersion * dt / (hx_ * hx_);
  const double rateY = opt_.dispersion * dt / (hy_ * hy_);
  auto swapAcross = [&](int a, int b, double rate) {
    const int levels = std::min(top_[a], top_[b]);
    const double expected = rate * levels;
    int count = static_cast<int>(expected);
    if (rng_.uniform() < expected - count) ++count;
    for (int m = 0; m < count; ++m) {
      const int slot = std::min(levels - 1, static_cast<int>(rng_.uniform() * levels));
      const int32_t p = parcelAtSlot(a, slot), q = parcelAtSlot(b, slot);
      if (p < 0 || q < 0) continue; // a void at this level
      std::swap(x_[p], x_[q]);
      std::swap(y_[p], y_[q]);
    }
  };
  for (int j = 0; j < ny_; ++j)
    for (int i = 0; i < nx_; ++i) {
      const int c = i + nx_ * j;
      if (i + 1 < nx_) swapAcross(c, c + 1, rateX);
      if (j + 1 < ny_) swapAcross(c, c + nx_, rateY);
    }
}

// The dense parcel of column c at `slot`, or -1 (binary search: a column's
// dense parcels are in slot order right after a restack).
int32_t SyntheticBed::parcelAtSlot(int c, int slot) const {
  // Below the first void a column's slots are 0, 1, 2, ...: try that first.
  const int32_t guess = colStart_[c] + slot;
  if (guess < denseEnd_[c] && slot_[order_[guess]] == slot) return order_[guess];
  const auto first = order_.begin() + colStart_[c], last = order_.begin() + denseEnd_[c];
  const auto it =
      std::lower_bound(first, last, slot, [&](int32_t p, int s) { return slot_[p] < s; });
  return it != last && slot_[*it] == slot ? *it : -1;
}

// The dipole flow closes in behind a bubble only approximately (walls, the
// discrete stacking), so under a void the solid may end below the wake level,
// leaving a gap that would trail the bubble as a tail.  Such a gap is filled
// by the emulsion flowing in sideways: parcels at the gap's heights (or up to
// one cell above) are taken from the neighbouring columns, those farther from
// the bubble axis first (limited to 2 m/s of filling per receiving column and
// 1 m/s of sinking per donor).  For every parcel pulled in below the void,
// one parcel from just above the void is pushed out to the same neighbour (at
// the next substep, before restacking), so no column gains or loses solid:
// together this is the flow around the bubble, the neighbour's stack carrying
// it down from above the void to below it.
void SyntheticBed::fillWakeGaps(double dt) {
  std::fill(pulled_.begin(), pulled_.end(), 0);
  given_.assign(ncol_, 0);
  // Rates: a gap fills at up to 2 m/s, a donor sinks at up to 1 m/s (several
  // times the rise velocity, so the flow keeps up with the bubbles).
  const int maxWanted = std::max(1, static_cast<int>(2.0 * dt / slotHeight_));
  const int maxGiven = std::max(1, static_cast<int>(1.0 * dt / slotHeight_));
  // Donors' budgets go first come, first served: alternate the sweep direction
  // so that no side of the bed is favoured.
  const bool backward = substeps_ % 2 == 1;
  for (int m = 0; m < ncol_; ++m) {
    const int c = backward ? ncol_ - 1 - m : m;
    for (int32_t v = voidStart_[c]; v < voidStart_[c + 1]; ++v) {
      VoidChord &chord = voids_[v];
      if (chord.belowTop < 0) continue;
      int want = std::min(chord.wakeTopSlot - chord.belowTop, maxWanted);
      if (want <= 0) continue;
      std::pair<double, int> around[4];
      const int numAround = neighboursByAxisDistance(c, bubbles_[chord.bubble], backward, around);
      for (int d = 0; d < numAround && want > 0; ++d) {
        const int donor = around[d].second;
        const int most = std::min(want, maxGiven - given_[donor]);
        if (most <= 0) continue;
        const int got = pullFrom(donor, c, chord.belowTop, chord.wakeTopSlot + ppc_, most);
        given_[donor] += got;
        chord.belowTop += got;
        want -= got;
        if (got > 0) queuePushes(c, chord.aboveStart, donor, got);
      }
    }
  }
}

// The (up to four) neighbours of column c with their squared distances from
// bubble b's axis, farthest first (ties in sweep order).  Returns how many
// there are.
int SyntheticBed::neighboursByAxisDistance(int c, const Bubble &b, bool backward,
                                           std::pair<double, int> *out) const {
  const int ci = c % nx_, cj = c / nx_;
  const int di[4] = {-1, 1, 0, 0}, dj[4] = {0, 0, -1, 1};
  int n = 0;
  for (int d = 0; d < 4; ++d) {
    const int i = ci + di[d], j = cj + dj[d];
    if (i < 0 || i >= nx_ || j < 0 || j >= ny_) continue;
    const double dx = (i + 0.5) * hx_ - b.x, dy = (j + 0.5) * hy_ - b.y;
    out[n++] = {dx * dx + dy * dy, i + nx_ * j};
  }
  if (backward) std::reverse(out, out + n);
  for (int d = 1; d < n; ++d) // insertion sort of at most four
    for (int e = d; e > 0 && out[e].first > out[e - 1].first; --e) std::swap(out[e], out[e - 1]);
  return n;
}

// Queue `count` parcels of column c from slot `fromSlot` up (lowest first) to
// move to column `target`.
void SyntheticBed::queuePushes(int c, int fromSlot, int target, int count) {
  int pushed = 0;
  for (int32_t e = colStart_[c]; e < denseEnd_[c] && pushed < count; ++e) {
    const int32_t p = order_[e];
    if (pulled_[p] || airborne_[p] || slot_[p] < fromSlot) continue;
    pulled_[p] = 1;
    pushes_.push_back({p, target});
    ++pushed;
  }
}

// Carry out the pushes queued by the last fillWakeGaps (before restacking, so
// the receiving column makes room at the parcel's height).
void SyntheticBed::applyPushes() {
  for (const auto &push : pushes_) {
    const int32_t p = push.first;
    if (airborne_[p]) continue; // thrown up by an eruption meanwhile
    const int ti = push.second % nx_, tj = push.second / nx_;
    x_[p] = (ti + rng_.uniform()) * hx_;
    y_[p] = (tj + rng_.uniform()) * hy_;
  }
  pushes_.clear();
}

// Move up to `most` dense parcels of column `donor` whose slots lie in
// [fromSlot, toSlot), lowest first, into the empty slots fromSlot,
// fromSlot + 1, ... of column `receiver`.  Returns how many moved.
int SyntheticBed::pullFrom(int donor, int receiver, int fromSlot, int toSlot, int most) {
  const int ri = receiver % nx_, rj = receiver / nx_;
  int moved = 0;
  for (int32_t e = colStart_[donor]; e < denseEnd_[donor] && moved < most; ++e) {
    const int32_t p = order_[e];
    if (pulled_[p] || airborne_[p] || slot_[p] < fromSlot || slot_[p] >= toSlot) continue;
    pulled_[p] = 1;
    x_[p] = (ri + rng_.uniform()) * hx_;
    y_[p] = (rj + rng_.uniform()) * hy_;
    slot_[p] = fromSlot + moved;
    z_[p] = zKey_[p] = (slot_[p] + 0.5) * slotHeight_;
    ++moved;
  }
  return moved;
}

// Renumber parcel storage to the current column order (identities stay in id_).
void SyntheticBed::renumber() {
  const size_t n = x_.size();
  std::vector<double> tmp(n);
  for (auto *v : {&x_, &y_, &z_, &zKey_, &vx_, &vy_, &vz_}) {
    for (size_t e = 0; e < n; ++e) tmp[e] = (*v)[order_[e]];
    v->swap(tmp);
  }
  std::vector<int32_t> itmp(n);
  for (auto *v : {&slot_, &id_}) {
    for (size_t e = 0; e < n; ++e) itmp[e] = (*v)[order_[e]];
    v->swap(itmp);
  }
  std::vector<uint8_t> btmp(n);
  for (size_t e = 0; e < n; ++e) btmp[e] = airborne_[order_[e]];
  airborne_.swap(btmp);
  for (size_t e = 0; e < n; ++e) order_[e] = static_cast<int32_t>(e);
}

// A bubble erupts when the dense roof over its centre column is thinner than
// eruptionRoof radii, or when its centre is above the mean bed surface.  Its
// roof is thrown up; the bubble stops and its void closes at the growth rate,
// so the crater walls slump in over several substeps.
void SyntheticBed::eruptBubbles() {
  const double surface = meanSurfaceHeight();
  for (size_t k = 0; k < bubbles_.size(); ++k) {
    Bubble &b = bubbles_[k];
    if (b.erupted) continue;
    const bool thinRoof = b.roof * slotHeight_ < opt_.eruptionRoof * b.radius();
    if (!thinRoof && b.z < surface) continue;
    eject(static_cast<int>(k));
    ++erupted;
    b.erupted = b.absorbed = true;
    b.shrinkRate = riseVelocity(std::max(b.diameter, opt_.initialDiameter));
    b.ux = b.uy = b.uz = 0.0;
  }
}

// The roof over an erupting bubble is thrown radially outward at
// ejectionSpeed * U with some scatter: in every column of its footprint, the
// parcels just above the void, a layer eruptionRoof radii plus one cell thick.
void SyntheticBed::eject(int k) {
  const Bubble &b = bubbles_[k];
  const double speed = opt_.ejectionSpeed * b.uz;
  const int roofSlots = static_cast<int>(std::ceil((opt_.eruptionRoof * b.radius() + hz_) / slotHeight_));
  for (int c = 0; c < ncol_; ++c)
    for (int32_t v = voidStart_[c]; v < voidStart_[c + 1]; ++v) {
      if (voids_[v].bubble != k || voids_[v].aboveStart < 0) continue;
      const int first = voids_[v].aboveStart, last = first + roofSlots;
      bool any = false;
      for (int32_t e = colStart_[c]; e < denseEnd_[c]; ++e) {
        const int32_t p = order_[e];
        if (pulled_[p] || slot_[p] < first || slot_[p] >= last) continue;
        const double dx = x_[p] - b.x, dy = y_[p] - b.y, dz = z_[p] - b.z;
        const double inv = 1.0 / std::sqrt(dx * dx + dy * dy + dz * dz);
        airborne_[p] = 1;
        vx_[p] = speed * (dx * inv + 0.25 * rng_.symmetric());
        vy_[p] = speed * (dy * inv + 0.25 * rng_.symmetric());
        vz_[p] = speed * (dz * inv + 0.25 * rng_.symmetric());
        any = true;
      }
      if (any) compactColumn(c);
    }
}

// After an ejection: dense parcels first (still in slot order), then airborne.
void SyntheticBed::compactColumn(int c) {
  dense_.clear();
  air_.clear();
  for (int32_t e = colStart_[c]; e < colStart_[c + 1]; ++e)
    (airborne_[order_[e]] ? air_ : dense_).push_back(order_[e]);
  int32_t e = colStart_[c];
  for (int32_t p : dense_) order_[e++] = p;
  denseEnd_[c] = e;
  for (int32_t p : air_) order_[e++] = p;
  top_[c] = dense_.empty() ? 0 : slot_[dense_.back()] + 1;
}

void SyntheticBed::cellsOf(std::vector<int32_t> &cells) const {
  const size_t n = x_.size();
  cells.resize(n);
  for (size_t p = 0; p < n; ++p) {
    const int layer = airborne_[p] ? layerOf(z_[p]) : slot_[p] / ppc_;
    cells[id_[p]] = columnOf(x_[p], y_[p]) + ncol_ * layer;
  }
}

double SyntheticBed::meanSurfaceHeight() const {
  long sum = 0;
  for (int t : top_) sum += t;
  return static_cast<double>(sum) / ncol_ * slotHeight_;
}

// ---------------------------------------------------------------------------
// Frames.

/// Column-stochastic shift from parcel identities: each parcel is one
/// transfer (cell at t_k) -> (cell at t_k+1).  Equal transfers are summed here
/// and handed over already ordered by (destination, source), which keeps the
/// sort inside shiftFromTransfers cheap.
CsrMatrix shiftBetween(int numCells, const std::vector<int32_t> &from,
                       const std::vector<int32_t> &to) {
  std::vector<int32_t> start(numCells + 1, 0);
  for (int32_t c : to) ++start[c + 1];
  for (int c = 0; c < numCells; ++c) start[c + 1] += start[c];
  std::vector<int32_t> sources(from.size());
  std::vector<int32_t> fill(start.begin(), start.end() - 1);
  for (size_t p = 0; p < from.size(); ++p) sources[fill[to[p]]++] = from[p];
  std::vector<int32_t> dest, src;
  std::vector<double> weight;
  dest.reserve(from.size());
  src.reserve(from.size());
  weight.reserve(from.size());
  for (int c = 0; c < numCells; ++c) {
    auto first = sources.begin() + start[c], last = sources.begin() + start[c + 1];
    for (auto it = first; it != last; ++it) // insertion sort: a cell gets few parcels
      for (auto jt = it; jt != first && *(jt - 1) > *jt; --jt) std::iter_swap(jt - 1, jt);
    for (auto it = first; it != last;) {
      auto runEnd = std::upper_bound(it, last, *it);
      dest.push_back(c);
      src.push_back(*it);
      weight.push_back(static_cast<double>(runEnd - it));
      it = runEnd;
    }
  }
  return shiftFromTransfers(numCells, std::move(dest), std::move(src), std::move(weight));
}

std::vector<double> alphaOf(int numCells, const std::vector<int32_t> &cells, double perParcel) {
  std::vector<int> count(numCells, 0);
  for (int32_t c : cells) ++count[c];
  std::vector<double> alpha(numCells);
  for (int c = 0; c < numCells; ++c) alpha[c] = count[c] * perParcel;
  return alpha;
}

/// Largest per-axis cell distance travelled by a parcel between two states.
class JumpMeter {
public:
  explicit JumpMeter(const BoxSpec &box) : ijk_(box.numCells()) {
    for (int k = 0; k < box.nz; ++k)
      for (int j = 0; j < box.ny; ++j)
        for (int i = 0; i < box.nx; ++i) ijk_[box.cellIndex(i, j, k)] = {i, j, k};
  }
  int largest(const std::vector<int32_t> &from, const std::vector<int32_t> &to) const {
    int jump = 0;
    for (size_t p = 0; p < from.size(); ++p) {
      const auto &a = ijk_[from[p]], &b = ijk_[to[p]];
      for (int axis = 0; axis < 3; ++axis) jump = std::max(jump, std::abs(a[axis] - b[axis]));
    }
    return jump;
  }

private:
  std::vector<std::array<int, 3>> ijk_;
};

/// Height of the solid's centre of gravity [m] from the parcels' cells (all
/// parcels have the same volume; heights are cell centres, as for alpha_s).
double centreOfGravity(const BoxSpec &box, const std::vector<int32_t> &cells) {
  const int perLayer = box.nx * box.ny;
  double sum = 0.0;
  for (int32_t c : cells) sum += c / perLayer + 0.5;
  return sum / static_cast<double>(cells.size()) * box.spacing()[2];
}

void require(bool ok, const std::string &sentence) {
  if (!ok) throw std::invalid_argument("synthetic bed: " + sentence);
}

} // namespace

void validateSyntheticBedOptions(const SyntheticBedOptions &o) {
  const BoxSpec &box = o.box;
  require(box.nx >= 1 && box.ny >= 1 && box.nz >= 2, "the box needs at least 1 x 1 x 2 cells.");
  require(box.length[0] > 0.0 && box.length[1] > 0.0 && box.length[2] > 0.0,
          "the box lengths must be positive.");
  require(static_cast<double>(box.nx) * box.ny * box.nz < 2.0e9,
          "the box has too many cells for 32-bit cell indices.");
  require(o.numFrames >= 1, "numFrames must be at least 1.");
  require(o.dtRec > 0.0 && std::isfinite(o.dtRec), "dtRec must be positive.");
  require(o.maxSubstep > 0.0 && std::isfinite(o.maxSubstep), "maxSubstep must be positive.");
  require(o.dtRec / o.maxSubstep <= 1e4, "dtRec / maxSubstep must not exceed 10000 substeps.");
  require(o.warmUpTime >= 0.0 && std::isfinite(o.warmUpTime), "warmUpTime must not be negative.");
  require(o.bedHeight > 0.0, "bedHeight must be positive.");
  require(o.bedHeight < box.length[2], "bedHeight must be below the top of the box.");
  require(o.bedHeight <= 0.7 * box.length[2],
          "bedHeight must leave at least 30 % of the box height as freeboard for voids and splashes.");
  require(o.packing > 0.0 && o.packing < 0.65, "packing must be in (0, 0.65).");
  require(o.parcelsPerCell >= 1 && o.parcelsPerCell <= 1000,
          "parcelsPerCell must be between 1 and 1000.");
  const double parcels = o.bedHeight / box.length[2] * box.nz * o.parcelsPerCell *
                         static_cast<double>(box.nx) * box.ny;
  require(parcels >= 1.0, "the bed holds no parcel: raise bedHeight or parcelsPerCell.");
  require(parcels < 2.0e9, "the bed holds too many parcels: lower parcelsPerCell.");
  require(o.dispersion >= 0.0, "dispersion must not be negative.");
  require(o.surfaceDiffusivity >= 0.0, "surfaceDiffusivity must not be negative.");
  require(o.nucleationRate >= 0.0 && std::isfinite(o.nucleationRate),
          "nucleationRate must not be negative.");
  require(o.nucleationStrips >= 1 && o.nucleationStrips <= 1000,
          "nucleationStrips must be between 1 and 1000.");
  require(o.initialDiameter > 0.0, "initialDiameter must be positive.");
  require(o.maxDiameter >= o.initialDiameter, "maxDiameter must not be below initialDiameter.");
  require(o.initialDiameter < std::min(box.length[0], box.length[2]),
          "initialDiameter must be smaller than the box width and height.");
  require(o.growthLength > 0.0, "growthLength must be positive.");
  require(o.riseCoefficient > 0.0, "riseCoefficient must be positive.");
  require(o.wakeFraction >= 0.0 && o.wakeFraction <= 0.5, "wakeFraction must be in [0, 0.5].");
  require(o.bubbleWander >= 0.0, "bubbleWander must not be negative.");
  require(o.centreDrift >= 0.0 && o.centreDrift <= 1.0, "centreDrift must be in [0, 1].");
  require(o.dipoleCutoff >= 1.0, "dipoleCutoff must be at least 1 (radius).");
  require(o.eruptionRoof >= 0.0, "eruptionRoof must not be negative.");
  require(o.ejectionSpeed >= 0.0, "ejectionSpeed must not be negative.");
  require(o.gravity > 0.0, "gravity must be positive.");
}

namespace {

/// The kinematic run behind both entry points: frames go to `sink` when it is
/// given; without it only the report (the per-frame series) is made, and the
/// shifts, the costly part, are not built.  The bed's motion is the same.
SyntheticBedReport runSyntheticBed(const SyntheticBedOptions &options, const FrameSink *sink) {
  const BoxSpec &box = options.box;
  const int numCells = box.numCells();
  const Vec3 h = box.spacing();
  const double cellVolume = h[0] * h[1] * h[2];

  SyntheticBed bed(options);
  const int substeps =
      std::max(1, static_cast<int>(std::ceil(options.dtRec / options.maxSubstep - 1e-9)));
  const double dt = options.dtRec / substeps;
  const long warmUp = static_cast<long>(std::ceil(options.warmUpTime / dt - 1e-9));
  for (long s = 0; s < warmUp; ++s) bed.advance(dt);
  bed.nucleated = bed.erupted = 0;

  SyntheticBedReport report;
  report.parcels = bed.numParcels();
  report.parcelVolume = bed.alphaPerParcel() * cellVolume;
  report.solidVolume = static_cast<double>(report.parcels) * report.parcelVolume;
  report.substepsPerFrame = substeps;

  const JumpMeter jumps(box);
  std::vector<int32_t> cells, next;
  bed.cellsOf(cells);
  const std::vector<double> alpha0 = alphaOf(numCells, cells, bed.alphaPerParcel());
  FrameRecord frame;
  frame.alphaS = alpha0;
  double heightSum = 0.0;
  report.surfaceHeight.reserve(options.numFrames);
  report.centreOfGravity.reserve(options.numFrames);
  for (int k = 0; k < options.numFrames; ++k) {
    heightSum += bed.meanSurfaceHeight();
    report.surfaceHeight.push_back(bed.meanSurfaceHeight());
    report.centreOfGravity.push_back(centreOfGravity(box, cells));
    for (int s = 0; s < substeps; ++s) bed.advance(dt);
    bed.cellsOf(next);
    report.maxAlpha = std::max(report.maxAlpha,
                               *std::max_element(frame.alphaS.begin(), frame.alphaS.end()));
    report.maxCellJump = std::max(report.maxCellJump, jumps.largest(cells, next));
    if (sink) {
      frame.shift = shiftBetween(numCells, cells, next);
      (*sink)(frame);
    }
    cells.swap(next);
    frame.alphaS = alphaOf(numCells, cells, bed.alphaPerParcel());
  }
  // frame.alphaS now holds alpha at t_K, where replay wraps to frame 0.
  report.maxAlpha =
      std::max(report.maxAlpha, *std::max_element(frame.alphaS.begin(), frame.alphaS.end()));
  for (int c = 0; c < numCells; ++c)
    report.wrapMismatchL1 += std::fabs(frame.alphaS[c] - alpha0[c]) * cellVolume;
  report.wrapMismatchRelative = report.wrapMismatchL1 / report.solidVolume;
  report.meanBedHeight = heightSum / options.numFrames;
  report.bubblesNucleated = bed.nucleated;
  report.bubblesErupted = bed.erupted;
  return report;
}

} // namespace

SyntheticBedReport generateSyntheticBed(const SyntheticBedOptions &options, const FrameSink &sink) {
  validateSyntheticBedOptions(options);
  if (!sink) throw std::invalid_argument("synthetic bed: the frame sink is empty.");
  return runSyntheticBed(options, &sink);
}

SyntheticBedReport generateSyntheticBedSeries(const SyntheticBedOptions &options) {
  validateSyntheticBedOptions(options);
  return runSyntheticBed(options, nullptr);
}

} // namespace rcfd
