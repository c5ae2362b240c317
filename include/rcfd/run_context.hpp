// What every operator and monitor of a run may read while it is set up: the
// database, the fractions and the conditions the run operates at.  In the state's
// room, below both operators and observables, which both see it.
#pragma once

#include "rcfd/database.hpp"
#include "rcfd/fractions.hpp"

#include <string>
#include <vector>

namespace rcfd {

/// What an operator or a monitor may read while it is set up.
struct RunContext {
  const Database &db;
  const FractionSet &fractions;
  double solidDensity; // [kg/m^3]
  /// The conditions the run operates at when they are not the database file's
  /// (a run on several databases: -db_conditions, a blend's interpolation, and
  /// a schedule's u_sup at the current time; docs/databases.md); null:
  /// db.metadata().conditions.
  const OperatingConditions *conditions = nullptr;
  /// Scalars the run carries per fraction (-scalars, docs/scalars.md): an
  /// operator that carries them (Operator::carriesScalars) prepares for
  /// FractionState::amounts() with numScalars x nf columns per cell.
  int numScalars = 0;
  /// Their names (-scalars), in the order of their columns; null without scalars.
  const std::vector<std::string> *scalarNames = nullptr;
  /// The run's conditions now: `conditions`, else the database file's.
  const OperatingConditions &operatingConditions() const { return conditions ? *conditions : db.metadata().conditions; }
};

} // namespace rcfd
