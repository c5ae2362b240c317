// What an operator sees: the case while it is set up (RunContext) and the
// step it advances (StepInfo).
#pragma once

#include "rcfd/database.hpp"
#include "rcfd/fractions.hpp"

namespace rcfd {

/// What an operator may read while it is set up.
struct RunContext {
  const Database &db;
  const FractionSet &fractions;
  double solidDensity; // [kg/m^3]
  /// The conditions the run operates at when they are not the database file's
  /// (a run on several databases: -db_conditions, a blend's interpolation, and
  /// a schedule's u_sup at the current time; docs/databases.md); null:
  /// db.metadata().conditions.
  const OperatingConditions *conditions = nullptr;
  /// The run's conditions now: `conditions`, else the database file's.
  const OperatingConditions &operatingConditions() const { return conditions ? *conditions : db.metadata().conditions; }
};

/// The step being taken: frame k moves the state from t_k to t_k + dt_rec.
struct StepInfo {
  long step = 0;      // 0-based step counter
  double time = 0.0;  // simulated time at the start of the step [s]
  double dt = 0.0;    // dt_rec [s]
  int frame = 0;      // database frame used by this step
  int nextFrame = 0;  // frame of the following step
  bool jump = false;  // true when nextFrame != frame + 1 (wrap or stitching jump)
};

} // namespace rcfd
