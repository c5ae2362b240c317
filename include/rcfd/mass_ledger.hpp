// Keeps every fraction's total mass exactly where it started.
//
// Each shift or swap conserves mass in exact arithmetic, and in floating
// point every step changes a total by a few units of round-off that add up
// like a random walk (about 1e-12 relative after 10,000 steps of the default
// bed).  The ledger compares the totals with the initial ones every few
// steps: a change larger than the leak tolerance means an operator is not
// conservative and stops the run with an error; a smaller one is round-off
// and is removed by scaling the fraction by M0 / M.  So a leak is never
// hidden, and round-off never accumulates, however long the run.
// Operators that add or remove mass on purpose (feed, discharge, growth
// between classes) report how much (Operator::addedMass); the expected total
// is then M0 + added, checked the same way.
#pragma once

#include "rcfd/fractions.hpp"

#include <vector>

namespace rcfd {

class MassLedger {
public:
  /// Reads -mass_check_every (steps, 0: never) and -mass_leak_tolerance.
  PetscErrorCode setFromOptions(MPI_Comm comm);
  /// Record the reference totals.
  PetscErrorCode start(const FractionState &state);
  /// Collective.  Every `checkEvery` steps: refuse a leak, remove round-off.  With
  /// `endOfRun` it also refuses a leak at a step between two checks (the end of a
  /// run), without removing round-off there, so that a run stopped and restarted
  /// gives the same bits as one that went on.
  /// `added`: mass added on purpose to each fraction since the start (see
  /// Operator::addedMass), or nullptr for none.
  PetscErrorCode check(long step, FractionState &state, bool endOfRun = false,
                       const std::vector<double> *added = nullptr);
  PetscInt interval() const { return checkEvery; }
  /// Reference totals, and setting them again on restart.
  const std::vector<double> &reference() const { return totals; }
  void restore(const std::vector<double> &reference) { totals = reference; }
  /// Largest relative round-off drift removed so far.
  double largestCorrection() const { return largest; }

private:
  std::vector<double> totals;
  PetscInt checkEvery = 10;
  PetscReal leakTolerance = 1e-10;
  double largest = 0.0;
  long lastStep = 0;
};

} // namespace rcfd
