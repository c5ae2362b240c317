#include "cli/figures.hpp"
#include "base/petsc_compat.hpp"

#include "base/collective.hpp"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char **environ;

namespace rcfd::cli {
namespace fs = std::filesystem;
namespace {

std::string environment(const char *name) {
  const char *value = std::getenv(name);
  return value ? value : "";
}

// Debian's python3 is the one with python3-matplotlib; a python3 earlier on
// the PATH (pyenv, conda) often lacks it.
std::string pythonInterpreter() {
  if (const std::string chosen = environment("RCFD_PYTHON"); !chosen.empty()) return chosen;
  if (access("/usr/bin/python3", X_OK) == 0) return "/usr/bin/python3";
  return "python3";
}

fs::path figuresDirectory() {
  if (const std::string chosen = environment("RCFD_FIGURES_DIR"); !chosen.empty()) return chosen;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path installed = (exe.parent_path() / ".." / "share" / "rcfd" / "figures").lexically_normal();
    if (fs::is_directory(installed, ec)) return installed;
  }
  return RCFD_SOURCE_FIGURES_DIR; // the build tree's program
}

/// Runs argv (searching the PATH for argv[0]) and waits; its output goes
/// where ours does, or nowhere when quiet.  The exit status, or -1 when it
/// could not start or was killed.
int runProgram(const std::vector<std::string> &argv, bool quiet) {
  std::vector<char *> pointers;
  for (const auto &a : argv) pointers.push_back(const_cast<char *>(a.c_str()));
  pointers.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (quiet) {
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  }
  std::fflush(nullptr); // our earlier lines first
  pid_t pid;
  const int started = posix_spawnp(&pid, pointers[0], &actions, nullptr, pointers.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (started != 0) return -1;
  int status = 0;
  pid_t waited;
  while ((waited = waitpid(pid, &status, 0)) < 0 && errno == EINTR) {
  }
  if (waited < 0 || !WIFEXITED(status)) return -1;
  return WEXITSTATUS(status);
}

/// Asked once per process: figures are optional, so their absence is said
/// once rather than at every figure.
bool matplotlibAvailable() {
  static const bool available = [] {
    const bool yes = runProgram({pythonInterpreter(), "-c", "import matplotlib, numpy"}, true) == 0;
    if (!yes)
      std::printf("figures skipped: python3 with matplotlib not found (every number is still in the CSV files)\n");
    return yes;
  }();
  return available;
}

std::string shellWord(const std::string &word) {
  if (!word.empty() && word.find_first_of(" \t'\"$\\()*?;&|<>") == std::string::npos) return word;
  std::string quoted = "'";
  for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

/// Empty on success, else why the figure was not drawn.
std::string runScript(const std::string &script, const std::vector<std::string> &args) {
  if (!matplotlibAvailable()) return "";
  const fs::path path = figuresDirectory() / script;
  if (!fs::is_regular_file(path))
    return "the figure script '" + path.string() +
           "' does not exist (set RCFD_FIGURES_DIR to the folder of rcfd's figure scripts)";
  std::vector<std::string> argv{pythonInterpreter(), "-B", path.string()}; // -B: no __pycache__ among the scripts
  argv.insert(argv.end(), args.begin(), args.end());
  const int status = runProgram(argv, false);
  if (status == 0) return "";
  std::string command;
  for (const auto &a : argv) command += (command.empty() ? "" : " ") + shellWord(a);
  return "the figure script " + script + " failed" +
         (status > 0 ? " with exit status " + std::to_string(status) : std::string()) + " (its message is above): " +
         command + "; the numbers are already in the CSV files";
}

} // namespace

bool figuresByDefault() { return environment("RCFD_PLOT") != "0"; }

PetscErrorCode drawFigure(MPI_Comm comm, const std::string &script, const std::vector<std::string> &args) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  const std::string why = rank == 0 ? runScript(script, args) : "";
  PetscCall(agreeOnFailure(comm, !why.empty(), why, PETSC_ERR_LIB));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode drawCogFigures(MPI_Comm comm, const std::string &csv, const std::string &png,
                              const std::string &title) {
  PetscFunctionBeginUser;
  const std::string stem = fs::path(png).replace_extension().string();
  PetscCall(drawFigure(comm, "cog.py", {csv, "-o", png, "--title", title}));
  PetscCall(drawFigure(comm, "delta_z.py", {csv, "-o", stem + "-delta.png", "--title", title}));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
