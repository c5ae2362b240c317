// rcfd: command-line front end.  `rcfd <command> [FILE] [PETSc options]`.
#include "cli/argument_check.hpp"
#include "cli/commands.hpp"

#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace {

using rcfd::cli::Command;

// Every subcommand: name, whether it takes a file as first argument, what it
// does and how it is called (for the usage text), and the function.
const Command commands[] = {
    {"run", false, "propagate size fractions on a database",
     "rcfd run -options_file cases/NAME/case.yaml",
     [](MPI_Comm c, const char *) { return rcfd::cli::runCommand(c); }},
    {"synth", false, "write the embedded default database (a kinematic bubbling bed)",
     "rcfd synth -o FILE", [](MPI_Comm c, const char *) { return rcfd::cli::synthCommand(c); }},
    {"info", true, "print what a database holds", "rcfd info FILE", rcfd::cli::infoCommand},
    {"coarsen", true, "an exactly coarsened copy of a database (space and time)",
     "rcfd coarsen FILE -factor 2,1,2 [-time_factor 2] -o OUT", rcfd::cli::coarsenCommand},
    {"recurrence", true, "compute, store and draw the recurrence matrix of a database",
     "rcfd recurrence FILE", rcfd::cli::recurrenceCommand},
    {"markov", true, "the frames as the solid's Markov chain: mixing, relaxation, zone visits",
     "rcfd markov FILE [-zones spray -zone_spray_layers 20,30]", rcfd::cli::markovCommand},
    {"plot", true, "PNG figures of a run's cog.csv", "rcfd plot RUN/cog.csv", rcfd::cli::plotCommand},
    {"build", false, "a database from DEM particle snapshots (or Eulerian frames: -eulerian)",
     "rcfd build -dumps \"DIR/dump.*.gz\" -times DIR/times.txt -o FILE",
     [](MPI_Comm c, const char *) { return rcfd::cli::buildCommand(c); }},
    {"export-eulerian", true, "write a database's frames as Eulerian ASCII frames",
     "rcfd export-eulerian FILE -o DIR", rcfd::cli::exportEulerianCommand},
    {"reference", false, "centres of gravity, profiles, halves from particle snapshots",
     "rcfd reference -dumps ... -o DIR",
     [](MPI_Comm c, const char *) { return rcfd::cli::referenceCommand(c); }},
    {"compare", false, "score runs against a reference (delta z, d32, profiles, halves); database distance",
     "rcfd compare -reference REF/cog.csv -rcfd RUN/cog.csv -score_window 0.5,1.5,1.5,2.5",
     [](MPI_Comm c, const char *) { return rcfd::cli::compareCommand(c); }},
    {"calibrate", false, "fit the drift coefficient k_d to a reference",
     "rcfd calibrate -reference REF/cog.csv -db DB ...",
     [](MPI_Comm c, const char *) { return rcfd::cli::calibrateCommand(c); }},
};

std::string usage() {
  std::string u = "rcfd: transport-based recurrence CFD for segregating particle fractions in fluidized beds\n\n"
                  "usage: rcfd <command> [options]     (PETSc options; -options_file FILE reads a case)\n\n"
                  "commands:\n";
  for (const auto &c : commands) {
    char line[256];
    std::snprintf(line, sizeof line, "  %-16s %s\n  %-16s   %s\n", c.name, c.summary, "", c.example);
    u += line;
  }
  return u + "\n`rcfd <command> -help` lists the command's options with their defaults.\n";
}

bool isHelp(const char *a) {
  return !std::strcmp(a, "-h") || !std::strcmp(a, "--help") || !std::strcmp(a, "-help") ||
         !std::strcmp(a, "help");
}

