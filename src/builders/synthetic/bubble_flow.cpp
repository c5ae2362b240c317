// Sub-step 2 of the kinematic bed: dense parcels move with the potential flow
// around each bubble (a dipole with mirror images), or with the bubble inside it.
#include "builders/synthetic/kinematic_bed.hpp"

namespace rcfd::synthetic {
namespace {

/// Keep a coordinate inside [0, L): reflect at the walls, then clamp.
inline double keepInside(double v, double length) {
  if (v < 0.0) v = -v;
  if (v >= length) v = 2.0 * length - v;
  return std::min(std::max(v, 0.0), length * (1.0 - 1e-12));
}

} // namespace

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

} // namespace rcfd::synthetic
