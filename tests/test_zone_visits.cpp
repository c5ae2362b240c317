// A zone's visits from particle trajectories (src/analysis/zone_visits, rcfd
// reference -zones): hand-made trajectories on a row of two cells, the zone
// being the first, with the run lengths known: complete runs, the correction
// for runs cut by the last snapshot, runs going at the first snapshot left
// out, the mass weighting and a particle outside the mesh.
#include "check.hpp"
#include "analysis/zone_visits.hpp"

#include <string>

using namespace rcfd;

namespace {

// Two cells of 1 m along x; the zone is cell 0 (x < 1).
ZoneVisits twoCells() {
  BoxSpec s;
  s.nx = 2;
  s.ny = 1;
  s.nz = 1;
  s.length = {2.0, 1.0, 1.0};
  return ZoneVisits("first", s, {1, 0});
}

// Feeds trajectories given as strings: '1' in the zone, '0' outside, 'x'
// outside the mesh; all of one length (the snapshots), particle p weighs mass[p].
void feed(ZoneVisits &v, const std::vector<std::string> &paths, const std::vector<double> &mass) {
  for (std::size_t k = 0; k < paths[0].size(); ++k) {
    std::vector<int64_t> id;
    std::vector<Vec3> pos;
    for (std::size_t p = 0; p < paths.size(); ++p) {
      id.push_back(static_cast<int64_t>(100 + p));
      const char c = paths[p][k];
      pos.push_back({c == '1' ? 0.5 : c == '0' ? 1.5 : 7.0, 0.5, 0.5});
    }
    v.add(id, pos, mass);
  }
}

void periodic() {
  // In for 2, out for 3, over 25 snapshots: every complete visit lasts 2, every time away 3.
  ZoneVisits v = twoCells();
  std::string path;
  for (int k = 0; k < 25; ++k) path += k % 5 < 2 ? '1' : '0';
  feed(v, {path}, {1.0});
  const std::vector<double> r = v.distribution(false), a = v.distribution(true);
  // The first visit (from snapshot 0) has no known start: 4 complete visits,
  // and the away runs at 2, 7, 12, 17 end, the one from 22 is cut.
  RCFD_CHECK(v.complete(false) == 4);
  RCFD_CHECK(v.complete(true) == 4);
  RCFD_CHECK(v.censored(true) == 1);
  RCFD_CHECK(v.censored(false) == 0);
  RCFD_CHECK(r.size() >= 3 && a.size() >= 4);
  for (std::size_t n = 0; n < r.size(); ++n) RCFD_CHECK_CLOSE(r[n], n + 1 == 2 ? 1.0 : 0.0, 1e-15);
  for (std::size_t n = 0; n < a.size(); ++n) RCFD_CHECK_CLOSE(a[n], n + 1 == 3 ? 1.0 : 0.0, 1e-15);
  RCFD_CHECK_CLOSE(v.share(), 10.0 / 25.0, 1e-15);
}

void cut() {
  // S = 10 snapshots.  A: visit 1..8 (ends at 9); B: visit from 5, still in
  // at 9 (cut); C and D: one-snapshot visits from 5 and 1.  Counting complete
  // visits alone gives P(8) = 1/3; among the visits that could show 8 (those
  // starting at or before 10 - 1 - 8 = 1: A and D) it is 1/2, and P(1) = 2/4.
  ZoneVisits v = twoCells();
  feed(v, {"0111111110", "0000011111", "0000010000", "0100000000"}, {1.0, 1.0, 1.0, 1.0});
  const std::vector<double> r = v.distribution(false);
  RCFD_CHECK(v.complete(false) == 3);
  RCFD_CHECK(v.censored(false) == 1);
  RCFD_CHECK(r.size() == 8); // n = 9 could only come from a start at 0, whose start is unknown
  RCFD_CHECK_CLOSE(r[0], 0.5, 1e-15);
  RCFD_CHECK_CLOSE(r[7], 0.5, 1e-15);
  for (int n = 2; n <= 7; ++n) RCFD_CHECK_CLOSE(r[n - 1], 0.0, 1e-15);
  // Mass-weighted: D three times heavier makes P(1) = (1 + 3) / 6 among all, P(8) = 1 / 4 among A and D.
  ZoneVisits w = twoCells();
  feed(w, {"0111111110", "0000011111", "0000010000", "0100000000"}, {1.0, 1.0, 1.0, 3.0});
  const std::vector<double> q = w.distribution(false);
  RCFD_CHECK_CLOSE(q[0], 4.0 / 6.0, 1e-15);
  RCFD_CHECK_CLOSE(q[7], 1.0 / 4.0, 1e-15);
  // A particle outside the mesh is outside the zone: 'x' ends a visit like '0'.
  ZoneVisits o = twoCells();
  feed(o, {"0110x11x00"}, {1.0});
  const std::vector<double> s = o.distribution(false);
  RCFD_CHECK(o.complete(false) == 2);
  RCFD_CHECK_CLOSE(s[1], 1.0, 1e-15);
  RCFD_CHECK_CLOSE(o.share(), 0.4, 1e-15);
}

void passes() {
  // In for 2, out for 3 (entries at 5, 10, 15, 20): within 5 intervals
  // exactly one entry from every start; within 7, two entries from the starts
  // k with two entries in (k, k + 7]: k = 3, 4 of each period of 5 (k <= 17).
  ZoneVisits v = twoCells();
  std::string path;
  for (int k = 0; k < 25; ++k) path += k % 5 < 2 ? '1' : '0';
  feed(v, {path}, {1.0});
  std::vector<double> p = v.passCounts(5, 3);
  RCFD_CHECK(p.size() == 4);
  if (p.size() == 4) RCFD_CHECK_CLOSE(p[1], 1.0, 1e-15);
  p = v.passCounts(7, 3);
  // Starts 0..17: two entries for k = 3, 4, 8, 9, 13, 14 (6 of 18).
  if (p.size() == 4) {
    RCFD_CHECK_CLOSE(p[2], 6.0 / 18.0, 1e-15);
    RCFD_CHECK_CLOSE(p[1], 12.0 / 18.0, 1e-15);
  }
  // Capped at 1: all of it in the last count.
  p = v.passCounts(7, 1);
  if (p.size() == 2) RCFD_CHECK_CLOSE(p[1], 1.0, 1e-15);
  RCFD_CHECK(p.size() == 2);
}

} // namespace

int main() {
  periodic();
  cut();
  passes();
  return RCFD_TEST_RESULT();
}
