// A study as a short program (include/rcfd/study.hpp): fit k_d of the drift's
// size law against a reference's segregation curve, run a small ensemble of
// stitched paths with the fitted law, and score the ensemble's mean curve
// against the same reference.  Everything is read from the options rcfd
// calibrate and rcfd run read; the study adds -study_members N (default 3).
//
//   mpiexec -n 2 ./study -db bed.h5 -reference ref/cog.csv -score_window 0.1,0.3 \
//       -calibrate_kd_range 1e4,1e7 -calibrate_scan 7 -fields 0 -output_dir out
#include <rcfd/plugin.hpp>
#include <rcfd/study.hpp>

#include <cmath>
#include <cstdio>

namespace {

PetscErrorCode study() {
  const MPI_Comm comm = PETSC_COMM_WORLD;
  const PetscViewer out = PETSC_VIEWER_STDOUT_(comm);
  PetscInt members = 3, nwindow = 2;
  PetscReal window[2] = {0.5, 1.5};
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-study_members", &members, nullptr));
  PetscCall(PetscOptionsGetRealArray(nullptr, nullptr, "-score_window", window, &nwindow, nullptr));
  // The program's registries: the built-ins (add your own operators, laws, paths here).
  const rcfd::Registries registries = rcfd::Registries::withBuiltins();

  // 1. k_d of each -calibrate_models law (default B) against -reference.
  rcfd::Calibration calibration(comm, registries);
  PetscCall(calibration.setFromOptions());
  PetscCall(calibration.setUp());
  PetscCall(calibration.solve());
  PetscCall(calibration.view(out));
  const rcfd::Calibration::Result &fit = calibration.results().front();
  PetscCall(PetscPrintf(comm, "study: fitted k_d = %.4g %s\n", fit.kd, fit.unit.c_str()));

  // 2. The ensemble's members run the fitted law along random stitched paths
  // (the path is an option the members read; the law is handed over typed).
  PetscCall(PetscOptionsSetValue(nullptr, "-path_type", "random"));
  rcfd::Ensemble ensemble(comm, registries);
  PetscCall(ensemble.setMembers(static_cast<int>(members)));
  PetscCall(ensemble.setDriftLaw(fit)); // its size law and k_d, as the calibration's replays ran them
  PetscCall(ensemble.setFromOptions());
  PetscCall(ensemble.setUp());
  PetscCall(ensemble.solve());
  PetscCall(ensemble.view(out));
  for (int k = 0; k < ensemble.members(); ++k) {
    const double before = ensemble.initialMasses()[k], after = ensemble.finalMasses()[k];
    PetscCall(PetscPrintf(comm, "study: member %d mass %.17g kg -> %.17g kg, relative change %.3g\n", k, before,
                          after, std::fabs(after - before) / before));
  }

  // 3. The ensemble's mean Delta z(t) against the reference, over the calibration's window.
  char reference[PETSC_MAX_PATH_LEN] = "";
  PetscCall(PetscOptionsGetString(nullptr, nullptr, "-reference", reference, sizeof reference, nullptr));
  rcfd::Comparison comparison(comm);
  PetscCall(comparison.setReference(reference));
  PetscCall(comparison.addRun(ensemble.summaryFile(), "ensemble"));
  PetscCall(comparison.setWindows({window[0], window[1]}));
  PetscCall(comparison.solve());
  PetscCall(comparison.view(out));
  for (const rcfd::Comparison::Score &s : comparison.scores())
    PetscCall(PetscPrintf(comm, "study: %s %s Delta_seg %.3f %% RMS/peak %.4f\n", s.run.c_str(), s.curve.c_str(),
                          s.agreement.segregationError, s.agreement.rmsRelative));
  PetscFunctionReturn(0);
}

} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, "A calibration, an ensemble and a comparison as one program"));
  PetscCall(study());
  PetscCall(PetscFinalize());
  return 0;
}
