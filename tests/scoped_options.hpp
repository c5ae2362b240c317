// Test helpers: options set for one check only, and PETSc errors captured
// with their first message, so that checks can assert on the sentence.
#pragma once

#include <petscsys.h>

#include <cctype>
#include <sstream>
#include <string>
#include <vector>

namespace {

// Options inserted for one check and removed again, so that checks do not
// see each other's options.
class ScopedOptions {
public:
  explicit ScopedOptions(const std::string &options) {
    PetscCallAbort(PETSC_COMM_WORLD, PetscOptionsInsertString(nullptr, options.c_str()));
    std::istringstream words(options);
    for (std::string w; words >> w;)
      if (w.size() > 1 && w[0] == '-' && !std::isdigit(static_cast<unsigned char>(w[1])))
        names.push_back(w);
  }
  ~ScopedOptions() {
    for (const auto &n : names) (void)PetscOptionsClearValue(nullptr, n.c_str());
  }

private:
  std::vector<std::string> names;
};

// Records the first message of PETSc errors raised while it lives, instead
// of printing tracebacks: for checks that an error is raised with its sentence.
class ErrorCapture {
public:
  ErrorCapture() { PetscCallAbort(PETSC_COMM_WORLD, PetscPushErrorHandler(handler, this)); }
  ~ErrorCapture() { (void)PetscPopErrorHandler(); }
  const std::string &message() const { return first; }

private:
  static PetscErrorCode handler(MPI_Comm, int, const char *, const char *, PetscErrorCode n,
                                PetscErrorType p, const char *mess, void *ctx) {
    auto *self = static_cast<ErrorCapture *>(ctx);
    if (p == PETSC_ERROR_INITIAL && self->first.empty() && mess) self->first = mess;
    return n;
  }
  std::string first;
};

} // namespace
