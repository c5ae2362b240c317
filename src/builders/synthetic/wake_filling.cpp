// Sub-step 7 of the kinematic bed: gaps under voids are filled from the
// neighbouring columns, balanced by pushing as many parcels out from above.
#include "builders/synthetic/kinematic_bed.hpp"

namespace rcfd::synthetic {

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

} // namespace rcfd::synthetic
