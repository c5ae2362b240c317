// Scalars carried with each size fraction (docs/scalars.md): temperature,
// moisture, a tracer.  The state holds them as extensive amounts (mass x
// value, FractionState::amounts()), which every operator that moves mass
// moves with the same coefficients.  This is the run's list of them: their
// names, initial values, first-order decay, and the ledger of their amounts.
#pragma once

#include "rcfd/database.hpp"
#include "rcfd/fractions.hpp"

#include <string>
#include <vector>

namespace rcfd {

class ScalarSet {
public:
  /// Collective.  Reads -scalars NAME,... and for each NAME (prefix scalar_NAME_):
  /// -scalar_NAME_initial v (default 0), -scalar_NAME_zones z1,z2 with
  /// -scalar_NAME_zone_values v1,v2 (cells of zone z_k take v_k; later zones
  /// win), -scalar_NAME_initial_file FILE (HDF5, /values [cells x fractions] in
  /// natural cell order, as -init_file's /masses: a value per cell and
  /// fraction, over the zones), -scalar_NAME_decay k [1/s] (default 0); and -scalar_leak_tolerance
  /// (relative, default 1e-12).  A negative or NaN value is refused.
  PetscErrorCode setFromOptions(MPI_Comm comm);
  int size() const { return static_cast<int>(scalars.size()); }
  const std::string &name(int s) const { return scalars[s].name; }
  std::vector<std::string> names() const;
  double decayRate(int s) const { return scalars[s].decay; }
  /// Collective.  Each amount = the cell's mass of the fraction x the scalar's
  /// initial value there (the masses set first).
  PetscErrorCode setInitial(const Database &db, FractionState &state) const;
  /// Not collective.  The sources of one step of dt: a decaying scalar's
  /// amounts times exp(-k dt).
  PetscErrorCode applySources(double dt, FractionState &state) const;

  /// Collective.  The ledger: the amounts' totals per scalar and fraction now.
  PetscErrorCode startLedger(const FractionState &state);
  /// Collective.  Every `every` steps (and at the run's end): each total must
  /// be its start times exp(-k t) within the tolerance, else the run stops
  /// naming the scalar; the round-off below it is removed by one factor per
  /// scalar and fraction (not at the end: a restart gives the same bits).
  PetscErrorCode checkLedger(long step, double dt, PetscInt every, FractionState &state, bool endOfRun);
  const std::vector<double> &ledgerReference() const { return reference; }
  void restoreLedger(const std::vector<double> &r) { reference = r; }
  /// Largest relative round-off the ledger removed.
  double largestCorrection() const { return largest; }

private:
  struct Scalar {
    std::string name;
    double initial = 0.0, decay = 0.0;
    std::vector<std::string> zones;
    std::vector<double> zoneValues;
    std::string file; // values per cell and fraction
  };
  std::vector<Scalar> scalars;
  std::vector<double> reference; // [scalar][fraction] at step 0
  PetscReal tolerance = 1e-12;
  double largest = 0.0;
};

} // namespace rcfd
