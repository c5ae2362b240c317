#include "analysis/zone_visits.hpp"

#include <algorithm>
#include <stdexcept>

namespace rcfd {

namespace {
// P(n) is given while the runs that could show n (those starting early
// enough) hold at least this share of all runs' mass; beyond, a handful of
// early runs would make it.
constexpr double kEligible = 0.1;
} // namespace

ZoneVisits::ZoneVisits(std::string name, BoxSpec mesh, std::vector<char> inside)
    : name_(std::move(name)), mesh_(mesh), inside_(std::move(inside)) {
  if (static_cast<long long>(inside_.size()) != static_cast<long long>(mesh_.nx) * mesh_.ny * mesh_.nz)
    throw std::invalid_argument("ZoneVisits: the zone's cell list does not match the mesh");
}

void ZoneVisits::add(const std::vector<int64_t> &id, const std::vector<Vec3> &position,
                     const std::vector<double> &mass) {
  const int k = snapshots_++;
  for (std::size_t p = 0; p < id.size(); ++p) {
    const int cell = mesh_.locate(position[p]);
    const int side = cell >= 0 && inside_[static_cast<std::size_t>(cell)] ? 1 : 0;
    insideMass_ += side * mass[p];
    shareMass_ += mass[p];
    State &s = state_[id[p]];
    s.mass = mass[p];
    if (s.side == side) continue;
    // The run on the other side ended at k - 1; one on this side starts at k.
    if (s.side >= 0 && s.start >= 0) runs_[s.side == 0].push_back({s.start, k - s.start, s.mass});
    if (s.side == 0) s.entries.push_back(k);
    s.start = s.side < 0 ? -1 : k;
    s.side = side;
  }
}

std::vector<ZoneVisits::Run> ZoneVisits::open(bool away) const {
  std::vector<Run> runs;
  for (const auto &entry : state_)
    if (entry.second.start >= 0 && (entry.second.side == 0) == away)
      runs.push_back({entry.second.start, 0, entry.second.mass});
  return runs;
}

std::vector<double> ZoneVisits::distribution(bool away) const {
  std::vector<Run> runs = runs_[away];
  const std::vector<Run> going = open(away);
  runs.insert(runs.end(), going.begin(), going.end());
  const int S = snapshots_;
  std::vector<double> p;
  if (S < 2) return p;
  // ended[n]: mass of complete runs of length n; started[k]: mass of the runs
  // starting at k (complete or not).  P(n) = ended_n(start <= S-1-n) / started(<= S-1-n).
  std::vector<double> started(static_cast<std::size_t>(S), 0.0);
  std::vector<std::vector<std::pair<int, double>>> byLength(static_cast<std::size_t>(S));
  for (const Run &r : runs) {
    started[static_cast<std::size_t>(r.start)] += r.mass;
    if (r.length > 0) byLength[static_cast<std::size_t>(r.length)].emplace_back(r.start, r.mass);
  }
  // Cumulative starts: cum[k] = mass of runs starting at or before k.
  std::vector<double> cum(static_cast<std::size_t>(S), 0.0);
  double c = 0.0;
  for (int k = 0; k < S; ++k) cum[static_cast<std::size_t>(k)] = c += started[static_cast<std::size_t>(k)];
  for (int n = 1; n < S; ++n) {
    const int last = S - 1 - n; // latest start whose length n could be seen
    double num = 0.0;
    for (const auto &e : byLength[static_cast<std::size_t>(n)])
      if (e.first <= last) num += e.second;
    const double den = last >= 0 ? cum[static_cast<std::size_t>(last)] : 0.0;
    if (!(den >= kEligible * c)) break; // too few runs could show it: noise
    p.push_back(num / den);
  }
  return p;
}

std::vector<double> ZoneVisits::passCounts(int steps, int maxPasses) const {
  std::vector<double> p(static_cast<std::size_t>(maxPasses) + 1, 0.0);
  const int starts = snapshots_ - steps; // k = 0 .. S - 1 - steps
  if (steps < 1 || starts < 1) return {};
  double total = 0.0;
  for (const auto &entry : state_) {
    const std::vector<int> &e = entry.second.entries;
    // Entries in (k, k + steps], by two pointers as k advances.
    std::size_t lo = 0, hi = 0;
    for (int k = 0; k < starts; ++k) {
      while (lo < e.size() && e[lo] <= k) ++lo;
      while (hi < e.size() && e[hi] <= k + steps) ++hi;
      p[std::min<std::size_t>(hi - lo, static_cast<std::size_t>(maxPasses))] += entry.second.mass;
      total += entry.second.mass;
    }
  }
  for (double &v : p) v = total > 0 ? v / total : 0.0;
  return p;
}

std::size_t ZoneVisits::complete(bool away) const { return runs_[away].size(); }

std::size_t ZoneVisits::censored(bool away) const { return open(away).size(); }

} // namespace rcfd
