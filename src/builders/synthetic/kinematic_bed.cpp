// The kinematic bed's parcels: the settled bed, one substep (the sub-steps in
// order, see kinematic_bed.hpp), the storage order and the cells of the parcels.
#include "builders/synthetic/kinematic_bed.hpp"

#include <numeric>

namespace rcfd::synthetic {
namespace {

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

} // namespace

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

} // namespace rcfd::synthetic
