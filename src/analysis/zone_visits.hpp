// A zone's visits from particle trajectories (rcfd reference -zones ...): the
// same distributions rcfd markov computes from the chain (docs/markov.md,
// "Validation against the particles"), from the particles of the dumps the
// database was built from.  A particle is in the zone at a snapshot when the
// cell holding its centre is; a visit is a run of consecutive snapshots in the
// zone (its length in snapshot intervals is the time per visit), the time
// away a run outside between two visits.
#pragma once

#include "rcfd/mesh.hpp"

#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

namespace rcfd {

class ZoneVisits {
public:
  /// `inside[c]`: whether natural cell c of `mesh` is in the zone.
  ZoneVisits(std::string name, BoxSpec mesh, std::vector<char> inside);

  /// Snapshots in order, equally spaced; positions in mesh axes.  A particle
  /// outside the mesh counts as outside the zone.
  void add(const std::vector<int64_t> &id, const std::vector<Vec3> &position, const std::vector<double> &mass);

  const std::string &name() const { return name_; }
  int snapshots() const { return snapshots_; }
  /// Mass-weighted share of the particle-snapshots in the zone.
  double share() const { return shareMass_ > 0 ? insideMass_ / shareMass_ : 0.0; }

  /// probability[n - 1] that a visit (away: a time outside between visits)
  /// lasts n snapshot intervals, mass-weighted, corrected for the end of the
  /// dumps: a run starting at snapshot k can only be seen to last n when
  /// k + n is a snapshot, so P(n) is the share of length n among the runs
  /// starting at k <= S - 1 - n (S snapshots), complete or not.  Runs already
  /// going at the first snapshot are left out (their start is unknown).  Given
  /// for the n whose eligible runs hold at least a tenth of all runs' mass
  /// (so for n up to about 0.9 S on a steady bed).
  std::vector<double> distribution(bool away) const;
  /// Complete runs counted (both ends seen) and runs cut by the last snapshot.
  std::size_t complete(bool away) const;
  std::size_t censored(bool away) const;
  /// probability[j] that a particle enters the zone j times within `steps`
  /// snapshot intervals (the last: maxPasses or more), mass-weighted, over
  /// every start snapshot k with k + steps a snapshot (an entry at snapshot e
  /// counts when k < e <= k + steps: outside at e - 1, in at e).
  std::vector<double> passCounts(int steps, int maxPasses) const;

private:
  struct State {
    int side = -1;  // 1 in the zone, 0 outside, -1 not seen yet
    int start = -1; // snapshot the current run started at; -1: unknown (seen from the first snapshot)
    double mass = 0.0;
    std::vector<int> entries; // snapshots it entered the zone at
  };
  struct Run {
    int start = 0, length = 0; // length 0: still going at the last snapshot
    double mass = 0.0;
  };
  std::string name_;
  BoxSpec mesh_;
  std::vector<char> inside_;
  std::unordered_map<int64_t, State> state_;
  std::vector<Run> runs_[2]; // [0]: visits (in the zone), [1]: away
  int snapshots_ = 0;
  double insideMass_ = 0.0, shareMass_ = 0.0;
  std::vector<Run> open(bool away) const; // the runs still going, as censored runs
};

} // namespace rcfd
