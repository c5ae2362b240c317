// The status page (-status, docs/live.md): OUTPUT_DIR/status.json with the
// latest numbers people act on -- time, Delta z, the bottom layer's d32 and
// u_mf/u_sup, the de-fluidization warning in plain words, the latest forecast
// (with a discharge, its product's size distribution), the database in use
// -- rewritten atomically (at most every -status_every wall seconds, at once
// when a warning, a forecast or the database is new, at the end), and OUTPUT_DIR/status.html, a
// self-contained page that polls it and the run's CSV files.  Any static
// server in the output directory shows it; rcfd runs no server of its own.
#pragma once

#include "rcfd/observables.hpp"

#include <functional>
#include <string>
#include <vector>

namespace rcfd {

class StatusMonitor final : public Monitor {
public:
  /// `byDefault`: whether -status is on when not given (on for a live run).
  explicit StatusMonitor(bool byDefault) : on(byDefault) {}
  std::string type() const override { return "status"; }
  /// -status 0|1, -status_every [wall s].
  PetscErrorCode setFromOptions(MPI_Comm comm) override;
  bool enabled() const { return on; }
  /// The monitors whose latest values the page shows (the run's list, sampled
  /// before this one at each step); they must outlive the monitor.
  void watch(std::vector<const Monitor *> monitors) { watched = std::move(monitors); }
  /// The name of the database in use, asked at each sample (the same on every rank); a change (a
  /// switch) rewrites status.json at once.
  void nameDatabase(std::function<std::string()> name) { database = std::move(name); }
  /// Collective.  Copies the page into `dir` (rank 0).
  PetscErrorCode setUp(const RunContext &run, const FractionState &state, const std::string &dir) override;
  /// Collective.  Rank 0 rewrites status.json when it is due; the ranks agree on
  /// whether it is (the slowest rank's clock) and on whether the write worked.
  PetscErrorCode sample(const MonitorContext &ctx) override;
  /// Collective: writes the latest sample's status.json if it is not written yet.
  PetscErrorCode flush() override;
  /// status.json's text for the latest values of the watched monitors, at `time` and `step`.
  std::string json(double time, long step, bool last) const;

private:
  PetscErrorCode write();
  /// What makes status.json worth writing at once when it changes: when the de-fluidization
  /// warning and the wet-bottom warning fired and when the latest forecast was issued (-1: not yet).
  std::vector<double> news() const;
  bool on;
  double every = 1.0;        // -status_every: wall seconds between writes
  double lastWrite = -1e300; // MPI_Wtime() of the last write
  MPI_Comm comm = MPI_COMM_NULL;
  std::string directory;
  std::vector<const Monitor *> watched;
  std::function<std::string()> database;
  std::string databaseName, writtenDatabase; // the latest sample's, and the one in status.json
  double time = 0.0; // the latest sample's
  long step = 0;
  bool last = false;
  std::vector<double> seen; // news() when last written
  bool pending = false;     // the latest sample is not in the file yet
};

/// The page's source: $RCFD_STATUS_PAGE, else share/rcfd/status/status.html
/// next to the program's prefix, else the source tree's src/cli/status/status.html.
std::string statusPageSource();

} // namespace rcfd
