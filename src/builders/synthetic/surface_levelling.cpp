// Sub-step 4 of the kinematic bed: the surface is levelled, parcels slide from
// higher to lower columns.
#include "builders/synthetic/kinematic_bed.hpp"

namespace rcfd::synthetic {

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

} // namespace rcfd::synthetic
