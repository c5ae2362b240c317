#include "rcfd/observables.hpp"
#include "base/petsc_compat.hpp"

#include "base/atomic_file.hpp"
#include "base/collective.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <sys/stat.h>

namespace rcfd {

PetscErrorCode writeFileAtomically(const std::string &path, const std::string &text) {
  PetscFunctionBeginUser;
  PetscCall(collectively(PETSC_COMM_SELF, [&] { writeTextAtomically(path, text); }, PETSC_ERR_FILE_WRITE));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode makeDirectories(MPI_Comm comm, const std::string &path) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  int failed = 0;
  if (rank == 0) {
    for (size_t pos = 1; pos <= path.size(); ++pos) {
      if (pos < path.size() && path[pos] != '/') continue;
      const std::string part = path.substr(0, pos);
      if (mkdir(part.c_str(), 0755) != 0 && errno != EEXIST) failed = errno;
    }
  }
  PetscCallMPI(MPI_Bcast(&failed, 1, MPI_INT, 0, comm));
  PetscCheck(!failed, comm, PETSC_ERR_FILE_OPEN, "Cannot create the output directory '%s': %s",
             path.c_str(), std::strerror(failed));
  PetscFunctionReturn(PETSC_SUCCESS);
}

CsvSeries::CsvSeries(MPI_Comm comm, std::string path, std::string header)
    : comm(comm), path(std::move(path)), header(std::move(header)) {}

PetscErrorCode CsvSeries::flush() const {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) {
    std::string text = header + "\n";
    for (const auto &r : rows) text += r + "\n";
    PetscCall(writeFileAtomically(path, text));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
