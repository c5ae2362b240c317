// The defaults of the Monitor base (include/rcfd/observables.hpp).
#include "rcfd/observables.hpp"
#include "base/petsc_compat.hpp"

namespace rcfd {

PetscErrorCode Monitor::setUp(const RunContext &, const FractionState &, const std::string &) {
  return PETSC_SUCCESS;
}
PetscErrorCode Monitor::flush() { return PETSC_SUCCESS; }

} // namespace rcfd
