#include "cli/commands.hpp"
#include "base/petsc_compat.hpp"

#include "cli/figures.hpp"

#include <filesystem>

namespace rcfd::cli {

// rcfd plot RUN/cog.csv [-o cog.png] [-title T]: the centre-of-gravity
// figures of a run (or of an ensemble's ensemble.csv, with bands), e.g. one
// made with -plot 0, on another machine or by an older rcfd.
PetscErrorCode plotCommand(MPI_Comm comm, const char *positional) {
  char csv[PETSC_MAX_PATH_LEN] = "", png[PETSC_MAX_PATH_LEN] = "", title[256] = "";
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, nullptr, "rcfd plot: PNG figures of a cog.csv", "rcfd");
  PetscCall(PetscOptionsString("-csv", "cog.csv of a run (or give it as the first argument)", "", csv,
                               csv, sizeof csv, nullptr));
  PetscCall(PetscOptionsString("-o", "PNG file (default: next to the CSV); Delta z goes to its name with -delta.png",
                               "", png, png, sizeof png, nullptr));
  PetscCall(PetscOptionsString("-title", "Figure title (default: the CSV's path)", "", title, title,
                               sizeof title, nullptr));
  PetscOptionsEnd();
  if (helpRequested()) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(rejectUnusedOptions(comm, "plot"));
  const std::string in = positional ? positional : csv;
  PetscCheck(!in.empty(), comm, PETSC_ERR_USER_INPUT, "No CSV given: rcfd plot RUN/cog.csv");
  PetscCheck(std::filesystem::is_regular_file(in), comm, PETSC_ERR_FILE_OPEN,
             "rcfd plot: cannot read the CSV file '%s'", in.c_str());
  std::string out = png;
  if (out.empty()) out = std::filesystem::path(in).replace_extension(".png").string();
  const std::string delta = std::filesystem::path(out).replace_extension().string() + "-delta.png";
  const auto start = std::filesystem::file_time_type::clock::now();
  PetscCall(drawCogFigures(comm, in, out, title[0] ? title : in));
  std::error_code ec; // no "Wrote" when the figures were skipped (PetscPrintf prints rank 0's)
  if (std::filesystem::exists(out, ec) && std::filesystem::last_write_time(out, ec) >= start)
    PetscCall(PetscPrintf(comm, "Wrote %s, %s\n", out.c_str(), delta.c_str()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
