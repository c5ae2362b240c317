#include "markov/wrap_carry.hpp"
#include "base/petsc_compat.hpp"

namespace rcfd {

PetscErrorCode WrapCarry::setFromOptions(MPI_Comm comm) {
  PetscFunctionBeginUser;
  carry_.setOptionsPrefix("carry_");
  PetscCall(carry_.setFromOptions(comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode WrapCarry::setUp(const FrameChain &chain, double solidDensity) {
  PetscFunctionBeginUser;
  frames_ = chain.numFrames();
  // The carry reads no diameter; one class holds the whole bed.
  PetscCall(FractionSet::create({1e-3}, {1.0}, &one_));
  PetscCall(OperatorStep::setUp(chain, carry_, one_, solidDensity));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
