// Sub-step 6 of the kinematic bed: horizontal dispersion by swaps of parcels
// between neighbouring columns.
#include "builders/synthetic/kinematic_bed.hpp"

namespace rcfd::synthetic {

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

} // namespace rcfd::synthetic