// `rcfd -help [-plugin FILE]`: the usage, then every extension point's names
// (built-in and from plugins); PETSc sees only the -plugin option.
int helpWithExtensions(int argc, char **argv) {
  std::fputs(usage().c_str(), stdout);
  std::fflush(stdout);
  std::vector<char *> args{argv[0]};
  for (int i = 2; i + 1 < argc; ++i)
    if (!std::strcmp(argv[i], "-plugin")) args.insert(args.end(), {argv[i], argv[i + 1]});
  int pargc = static_cast<int>(args.size());
  args.push_back(nullptr); // argv ends with a null pointer, as MPI expects
  char **pargv = args.data();
  if (PetscInitialize(&pargc, &pargv, nullptr, nullptr) != 0) return 1;
  std::signal(SIGPIPE, SIG_DFL); // `rcfd -help | head` ends quietly
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  const PetscErrorCode ierr = rcfd::cli::listExtensions(PETSC_COMM_WORLD);
  if (ierr) {
    const char *generic = nullptr;
    char *specific = nullptr;
    PetscErrorMessage(ierr, &generic, &specific);
    std::fprintf(stderr, "rcfd: error: %s\n", specific && *specific ? specific : (generic ? generic : "unknown error"));
  }
  PetscFinalize();
  return ierr ? 1 : 0;
}

} // namespace

int main(int argc, char **argv) {
  if (argc < 2) {
    std::fputs(usage().c_str(), stderr);
    return 2;
  }
  if (isHelp(argv[1])) return helpWithExtensions(argc, argv);
  const Command *command = nullptr;
  for (const auto &c : commands)
    if (argv[1] == std::string(c.name)) command = &c;
  if (!command) {
    std::string names;
    for (const auto &c : commands) names += std::string(names.empty() ? "" : ", ") + c.name;
    std::fprintf(stderr, "rcfd: unknown command '%s'; expected one of %s (rcfd --help)\n", argv[1],
                 names.c_str());
    return 2;
  }
  // PETSc sees the command as the program name; a positional file argument
  // is taken out so that PETSc does not see it as an option.
  int pargc = argc - 1;
  char **pargv = argv + 1;
  const char *positional = nullptr;
  if (pargc > 1 && pargv[1][0] != '-') {
    if (!command->positional) {
      std::fprintf(stderr, "rcfd %s: error: unexpected argument '%s'; options start with '-' (rcfd %s -help)\n",
                   command->name, pargv[1], command->name);
      return 2;
    }
    positional = pargv[1];
    for (int i = 1; i + 1 < pargc; ++i) pargv[i] = pargv[i + 1];
    --pargc;
  }
  // PETSc would ignore a word that is neither an option nor its value.
  const std::string stray = rcfd::cli::strayArgument(pargc, pargv, 1);
  if (!stray.empty()) {
    std::fprintf(stderr,
                 "rcfd %s: error: unexpected argument '%s'; every value follows its option (an unquoted "
                 "pattern such as dump/*.gz expands to many words: quote it)\n",
                 command->name, stray.c_str());
    return 2;
  }
  const std::string badFile = rcfd::cli::checkOptionsFiles(pargc, pargv);
  if (!badFile.empty()) {
    std::fprintf(stderr, "rcfd %s: error: %s\n", command->name, badFile.c_str());
    return 2;
  }
  const std::string help = usage();
  if (PetscInitialize(&pargc, &pargv, nullptr, help.c_str()) != 0) return 1;
  // `rcfd info DB | head` ends quietly, as any command-line tool does, instead
  // of PETSc reporting the broken pipe as a crash.
  std::signal(SIGPIPE, SIG_DFL);
  // Errors travel up as codes; this program prints one sentence for the user
  // instead of PETSc's traceback (-rcfd_traceback restores it for debugging).
  PetscBool traceback = PETSC_FALSE;
  PetscOptionsGetBool(nullptr, nullptr, "-rcfd_traceback", &traceback, nullptr);
  if (!traceback) PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);

  const PetscErrorCode ierr = command->run(PETSC_COMM_WORLD, positional);
  if (ierr) {
    const char *generic = nullptr;
    char *specific = nullptr;
    PetscErrorMessage(ierr, &generic, &specific);
    int rank = 0;
    MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
    if (rank == 0)
      std::fprintf(stderr, "rcfd %s: error: %s\n", command->name,
                   specific && *specific ? specific : (generic ? generic : "unknown error"));
  }
  PetscFinalize();
  return ierr ? 1 : 0;
}
