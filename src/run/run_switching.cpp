// A run on several databases: the operators follow the active database
// (docs/databases.md).  The rule and its signals are in src/switching.
#include "run/run_impl.hpp"
#include "base/petsc_compat.hpp"

#include <cstdio>

namespace rcfd {

std::string Run::Impl::databaseInUse() const {
  if (!switching) return dbPath;
  const SwitchDecision &d = switching->active();
  const std::string &first = switching->set().entry(d.database).path;
  if (d.partner < 0) return first;
  char text[64];
  std::snprintf(text, sizeof text, " (weight %.4g) blended with ", d.weight);
  std::string out = first + text + switching->set().entry(d.partner).path;
  std::snprintf(text, sizeof text, " (weight %.4g)", 1.0 - d.weight);
  return out + text;
}

PetscErrorCode Run::Impl::followSwitches(long step, double time, int nextFrame) {
  bool change = false;
  SwitchDecision target;
  PetscFunctionBeginUser;
  PetscCall(switching->decide(step, time, fstate, &change, &target));
  if (change) PetscCall(switchTo(target, nextFrame, time, true));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The operators are set up anew on the database, as at the start: the shift
// takes its frames, drift makes its agitation field for it, the swaps their faces.  What
// they keep across a restart (saveState) they keep across a switch too.
PetscErrorCode Run::Impl::switchTo(const SwitchDecision &target, int nextFrame, double time, bool remap) {
  PetscFunctionBeginUser;
  const SwitchDecision from = switching->active();
  const double start = MPI_Wtime();
  std::vector<std::vector<double>> kept; // what each operator keeps, taken while its database lives
  for (const auto &op : ops.operators()) kept.push_back(op->saveState());
  // The database switched from goes first, before the next is read, so that a
  // run holds one database (and a blend its two while it is made); the
  // operators that point into it are set up again below, before any use.
  db.reset();
  PetscCall(switching->activate(target, time, &db));
  const RunContext ctx = context();
  for (std::size_t k = 0; k < ops.operators().size(); ++k) {
    PetscCall(ops.operators()[k]->setUp(ctx));
    PetscCall(ops.operators()[k]->restoreState(kept[k]));
  }
  switching->set().dropUnused(); // a blend's two databases
  // The scalars' sources hold the database (spray zone, layers, gas conditions): set up on the new one,
  // their account kept.
  if (scalars.size() > 0) PetscCall(scalars.setUp(*db, set, solidDensity));
  if (remap) { // the composition remap of a stitching jump, onto the new database's frame (amounts with their masses)
    PetscCall(switchCarry->setUp(ctx));
    StepInfo jump;
    jump.jump = true;
    jump.frame = dbFrame(nextFrame); // the new database's frame of the path's
    jump.nextFrame = jump.frame;
    PetscCall(switchCarry->apply(jump, fstate));
    PetscCall(switching->record(time, from, MPI_Wtime() - start));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
