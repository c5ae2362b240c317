#include "rcfd/mass_ledger.hpp"
#include "base/checked_options.hpp"
#include "base/petsc_compat.hpp"

#include <algorithm>
#include <cmath>

namespace rcfd {

PetscErrorCode MassLedger::setFromOptions(MPI_Comm comm) {
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, nullptr, "Mass ledger", "rcfd");
  PetscCall(checkedInt(PetscOptionsObject, "-mass_check_every",
                       "Steps between checks of every fraction's total mass (0: never)",
                       &checkEvery, 0, PETSC_MAX_INT));
  PetscCall(checkedReal(PetscOptionsObject, "-mass_leak_tolerance",
                        "Relative change of a fraction's mass treated as a leak, not round-off",
                        &leakTolerance, kPositive));
  PetscOptionsEnd();
  PetscCheck(checkEvery >= 0, comm, PETSC_ERR_USER_INPUT, "-mass_check_every must be >= 0");
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode MassLedger::start(const FractionState &state) {
  PetscFunctionBeginUser;
  PetscCall(state.totals(&totals));
  lastStep = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode MassLedger::check(long step, FractionState &state, bool endOfRun,
                                 const std::vector<double> *added) {
  PetscFunctionBeginUser;
  const bool regular = checkEvery > 0 && step % checkEvery == 0;
  if (checkEvery == 0 || (!regular && !endOfRun)) PetscFunctionReturn(PETSC_SUCCESS);
  std::vector<double> now;
  PetscCall(state.totals(&now));
  const int nf = state.numFractions();
  const MPI_Comm comm = PetscObjectComm((PetscObject)state.masses()); // the totals are global
  std::vector<double> expected = totals;
  double bed = 0.0; // the scale of a fraction whose expected total is 0
  if (added && !added->empty()) {
    for (int i = 0; i < nf; ++i) expected[i] += (*added)[i];
    for (int i = 0; i < nf; ++i) bed += std::fabs(expected[i]);
  }
  std::vector<double> factor(nf, 1.0);
  for (int i = 0; i < nf; ++i) {
    if (expected[i] == 0.0) {
      PetscCheck(std::fabs(now[i]) <= leakTolerance * bed, comm, PETSC_ERR_PLIB,
                 "Fraction %d should have no mass but has %g kg after step %ld: an operator created mass", i,
                 now[i], step);
      continue;
    }
    const double change = now[i] / expected[i] - 1.0;
    // An operator that adds or removes mass on purpose says how much through
    // Operator::addedMass(), or returns false from conservesMass() and the
    // run then leaves the ledger off.
    PetscCheck(std::fabs(change) <= leakTolerance, comm, PETSC_ERR_PLIB,
               "Fraction %d changed its mass by %.3e (relative) between steps %ld and %ld, more "
               "than round-off (-mass_leak_tolerance %g): an operator is not mass-conserving "
               "(one that adds or removes mass on purpose must return false from conservesMass() "
               "and report it through addedMass())",
               i, change, lastStep, step, (double)leakTolerance);
    largest = std::fmax(largest, std::fabs(change));
    factor[i] = expected[i] / now[i];
  }
  if (!regular) PetscFunctionReturn(PETSC_SUCCESS); // verified only: see the header
  if (std::any_of(factor.begin(), factor.end(), [](double f) { return f != 1.0; })) {
    PetscScalar *m;
    PetscInt occupied;
    PetscCall(state.occupiedEnd(&occupied));
    PetscCall(VecGetArray(state.masses(), &m));
    for (PetscInt k = 0; k < occupied * nf; k += nf)
      for (int i = 0; i < nf; ++i) m[k + i] *= factor[i];
    PetscCall(VecRestoreArray(state.masses(), &m));
    PetscCall(state.setOccupiedEnd(occupied)); // an empty cell stays empty
  }
  lastStep = step;
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
