// Turning C++ exceptions and rank-local failures into one PETSc error that
// every rank of a communicator returns, with the first failing rank's text.
#pragma once

#include <petscsys.h>

#include <exception>
#include <stdexcept>
#include <string>

namespace rcfd {

/// Collective.  Every rank passes whether it failed and why; if any did, all
/// return PETSC_ERR_FILE_UNEXPECTED (or `code`) with the lowest failing rank's message.
PetscErrorCode agreeOnFailure(MPI_Comm comm, bool failed, const std::string &why,
                              PetscErrorCode code = PETSC_ERR_FILE_UNEXPECTED);

/// Collective.  `status` is this rank's result of a call that may fail on
/// some ranks only (a file written by rank 0); if it failed anywhere, every
/// rank returns an error with the lowest failing rank's message, so that no
/// rank goes on to wait in the next collective call.
PetscErrorCode agreeOnStatus(MPI_Comm comm, PetscErrorCode status);

/// Collective.  Runs body(); an exception thrown on any rank becomes a PETSc
/// error on all ranks carrying its message.
template <typename Body>
PetscErrorCode collectively(MPI_Comm comm, Body &&body,
                            PetscErrorCode code = PETSC_ERR_FILE_UNEXPECTED) {
  std::string why;
  bool failed = false;
  try {
    body();
  } catch (const std::exception &e) {
    failed = true;
    why = e.what();
  }
  return agreeOnFailure(comm, failed, why, code);
}

/// Not collective.  Runs call(), a function that returns a PetscErrorCode,
/// without PETSc printing a traceback, and throws std::invalid_argument with
/// its sentence if it fails: for internal code that reports by exceptions
/// calling the public, PETSc-style API.
template <typename Call> void throwOnError(Call &&call) {
  PetscErrorCode ierr = PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  if (!ierr) {
    ierr = call();
    (void)PetscPopErrorHandler();
  }
  if (!ierr) return;
  char *specific = nullptr;
  (void)PetscErrorMessage(ierr, nullptr, &specific);
  throw std::invalid_argument(specific && *specific ? specific : "PETSc error " + std::to_string(static_cast<int>(ierr)));
}

} // namespace rcfd
