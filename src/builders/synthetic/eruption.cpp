// Sub-step 8 of the kinematic bed: bubbles with a thin roof erupt, the roof is
// thrown up and the void closes gradually.
#include "builders/synthetic/kinematic_bed.hpp"

namespace rcfd::synthetic {

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

} // namespace rcfd::synthetic
