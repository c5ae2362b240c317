// Sub-step 5 of the kinematic bed: the void chords of the bubbles, and every
// column restacked from the floor, one parcel per slot, jumping over the voids.
#include "builders/synthetic/kinematic_bed.hpp"

namespace rcfd::synthetic {

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

} // namespace rcfd::synthetic
