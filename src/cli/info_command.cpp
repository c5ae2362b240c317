#include "cli/commands.hpp"
#include "base/petsc_compat.hpp"

#include "rcfd/database.hpp"

namespace rcfd::cli {

PetscErrorCode infoCommand(MPI_Comm comm, const char *positional) {
  char path[PETSC_MAX_PATH_LEN] = "";
  PetscBool set = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, nullptr, "rcfd info: what a database holds", "rcfd");
  PetscCall(PetscOptionsString("-db", "Database file (or give it as the first argument)", "", "",
                               path, sizeof path, &set));
  PetscOptionsEnd();
  DatabaseLoadOptions options;
  PetscCall(Database::optionsFromCommandLine(&options));
  if (helpRequested()) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(rejectUnusedOptions(comm, "info"));
  std::string file = positional ? positional : path;
  PetscCheck(!file.empty(), comm, PETSC_ERR_USER_INPUT, "No database given: rcfd info FILE");
  std::unique_ptr<Database> db;
  PetscCall(Database::load(comm, file, options, &db));
  PetscCall(db->view(PETSC_VIEWER_STDOUT_(comm)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
