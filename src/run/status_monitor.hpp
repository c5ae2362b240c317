// The status page (-status, docs/live.md): OUTPUT_DIR/status.json with the
// latest numbers people act on -- time, Delta z, the bottom layer's d32 and
// u_mf/u_sup, the de-fluidization warning in plain words, the latest forecast
// -- rewritten atomically at each sample, and OUTPUT_DIR/status.html, a
// self-contained page that polls it and the run's CSV files.  Any static
// server in the output directory shows it; rcfd runs no server of its own.
#pragma once

#include "rcfd/observables.hpp"

#include <string>
#include <vector>

namespace rcfd {

class StatusMonitor final : public Monitor {
public:
  /// `byDefault`: whether -status is on when not given (on for a live run).
  explicit StatusMonitor(bool byDefault) : on(byDefault) {}
  std::string type() const override { return "status"; }
  /// -status 0|1.
  PetscErrorCode setFromOptions(MPI_Comm comm) override;
  bool enabled() const { return on; }
  /// The monitors whose latest values the page shows (the run's list, sampled
  /// before this one at each step); they must outlive the monitor.
  void watch(std::vector<const Monitor *> monitors) { watched = std::move(monitors); }
  /// Collective.  Copies the page into `dir` (rank 0).
  PetscErrorCode setUp(const RunContext &run, const FractionState &state, const std::string &dir) override;
  /// Collective.  Rank 0 rewrites status.json; the ranks agree on whether it could.
  PetscErrorCode sample(const MonitorContext &ctx) override;
  /// status.json's text for the latest values (public for the sake of tests and the summary).
  std::string json(const MonitorContext &ctx) const;

private:
  bool on;
  MPI_Comm comm = MPI_COMM_NULL;
  std::string directory;
  std::vector<const Monitor *> watched;
};

/// The page's source: $RCFD_STATUS_PAGE, else share/rcfd/status/status.html
/// next to the program's prefix, else the source tree's src/cli/status/status.html.
std::string statusPageSource();

} // namespace rcfd
