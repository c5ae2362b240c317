// The defaults of the Monitor base (include/rcfd/observables.hpp).
#include "rcfd/observables.hpp"
#include "base/petsc_compat.hpp"

#include <limits>

namespace rcfd {

PetscErrorCode Monitor::setUp(const RunContext &, const FractionState &, const std::string &) {
  return PETSC_SUCCESS;
}
PetscErrorCode Monitor::flush() { return PETSC_SUCCESS; }
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

} // namespace rcfd
