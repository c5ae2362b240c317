#include "markov/class_drift.hpp"
#include "base/petsc_compat.hpp"

#include "rcfd/run_context.hpp"

namespace rcfd {

PetscErrorCode ClassDrift::setFromOptions(MPI_Comm comm) {
  PetscFunctionBeginUser;
  drift_.setOptionsPrefix("drift_");
  PetscCall(drift_.setFromOptions(comm));
  PetscCall(PetscOptionsGetViewer(comm, nullptr, "drift_", "-view", viewer_.put(), nullptr, nullptr));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClassDrift::setUp(const FrameChain &chain, const FractionSet &fractions, double solidDensity) {
  PetscFunctionBeginUser;
  classes_ = fractions.size();
  moves_ = drift_.needed(RunContext{chain.database(), fractions, solidDensity});
  PetscCall(OperatorStep::setUp(chain, drift_, fractions, solidDensity));
  if (viewer_) PetscCall(drift_.view(viewer_));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
