#include "rcfd/observables.hpp"
#include "base/petsc_compat.hpp"

#include "base/atomic_file.hpp"
#include "base/collective.hpp"

#include <cerrno>
#include <cmath>
#include <fcntl.h>
#include <stdexcept>
#include <unistd.h>
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

namespace {
constexpr std::size_t kSpillBytes = 1u << 16; // rows waiting before they are written unasked
}

PetscErrorCode CsvSeries::add(const std::string &row) {
  PetscFunctionBeginUser;
  waiting += row;
  waiting += '\n';
  ++count;
  if (waiting.size() >= kSpillBytes) PetscCall(write(false)); // bounded by a size, not by the run's length
  PetscFunctionReturn(PETSC_SUCCESS);
}

namespace {

/// Appends `text` to `path`, synced to disk when asked; throws naming the file.
void appendText(const std::string &path, const std::string &text, bool sync) {
  const int fd = open(path.c_str(), O_WRONLY | O_APPEND);
  if (fd < 0) throw std::runtime_error("Cannot append to '" + path + "': " + std::strerror(errno));
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int why = errno;
      close(fd);
      throw std::runtime_error("Appending to '" + path + "' failed: " + std::strerror(why));
    }
    done += static_cast<std::size_t>(n);
  }
  const bool synced = !sync || fsync(fd) == 0;
  const int why = errno;
  if (close(fd) != 0 || !synced)
    throw std::runtime_error("Appending to '" + path + "' failed: " + std::strerror(synced ? errno : why));
}

} // namespace

PetscErrorCode CsvSeries::write(bool sync) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  if (started && waiting.empty()) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!started) waiting.insert(0, header + "\n");
  PetscCall(collectively(comm, [&] {
    if (rank != 0) return;
    if (started) appendText(path, waiting, sync);
    else writeTextAtomically(path, waiting); // a new run: no older file shows through
  }, PETSC_ERR_FILE_WRITE));
  written += waiting.size();
  waiting.clear();
  started = true;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode CsvSeries::resume(double mark) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCheck(mark >= 0 && mark == std::floor(mark) && mark < 9e15, comm, PETSC_ERR_FILE_UNEXPECTED,
             "The checkpoint's length of '%s' is not a byte count: %g", path.c_str(), mark);
  const auto bytes = static_cast<unsigned long long>(mark);
  PetscCall(collectively(comm, [&] {
    if (rank != 0) return;
    struct stat st;
    if (stat(path.c_str(), &st) != 0 || static_cast<unsigned long long>(st.st_size) < bytes)
      throw std::runtime_error("Cannot continue '" + path + "': the checkpoint's run had written " +
                               std::to_string(bytes) + " bytes to it, but it " +
                               (stat(path.c_str(), &st) != 0 ? std::string("is missing")
                                                             : "holds " + std::to_string(st.st_size)) +
                               "; restart into the output directory of the run that wrote the checkpoint");
    if (truncate(path.c_str(), static_cast<off_t>(bytes)) != 0)
      throw std::runtime_error("Cannot cut '" + path + "' back to the checkpoint's " + std::to_string(bytes) +
                               " bytes: " + std::strerror(errno));
  }, PETSC_ERR_FILE_UNEXPECTED));
  written = bytes;
  waiting.clear();
  count = 0;
  started = true;
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::string formatNumberRow(const std::vector<double> &row) {
  std::string text;
  char number[32];
  for (std::size_t c = 0; c < row.size(); ++c) {
    std::snprintf(number, sizeof number, "%.10g", row[c]);
    if (c) text += ',';
    text += number;
  }
  return text;
}

} // namespace rcfd
