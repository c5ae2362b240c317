#include "rcfd/observables.hpp"
#include "base/petsc_compat.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <sys/stat.h>

namespace rcfd {

PetscErrorCode writeFileAtomically(const std::string &path, const std::string &text) {
  PetscFunctionBeginUser;
  const std::string tmp = path + ".tmp";
  FILE *f = std::fopen(tmp.c_str(), "w");
  PetscCheck(f, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "Cannot write '%s': %s", tmp.c_str(),
             std::strerror(errno));
  const size_t written = std::fwrite(text.data(), 1, text.size(), f);
  const bool closed = std::fclose(f) == 0;
  PetscCheck(written == text.size() && closed, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE,
             "Could not write all of '%s' (disk full?)", tmp.c_str());
  PetscCheck(std::rename(tmp.c_str(), path.c_str()) == 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE,
             "Cannot rename '%s' to '%s': %s", tmp.c_str(), path.c_str(), std::strerror(errno));
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
