// rcfd::Ensemble::setDriftLaw: members given a size law and k_d typed run
// exactly what -drift_size_law and -drift_kd give (the same ensemble.csv,
// byte for byte), over options that say otherwise, and keep their mass to
// 1e-12; an unknown law, a k_d that is not positive and a -pipeline without
// drift are refused in one sentence.  Runs at 1 and 2 ranks.
// usage: test_ensemble_drift_law OUTPUT_DIR -db SMALL.h5 [run options]
#include "check.hpp"
#include "scoped_options.hpp"
#include "state_access.hpp"
#include "base/petsc_compat.hpp"
#include "rcfd/plugin.hpp"
#include "rcfd/study.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

using namespace rcfd;

namespace {

std::string contents(const std::string &path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The specific message of the last PETSc error.
std::string message(PetscErrorCode ierr) {
  char *why = nullptr;
  PetscErrorMessage(ierr, nullptr, &why);
  return why ? why : "";
}

/// Two members on random paths into `directory`, the drift law set typed
/// when `law` is not empty; every member's mass kept to 1e-12.
PetscErrorCode runEnsemble(const Registries &registries, const std::string &directory, const std::string &law,
                           double kd) {
  PetscFunctionBeginUser;
  Ensemble ensemble(PETSC_COMM_WORLD, registries);
  PetscCall(ensemble.setMembers(2));
  if (!law.empty()) PetscCall(ensemble.setDriftLaw(law, kd));
  PetscCall(ensemble.setFromOptions());
  PetscCall(ensemble.setUp());
  PetscCall(ensemble.solve());
  RCFD_CHECK(ensemble.outputDirectory() == directory);
  for (int k = 0; k < ensemble.members(); ++k) {
    const double before = ensemble.initialMasses()[k], after = ensemble.finalMasses()[k];
    RCFD_CHECK(before > 0 && std::fabs(after - before) <= 1e-12 * before);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

int check(const std::string &dir) {
  const Registries registries = Registries::withBuiltins();
  PetscMPIInt rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  const std::string common = " -path_type random -quiet -output_dir ";
  {
    ScopedOptions options("-drift_size_law B -drift_kd 123456.789" + common + dir + "/options");
    RCFD_CHECK(runEnsemble(registries, dir + "/options", "", 0.0) == 0);
  }
  {
    // Options naming another law and k_d: the typed law wins.
    ScopedOptions options("-drift_size_law A -drift_kd 5" + common + dir + "/typed");
    RCFD_CHECK(runEnsemble(registries, dir + "/typed", "B", 123456.789) == 0);
  }
  {
    ScopedOptions options("-drift_size_law A -drift_kd 5" + common + dir + "/untouched");
    RCFD_CHECK(runEnsemble(registries, dir + "/untouched", "", 0.0) == 0);
  }
  MPI_Barrier(PETSC_COMM_WORLD);
  if (rank == 0) {
    const std::string byOptions = contents(dir + "/options/ensemble.csv");
    RCFD_CHECK(!byOptions.empty() && byOptions == contents(dir + "/typed/ensemble.csv"));
    RCFD_CHECK(byOptions != contents(dir + "/untouched/ensemble.csv")); // the law matters here
  }

  // Refusals, each in one sentence.
  Ensemble ensemble(PETSC_COMM_WORLD, registries);
  PetscErrorCode ierr = ensemble.setDriftLaw("nope", 1e5);
  RCFD_CHECK(ierr == PETSC_ERR_USER_INPUT &&
             message(ierr).rfind("-drift_size_law: unknown size law 'nope'; known size laws: A, B,", 0) == 0);
  ierr = ensemble.setDriftLaw("B", 0.0);
  RCFD_CHECK(ierr == PETSC_ERR_ARG_OUTOFRANGE &&
             message(ierr) == "Ensemble::setDriftLaw: k_d of the size law B must be positive and finite, not 0");
  RCFD_CHECK(ensemble.setDriftLaw("B", NAN) == PETSC_ERR_ARG_OUTOFRANGE);
  {
    ScopedOptions options("-pipeline shift,carry" + common + dir + "/nodrift");
    RCFD_CHECK(ensemble.setDriftLaw("B", 1e5) == 0 && ensemble.setFromOptions() == 0);
    ierr = ensemble.setUp();
    RCFD_CHECK(ierr == PETSC_ERR_USER_INPUT &&
               message(ierr) == "Ensemble::setDriftLaw(B, 100000): -pipeline has no drift operator to run it (add drift)");
  }
  return 0;
}

} // namespace

int main(int argc, char **argv) {
  return rcfd::test::rankTestMain(argc, argv, "ensemble_drift_law", check);
}
