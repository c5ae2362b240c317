#include "cli/answer_figures.hpp"
#include "cli/commands.hpp"
#include "base/checked_options.hpp"
#include "base/petsc_compat.hpp"
#include "cli/figures.hpp"
#include "markov/markov_monitor.hpp"

#include "rcfd/study.hpp"
#include "base/collective.hpp"
#include "rcfd/plugin.hpp"
#include "rcfd/run.hpp"

#include <memory>
#include <string>
#include <vector>

namespace rcfd::cli {
namespace {

// An ensemble (rcfd::Ensemble, include/rcfd/study.hpp) set from the options, then solved, then its figure.
PetscErrorCode runEnsemble(MPI_Comm comm, Ensemble &ensemble, bool plot) {
  PetscFunctionBeginUser;
  PetscCall(ensemble.setUp());
  PetscCall(ensemble.solve());
  const std::string dir = ensemble.outputDirectory();
  if (plot) PetscCall(drawCogFigures(comm, ensemble.summaryFile(), dir + "/ensemble.png", dir));
  PetscCall(PetscPrintf(comm, "Ensemble of %d paths: %s/ensemble.csv%s\n", ensemble.members(), dir.c_str(),
                        plot ? ", ensemble.png" : ""));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The program's monitors from rooms above the run (src/markov), which the
// run's own registry cannot name.
PetscErrorCode addProgramMonitors(Registries *registries) {
  PetscFunctionBeginUser;
  PetscCall(registries->monitors.add("markov", [] { return std::make_unique<MarkovMonitor>(); },
                                     "the zones' time per visit and away from the database as a Markov chain "
                                     "(markov.csv; docs/markov.md)"));
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
  PetscCall(addProgramMonitors(&registries));
  PetscCall(loadPlugins(comm, &registries));
  PetscCall(viewExtensions(comm, registries));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode runCommand(MPI_Comm comm) {
  PetscInt members = 1;
  PetscBool plot = figuresByDefault() ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionBeginUser;
  Registries registry = Registries::withBuiltins();
  PetscCall(addProgramMonitors(&registry));
  PetscCall(loadPlugins(comm, &registry)); // -plugin, $RCFD_PLUGINS: before the options name what they add
  Run run(comm, registry);
  PetscCall(run.setFromOptions());
  char reference[PETSC_MAX_PATH_LEN] = "";
  PetscOptionsBegin(comm, nullptr, "rcfd run: ensembles and figures", "rcfd");
  PetscCall(checkedInt(PetscOptionsObject, "-ensemble",
                       "Run this many stitched paths (seeds path_seed, path_seed+1, ...)",
                       &members, 1, 100000));
  PetscCall(PetscOptionsBool("-plot", "Draw figures of the results at the end (default: $RCFD_PLOT, else true)", "", plot, &plot, nullptr));
  PetscCall(PetscOptionsString("-plot_reference", "Directory of rcfd reference whose profiles.csv and halves.csv "
                               "the figures show alongside the run's", "", reference, reference, sizeof reference, nullptr));
  PetscOptionsEnd();
  if (helpRequested()) { // what can be chosen by name, plugins' additions included
    PetscCall(viewExtensions(comm, registry));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCheck(members >= 1, comm, PETSC_ERR_USER_INPUT, "-ensemble must be at least 1");
  PetscCheck(members == 1 || !run.followsLive(), comm, PETSC_ERR_USER_INPUT,
             "-ensemble %d with -live: an ensemble's members run one after the other and cannot each follow the "
             "live file; follow it with one run (docs/live.md)", static_cast<int>(members));
  std::unique_ptr<Ensemble> ensemble; // `run` only read the options; the ensemble's members read them again
  if (members > 1) {
    ensemble = std::make_unique<Ensemble>(comm, registry);
    PetscCall(ensemble->setMembers(static_cast<int>(members)));
    PetscCall(ensemble->setFromOptions()); // -ensemble_view
  }
  PetscCall(rejectUnusedOptions(comm, "run"));
  if (ensemble) {
    PetscCall(runEnsemble(comm, *ensemble, plot));
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
