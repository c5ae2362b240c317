// The defaults of the Monitor base (include/rcfd/observables.hpp).
#include "rcfd/observables.hpp"
#include "observable/answers.hpp"
#include "base/petsc_compat.hpp"

#include <limits>

namespace rcfd {

PetscErrorCode Monitor::setUp(const RunContext &, const FractionState &, const std::string &) {
  return PETSC_SUCCESS;
}
PetscErrorCode Monitor::flush() { return PETSC_SUCCESS; }
PetscErrorCode Monitor::setFromOptions(MPI_Comm) { return PETSC_SUCCESS; }

PetscErrorCode Monitor::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer, "monitor %s\n", type().c_str()));
  PetscFunctionReturn(PETSC_SUCCESS);
}
std::vector<double> Monitor::saveState() const { return {}; }
double Monitor::signal(const std::string &) const { return std::numeric_limits<double>::quiet_NaN(); }
PetscErrorCode Monitor::steadyAt(const MonitorContext &, bool *steady) const {
  *steady = false;
  return PETSC_SUCCESS;
}

PetscErrorCode Monitor::restoreState(const std::vector<double> &state) {
  PetscFunctionBeginUser;
  PetscCheck(state.empty(), PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG,
             "A monitor that saves no state was given %zu numbers from a checkpoint", state.size());
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The built-in names are identifiers and distinct: add() cannot fail here.
MonitorRegistry MonitorRegistry::withBuiltins() {
  MonitorRegistry r;
  PetscCallAbort(PETSC_COMM_SELF, r.add("mixing_index", [] { return std::make_unique<MixingMonitor>(); },
                                        "Lacey's index of each fraction over time (mixing.csv)"));
  return r;
}

} // namespace rcfd
