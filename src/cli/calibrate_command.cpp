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
  PetscCall(calibration.setUp());
  PetscCall(rejectUnusedOptions(comm, "calibrate")); // every option has been read by now
  PetscCall(calibration.solve());
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
