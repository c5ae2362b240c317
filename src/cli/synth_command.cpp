#include "cli/commands.hpp"
namespace rcfd::cli {
PetscErrorCode synthCommand(MPI_Comm) { return PETSC_ERR_SUP; }
}
