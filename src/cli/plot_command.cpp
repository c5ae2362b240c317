#include "cli/commands.hpp"
#include "base/petsc_compat.hpp"

#include "observable/cog_plot.hpp"
#include "base/collective.hpp"

namespace rcfd::cli {

// rcfd plot RUN/cog.csv [-o cog.png] [-title T]: the centre-of-gravity
// figures of a run, e.g. one made with -plot 0 or by an older rcfd.
PetscErrorCode plotCommand(MPI_Comm comm, const char *positional) {
  char csv[PETSC_MAX_PATH_LEN] = "", png[PETSC_MAX_PATH_LEN] = "", title[256] = "";
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscOptionsBegin(comm, nullptr, "rcfd plot: PNG figures of a cog.csv", "rcfd");
  PetscCall(PetscOptionsString("-csv", "cog.csv of a run (or give it as the first argument)", "", csv,
                               csv, sizeof csv, nullptr));
  PetscCall(PetscOptionsString("-o", "PNG file (default: next to the CSV)", "", png, png, sizeof png, nullptr));
  PetscCall(PetscOptionsString("-title", "Figure title (default: the CSV's path)", "", title, title,
                               sizeof title, nullptr));
  PetscOptionsEnd();
  if (helpRequested()) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(rejectUnusedOptions(comm, "plot"));
  const std::string in = positional ? positional : csv;
  PetscCheck(!in.empty(), comm, PETSC_ERR_USER_INPUT, "No CSV given: rcfd plot RUN/cog.csv");
  std::string out = png;
  if (out.empty()) out = in.substr(0, in.rfind('.')) + ".png";
  PetscCall(collectively(
      comm, [&] { if (rank == 0) plotCogCsv(in, out, title[0] ? title : in); }, PETSC_ERR_USER_INPUT));
  PetscCall(PetscPrintf(comm, "Wrote %s\n", out.c_str()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
