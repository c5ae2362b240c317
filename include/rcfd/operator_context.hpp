// What an operator sees: the case while it is set up (RunContext, shared with
// the monitors) and the step it advances (StepInfo).
#pragma once

#include "rcfd/run_context.hpp"

#include <vector>

namespace rcfd {

/// The step being taken: frame k moves the state from t_k to t_k + dt_rec.
struct StepInfo {
  long step = 0;      // 0-based step counter
  double time = 0.0;  // simulated time at the start of the step [s]
  double dt = 0.0;    // dt_rec [s]
  int frame = 0;      // database frame used by this step
  int nextFrame = 0;  // frame of the following step
  bool jump = false;  // true when nextFrame != frame + 1 (wrap or stitching jump)
  /// The mass of each fraction [kg] the run's mass ledger expects at the
  /// step's start (its reference plus what the operators added), which the
  /// state holds up to round-off; nullptr when the run keeps no ledger.  An
  /// operator that needs the bed's totals reads them here instead of the bed.
  const std::vector<double> *expectedTotals = nullptr;
  /// The conditions the run operates at during the step (RunContext::operatingConditions:
  /// a schedule's or a live file's u_sup at the step's start); nullptr: those of set-up.
  const OperatingConditions *conditions = nullptr;
};

} // namespace rcfd
