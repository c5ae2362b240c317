// rcfd: command-line front end.  `rcfd <command> [PETSc options]`.
#include "cli/commands.hpp"

#include <cstdio>
#include <cstring>
#include <string>

namespace {

const char usage[] =
    "rcfd: transport-based recurrence CFD for segregating particle fractions in fluidized beds\n"
    "\n"
    "usage: rcfd <command> [options]     (options are PETSc options; -options_file FILE reads a case)\n"
    "\n"
    "commands:\n"
    "  run     propagate size fractions on a database: rcfd run -options_file cases/NAME/case.yaml\n"
    "  synth   write the embedded default database (a kinematic bubbling bed): rcfd synth -o FILE\n"
    "  info    print what a database holds: rcfd info FILE\n"
    "\n"
    "`rcfd <command> -help` lists the command's options with their defaults.\n";

bool isHelp(const char *a) {
  return !std::strcmp(a, "-h") || !std::strcmp(a, "--help") || !std::strcmp(a, "help");
}

} // namespace

int main(int argc, char **argv) {
  if (argc < 2 || isHelp(argv[1])) {
    std::fputs(usage, argc < 2 ? stderr : stdout);
    return argc < 2 ? 2 : 0;
  }
  const std::string command = argv[1];
  if (command != "run" && command != "synth" && command != "info") {
    std::fprintf(stderr, "rcfd: unknown command '%s'; expected run, synth or info (rcfd --help)\n",
                 command.c_str());
    return 2;
  }
  // PETSc sees the command as the program name; `info` takes one positional
  // argument (the file) which PETSc must not see as an option.
  int pargc = argc - 1;
  char **pargv = argv + 1;
  const char *positional = nullptr;
  if (command == "info" && pargc > 1 && pargv[1][0] != '-') {
    positional = pargv[1];
    for (int i = 1; i + 1 < pargc; ++i) pargv[i] = pargv[i + 1];
    --pargc;
  }
  if (PetscInitialize(&pargc, &pargv, nullptr, usage) != 0) return 1;
  // Errors travel up as codes; this program prints one sentence for the user
  // instead of PETSc's traceback (-rcfd_traceback restores it for debugging).
  PetscBool traceback = PETSC_FALSE;
  PetscOptionsGetBool(nullptr, nullptr, "-rcfd_traceback", &traceback, nullptr);
  if (!traceback) PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);

  PetscErrorCode ierr = 0;
  if (command == "run") ierr = rcfd::cli::runCommand(PETSC_COMM_WORLD);
  else if (command == "synth") ierr = rcfd::cli::synthCommand(PETSC_COMM_WORLD);
  else ierr = rcfd::cli::infoCommand(PETSC_COMM_WORLD, positional);

  if (ierr) {
    const char *generic = nullptr;
    char *specific = nullptr;
    PetscErrorMessage(ierr, &generic, &specific);
    int rank = 0;
    MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
    if (rank == 0)
      std::fprintf(stderr, "rcfd %s: error: %s\n", command.c_str(),
                   specific && *specific ? specific : (generic ? generic : "unknown error"));
  }
  PetscFinalize();
  return ierr ? 1 : 0;
}
