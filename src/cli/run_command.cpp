#include "cli/commands.hpp"
#include "base/petsc_compat.hpp"

#include "observable/cog_plot.hpp"
#include "rcfd/run.hpp"
#include "base/collective.hpp"

#include <string>
#include <vector>

namespace rcfd::cli {
namespace {

PetscErrorCode setOption(const std::string &name, const std::string &value) {
  return PetscOptionsSetValue(nullptr, name.c_str(), value.c_str());
}

// An ensemble: the same case along stitched paths with seeds s, s+1, ...,
// sharing one loaded database; each member writes OUTPUT/member_k/cog.csv,
// and OUTPUT/ensemble.csv and ensemble.png give mean and spread.
PetscErrorCode runEnsemble(MPI_Comm comm, const OperatorRegistry &registry, PetscInt members,
                           const std::string &outputDir, PetscInt seed) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  std::vector<std::string> csvs;
  std::shared_ptr<Database> db;
  for (PetscInt k = 0; k < members; ++k) {
    const std::string dir = outputDir + "/member_" + std::to_string(k);
    PetscCall(setOption("-path_seed", std::to_string(seed + k)));
    PetscCall(setOption("-output_dir", dir));
    PetscCall(setOption("-fields", "0"));
    PetscCall(setOption("-plot", "0"));
    Run member(comm, registry);
    if (db) member.useDatabase(db);
    PetscCall(member.setFromOptions());
    PetscCall(member.setUp());
    db = member.sharedDatabase();
    PetscCall(PetscPrintf(comm, "Ensemble member %d of %d (path seed %d)\n", (int)k + 1, (int)members,
                          (int)(seed + k)));
    PetscCall(member.solve());
    csvs.push_back(dir + "/cog.csv");
  }
  PetscCall(collectively(comm, [&] {
    if (rank == 0)
      summariseEnsemble(csvs, outputDir + "/ensemble.csv", outputDir + "/ensemble.png", outputDir);
  }));
  PetscCall(PetscPrintf(comm, "Ensemble of %d paths: %s/ensemble.csv, ensemble.png\n", (int)members,
                        outputDir.c_str()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

PetscErrorCode runCommand(MPI_Comm comm) {
  PetscBool view = PETSC_FALSE;
  PetscInt members = 1, seed = 1;
  char dir[PETSC_MAX_PATH_LEN] = "rcfd-output";
  PetscFunctionBeginUser;
  const OperatorRegistry registry = OperatorRegistry::withBuiltins();
  Run run(comm, registry);
  PetscCall(run.setFromOptions());
  PetscOptionsBegin(comm, nullptr, "rcfd run: ensembles", "rcfd");
  PetscCall(PetscOptionsInt("-ensemble", "Run this many stitched paths (seeds path_seed, path_seed+1, ...)",
                            "", members, &members, nullptr));
  PetscOptionsEnd();
  PetscCall(PetscOptionsGetBool(nullptr, nullptr, "-run_view", &view, nullptr));
  PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-path_seed", &seed, nullptr));
  PetscCall(PetscOptionsGetString(nullptr, nullptr, "-output_dir", dir, sizeof dir, nullptr));
  if (helpRequested()) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(rejectUnusedOptions(comm, "run"));
  PetscCheck(members >= 1, comm, PETSC_ERR_USER_INPUT, "-ensemble must be at least 1");
  if (members > 1) {
    PetscCall(runEnsemble(comm, registry, members, dir, seed)); // `run` only read the options
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(run.setUp());
  if (view) PetscCall(run.view(PETSC_VIEWER_STDOUT_(comm)));
  PetscCall(run.solve());
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
