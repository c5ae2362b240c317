#include "cli/answer_figures.hpp"
#include "cli/commands.hpp"
#include "base/checked_options.hpp"
#include "base/petsc_compat.hpp"
#include "cli/figures.hpp"

#include "analysis/ensemble.hpp"
#include "base/collective.hpp"
#include "rcfd/plugin.hpp"
#include "rcfd/run.hpp"

#include <string>
#include <vector>

namespace rcfd::cli {
namespace {

// An ensemble: the same case along stitched paths with seeds s, s+1, ...
// (s: -path_seed), sharing one loaded database; each member writes
// OUTPUT/member_k/cog.csv, and OUTPUT/ensemble.csv gives mean and spread.
// Every member reads the options itself; the setters then give it its own
// seed and directory and turn fields off.
PetscErrorCode runEnsemble(MPI_Comm comm, const Registries &registry, PetscInt members,
                           const std::string &outputDir, std::uint64_t seed, bool plot) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  std::vector<std::string> csvs;
  std::shared_ptr<Database> db;
  for (PetscInt k = 0; k < members; ++k) {
    const std::string dir = outputDir + "/member_" + std::to_string(k);
    Run member(comm, registry);
    if (db) member.useDatabase(db);
    PetscCall(member.setFromOptions());
    PetscCall(member.setPathSeed(seed + static_cast<std::uint64_t>(k)));
    member.setOutputDirectory(dir);
    member.setWriteFields(false);
    PetscCall(member.setUp());
    db = member.sharedDatabase();
    if (!member.quiet())
      PetscCall(PetscPrintf(comm, "Ensemble member %d of %d (path seed %llu)\n", (int)k + 1, (int)members,
                            (unsigned long long)(seed + k)));
    PetscCall(member.solve());
    csvs.push_back(dir + "/cog.csv");
  }
  PetscCall(collectively(comm, [&] {
    if (rank == 0) writeEnsembleSummary(csvs, outputDir + "/ensemble.csv");
  }));
  if (plot) PetscCall(drawCogFigures(comm, outputDir + "/ensemble.csv", outputDir + "/ensemble.png", outputDir));
  PetscCall(PetscPrintf(comm, "Ensemble of %d paths: %s/ensemble.csv%s\n", (int)members, outputDir.c_str(),
                        plot ? ", ensemble.png" : ""));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode viewExtensions(MPI_Comm comm, const Registries &registries) {
  PetscFunctionBeginUser;
  PetscCall(PetscPrintf(comm, "Registered by name (built-in and from plugins, docs/extending.md):\n"));
  PetscCall(registries.view(PETSC_VIEWER_STDOUT_(comm)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

PetscErrorCode listExtensions(MPI_Comm comm) {
  PetscFunctionBeginUser;
  Registries registries = Registries::withBuiltins();
  PetscCall(loadPlugins(comm, &registries));
  PetscCall(viewExtensions(comm, registries));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode runCommand(MPI_Comm comm) {
  PetscInt members = 1;
  PetscBool plot = PETSC_TRUE;
  PetscFunctionBeginUser;
  Registries registry = Registries::withBuiltins();
  PetscCall(loadPlugins(comm, &registry)); // -plugin, $RCFD_PLUGINS: before the options name what they add
  Run run(comm, registry);
  PetscCall(run.setFromOptions());
  char reference[PETSC_MAX_PATH_LEN] = "";
  PetscOptionsBegin(comm, nullptr, "rcfd run: ensembles and figures", "rcfd");
  PetscCall(checkedInt(PetscOptionsObject, "-ensemble",
                       "Run this many stitched paths (seeds path_seed, path_seed+1, ...)",
                       &members, 1, 100000));
  PetscCall(PetscOptionsBool("-plot", "Draw figures of the results at the end", "", plot, &plot, nullptr));
  PetscCall(PetscOptionsString("-plot_reference", "Directory of rcfd reference whose profiles.csv and halves.csv "
                               "the figures show alongside the run's", "", reference, reference, sizeof reference, nullptr));
  PetscOptionsEnd();
  if (helpRequested()) { // what can be chosen by name, plugins' additions included
    PetscCall(viewExtensions(comm, registry));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(rejectUnusedOptions(comm, "run"));
  PetscCheck(members >= 1, comm, PETSC_ERR_USER_INPUT, "-ensemble must be at least 1");
  if (members > 1) { // `run` only read the options: its path's seed is the first member's
    PetscCheck(!run.switchesDatabases(), comm, PETSC_ERR_USER_INPUT,
               "-ensemble %d with several databases in -db: an ensemble's members share one loaded database, and "
               "a run on several reads and drops them as it switches; run each member as its own rcfd run on the "
               "set with -path_seed s, s+1, ... (or the ensemble on one database of the set)", (int)members);
    PetscCheck(run.path().hasSeed(), comm, PETSC_ERR_USER_INPUT,
               "-ensemble %d needs a stochastic -path_type (random, markov or quarter), not %s",
               (int)members, run.path().type().c_str());
    PetscCall(runEnsemble(comm, registry, members, run.outputDirectory(), run.path().seed(), plot));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(run.setUp());
  PetscCall(run.solve());
  const std::string dir = run.outputDirectory();
  if (plot) PetscCall(drawCogFigures(comm, dir + "/cog.csv", dir + "/cog.png", dir));
  if (plot) PetscCall(drawAnswerFigures(comm, dir, reference));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
