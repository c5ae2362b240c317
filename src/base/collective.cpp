#include "base/collective.hpp"
#include "base/petsc_compat.hpp"

#include "rcfd/handle.hpp"

namespace rcfd {

PetscErrorCode agreeOnFailure(MPI_Comm comm, bool failed, const std::string &why,
                              PetscErrorCode code) {
  PetscMPIInt rank, size, first;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscMPIInt mine = failed ? rank : size;
  PetscCallMPI(MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm));
  if (first == size) PetscFunctionReturn(PETSC_SUCCESS);
  int length = rank == first ? static_cast<int>(why.size()) : 0;
  PetscCallMPI(MPI_Bcast(&length, 1, MPI_INT, first, comm));
  std::string text = rank == first ? why : std::string(length, ' ');
  PetscCallMPI(MPI_Bcast(text.data(), length, MPI_CHAR, first, comm));
  SETERRQ(comm, code, "%s", text.c_str());
}

PetscErrorCode agreeOnStatus(MPI_Comm comm, PetscErrorCode status) {
  const char *generic = nullptr;
  char *specific = nullptr;
  if (status) PetscErrorMessage(status, &generic, &specific);
  const std::string why = specific && *specific ? specific : (generic ? generic : "");
  return agreeOnFailure(comm, status != 0, why, status ? status : PETSC_ERR_FILE_UNEXPECTED);
}

} // namespace rcfd
