// The subcommands of the rcfd program.  Each reads its own options, does its
// work collectively on PETSC_COMM_WORLD and returns a PETSc error code.
#pragma once

#include "rcfd/handle.hpp"

namespace rcfd::cli {

PetscErrorCode runCommand(MPI_Comm comm);
PetscErrorCode synthCommand(MPI_Comm comm);
PetscErrorCode infoCommand(MPI_Comm comm, const char *positional);
PetscErrorCode coarsenCommand(MPI_Comm comm, const char *positional);
PetscErrorCode buildCommand(MPI_Comm comm);
/// rcfd build -eulerian PATTERN (buildCommand hands over when -eulerian is given).
PetscErrorCode buildEulerianCommand(MPI_Comm comm);
PetscErrorCode exportEulerianCommand(MPI_Comm comm, const char *positional);
PetscErrorCode referenceCommand(MPI_Comm comm);
PetscErrorCode compareCommand(MPI_Comm comm);
PetscErrorCode calibrateCommand(MPI_Comm comm);
PetscErrorCode recurrenceCommand(MPI_Comm comm, const char *positional);
PetscErrorCode plotCommand(MPI_Comm comm, const char *positional);
/// rcfd markov DB.h5: the frames as the solid's Markov chain (docs/markov.md).
PetscErrorCode markovCommand(MPI_Comm comm, const char *positional);
/// `rcfd -help`: what can be chosen by name at every extension point, the
/// plugins' additions (-plugin, $RCFD_PLUGINS) included (run_command.cpp).
PetscErrorCode listExtensions(MPI_Comm comm);

/// A subcommand of the rcfd program.
struct Command {
  const char *name;
  bool positional; // takes a file as its first argument
  const char *summary, *example;
  PetscErrorCode (*run)(MPI_Comm comm, const char *positional);
};

/// Refuse options nobody read: a misspelt option must not silently fall back
/// to a default.  Call after every object has read its options.
PetscErrorCode rejectUnusedOptions(MPI_Comm comm, const char *command);
/// True when -help was given: commands then print their options and stop.
bool helpRequested();

} // namespace rcfd::cli
