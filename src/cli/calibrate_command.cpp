// rcfd calibrate: the drift coefficient k_d that best reproduces a
// reference's segregation curve, through the public rcfd::Calibration
// (include/rcfd/study.hpp; the search in src/analysis/calibration.hpp).
#include "cli/commands.hpp"
#include "base/petsc_compat.hpp"

#include "rcfd/plugin.hpp"
#include "rcfd/run.hpp"
#include "rcfd/study.hpp"

namespace rcfd::cli {

PetscErrorCode calibrateCommand(MPI_Comm comm) {
  PetscFunctionBeginUser;
  Registries registries = Registries::withBuiltins();
  PetscCall(loadPlugins(comm, &registries)); // -plugin, $RCFD_PLUGINS
  Calibration calibration(comm, registries);
  PetscCall(calibration.setFromOptions());
  if (helpRequested()) { // list the run's options too; without -db the run stops early, never mind
    Run run(comm, registries);
    run.setDefaultOutputDirectory("rcfd-calibrate");
    (void)run.setFromOptions();
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscBool live = PETSC_FALSE; // the calibration's runs replay one database many times: nothing to follow
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-live", &live));
  PetscCheck(!live, comm, PETSC_ERR_USER_INPUT,
             "-live is for rcfd run: a calibration replays its runs many times and follows no file (docs/live.md)");
  PetscCall(calibration.setUp());
  PetscCall(rejectUnusedOptions(comm, "calibrate")); // every option has been read by now
  PetscCall(calibration.solve());
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
