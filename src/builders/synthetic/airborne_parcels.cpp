// Airborne parcels of the kinematic bed: their ballistic flight (sub-step 3)
// and their landing on a column while it is restacked (sub-step 5).
#include "builders/synthetic/kinematic_bed.hpp"

namespace rcfd::synthetic {

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

} // namespace rcfd::synthetic
