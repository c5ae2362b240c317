// A switching rule whose u_sup over time can grow while the run goes: a live
// run (rcfd run -live, docs/live.md) appends the measured u_sup to it.  Private
// to the library (the built-in schedule and blend rules), so that the public
// SwitchRule keeps its layout for plugins built against it.
#pragma once

#include "base/petsc_compat.hpp"
#include "rcfd/switching.hpp"

#include <petscsys.h>

namespace rcfd {

class MeasuredSchedule {
public:
  virtual ~MeasuredSchedule() = default;
  /// Not collective.  u [m/s] from time t [s] on, appended as the
  /// measurements arrive, in increasing time from 0, before the run reaches t.
  virtual PetscErrorCode appendSchedule(double t, double u) = 0;
  /// The database (or blend) the rule runs the bed on at u_sup u [m/s], whatever the time: what a
  /// forecast's member switches to as its own u_sup goes (docs/live.md, "Forecasts").
  virtual SwitchDecision choiceFor(double u) const = 0;
};

} // namespace rcfd
