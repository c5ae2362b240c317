#include "rcfd/swap_operator.hpp"
#include "base/petsc_compat.hpp"

#include <algorithm>

namespace rcfd {

SwapOperator::SwapOperator() = default;
SwapOperator::~SwapOperator() = default;

SwapOperator::FaceChoice SwapOperator::swapFaces(const RunContext &) const { return {}; }

PetscErrorCode SwapOperator::setUpSwap(const RunContext &) { return PETSC_SUCCESS; }

PetscErrorCode SwapOperator::setUp(const RunContext &ctx) {
  PetscFunctionBeginUser;
  db = &ctx.db;
  comm = ctx.db.layout().comm();
  nf = ctx.fractions.size();
  rho = ctx.solidDensity;
  const FaceChoice choice = swapFaces(ctx);
  faces = std::make_unique<FaceExchange>();
  PetscCall(faces->setUp(ctx.db, nf, choice.direction, choice.minShare));
  ns = ctx.numScalars;
  amountFaces.reset();
  if (ns > 0) { // the same faces in the same order, so the same gathered cells
    amountFaces = std::make_unique<FaceExchange>();
    PetscCall(amountFaces->setUp(ctx.db, nf * ns, choice.direction, choice.minShare));
  }
  PetscCall(setUpSwap(ctx));
  PetscFunctionReturn(PETSC_SUCCESS);
}

void SwapOperator::countStep(int n) {
  ++steps;
  substeps += n;
  mostSubsteps = std::max(mostSubsteps, n);
}

} // namespace rcfd
