#include "cli/commands.hpp"
#include "base/petsc_compat.hpp"

#include <string>

namespace rcfd::cli {

bool helpRequested() {
  PetscBool help = PETSC_FALSE;
  PetscOptionsHasName(nullptr, nullptr, "-help", &help);
  return help;
}

PetscErrorCode rejectUnusedOptions(MPI_Comm comm, const char *command) {
  PetscInt n;
  char **names, **values;
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsLeftGet(nullptr, &n, &names, &values));
  std::string unused;
  for (PetscInt i = 0; i < n; ++i) {
    const std::string name = names[i];
    // Options PETSc reads only at finalize or that rcfd's front end handles.
    if (name == "rcfd_traceback" || name.rfind("log_view", 0) == 0 || name == "malloc_dump" ||
        name == "malloc_debug" || name == "options_left" || name == "help")
      continue;
    unused += (unused.empty() ? "-" : ", -") + name;
  }
  PetscCall(PetscOptionsLeftRestore(nullptr, &n, &names, &values));
  PetscCheck(unused.empty(), comm, PETSC_ERR_USER_INPUT,
             "Unknown option %s: 'rcfd %s' does not use it (misspelt? 'rcfd %s -help' lists the options)",
             unused.c_str(), command, command);
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
