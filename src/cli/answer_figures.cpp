#include "cli/answer_figures.hpp"
#include "base/petsc_compat.hpp"

#include "cli/figures.hpp"

#include <algorithm>
#include <filesystem>
#include <vector>

namespace fs = std::filesystem;

namespace rcfd::cli {

PetscErrorCode drawAnswerFigures(MPI_Comm comm, const std::string &dir, const std::string &referenceDir) {
  PetscFunctionBeginUser;
  // Every rank sees the output directory (the run wrote it from rank 0).
  const auto withReference = [&](std::vector<std::string> args, const std::string &name) {
    const std::string ref = referenceDir + "/" + name;
    // The legend names the reference by its directory (e.g. "reference", or "bi" for another run).
    const std::string label = fs::path(referenceDir).filename().string();
    if (!referenceDir.empty() && fs::exists(ref))
      args.insert(args.end(), {"--reference", ref, "--reference-label", label.empty() ? "reference" : label});
    return args;
  };
  if (fs::exists(dir + "/profiles.csv"))
    PetscCall(drawFigure(comm, "profiles.py",
                         withReference({dir + "/profiles.csv", "-o", dir + "/profiles.png"}, "profiles.csv")));
  if (fs::exists(dir + "/halves.csv"))
    PetscCall(drawFigure(comm, "halves.py", withReference({dir + "/halves.csv", "-o", dir + "/halves.png"}, "halves.csv")));
  if (fs::exists(dir + "/bottom.csv")) {
    char correlation[64] = "wen-yu";
    PetscCall(PetscOptionsGetString(nullptr, nullptr, "-umf_correlation", correlation, sizeof correlation, nullptr));
    PetscCall(drawFigure(comm, "bottom_layer.py",
                         {dir + "/bottom.csv", "-o", dir + "/bottom.png", "--correlation", correlation}));
  }
  if (fs::exists(dir + "/product.csv")) // a granulator: product and holdup size distributions over time
    PetscCall(drawFigure(comm, "granulation.py", {dir + "/product.csv", "-o", dir + "/granulation.png"}));
  std::vector<std::string> snapshots;
  for (const auto &entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("snapshot_", 0) == 0 && entry.path().extension() == ".csv") snapshots.push_back(entry.path().string());
  }
  std::sort(snapshots.begin(), snapshots.end()); // snapshots.py puts them in time order
  if (!snapshots.empty()) {
    snapshots.insert(snapshots.end(), {"-o", dir + "/snapshots.png"});
    PetscCall(drawFigure(comm, "snapshots.py", snapshots));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
