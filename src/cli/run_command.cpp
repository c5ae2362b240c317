#include "cli/commands.hpp"

#include "rcfd/run.hpp"

namespace rcfd::cli {

PetscErrorCode runCommand(MPI_Comm comm) {
  PetscBool view = PETSC_FALSE;
  PetscFunctionBeginUser;
  const OperatorRegistry registry = OperatorRegistry::withBuiltins();
  Run run(comm, registry);
  PetscCall(run.setFromOptions());
  PetscCall(PetscOptionsGetBool(nullptr, nullptr, "-run_view", &view, nullptr));
  if (helpRequested()) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(rejectUnusedOptions(comm, "run"));
  PetscCall(run.setUp());
  if (view) PetscCall(run.view(PETSC_VIEWER_STDOUT_(comm)));
  PetscCall(run.solve());
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
