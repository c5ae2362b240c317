// Scalars carried with each size fraction (docs/scalars.md): temperature,
// moisture, a tracer.  The state holds them as extensive amounts (mass x
// value, FractionState::amounts()), which every operator that moves mass
// moves with the same coefficients.  This is the run's list of them: their
// names, initial values, first-order decay, and the ledger of their amounts.
#pragma once

#include "rcfd/database.hpp"
#include "rcfd/fractions.hpp"
#include "state/scalar_sources.hpp"

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
  /// -scalar_mixing (scalar_mixing.csv) and its -scalar_mixing_tolerance (0.05).
  bool mixingAsked() const { return mixing == PETSC_TRUE; }
  /// -scalar_profiles (scalar_profiles.csv) and its -scalar_profiles_window t0,t1 (NaN: not given).
  bool profilesAsked() const { return profiles == PETSC_TRUE; }
  const std::vector<double> &profilesWindow() const { return window; }
  double mixingTolerance() const { return mixingShare; }
  /// Collective.  Each amount = the cell's mass of the fraction x the scalar's
  /// initial value there (the masses set first).
  PetscErrorCode setInitial(const Database &db, FractionState &state) const;
  /// Collective.  The sources' set-up (ScalarSources::setUp).
  PetscErrorCode setUp(const Database &db, const FractionSet &fractions, double solidDensity);
  /// Collective when sources other than decay are on (one reduction).  The
  /// sources of one step of dt ending in `frame`: a decaying scalar's amounts
  /// times exp(-k dt), then the spray and the exchange with the gas
  /// (ScalarSources), whose global change the ledger adds.
  PetscErrorCode applySources(double dt, int frame, FractionState &state);
  const ScalarSources &sources() const { return sourceTerms; }
  ScalarSources &sources() { return sourceTerms; }

  /// Collective.  The ledger: the amounts' totals per scalar and fraction now.
  PetscErrorCode startLedger(const FractionState &state);
  /// Not collective.  After a step's operators and sources: what the ledger
  /// expects each total to be now, from what it expected before, what the
  /// operators added in the step (`operatorsAdded`: Pipeline::addedAmounts
  /// since the start, global; empty when none reports), the decay and the
  /// sources' global change (both of applySources):
  ///   expected <- (expected + operators' step) exp(-k dt) + sources' step.
  void advanceLedger(const std::vector<double> &operatorsAdded);
  /// On a restart: the operators' amounts added up to the checkpoint (restored).
  void operatorsAddedSoFar(const std::vector<double> &operatorsAdded) { seen = operatorsAdded; }
  /// Collective.  Every `every` steps (and at the run's end): each total must
  /// be what the ledger expects within the tolerance, else the run stops
  /// naming the scalar; the round-off below it is removed by one factor per
  /// scalar and fraction (not at the end: a restart gives the same bits).
  PetscErrorCode checkLedger(long step, PetscInt every, FractionState &state, bool endOfRun);
  /// The checkpoint's part of the ledger: the expected totals, then per scalar what passed through it.
  std::vector<double> ledgerState() const;
  void restoreLedger(const std::vector<double> &r);
  /// Collective.  Prints the ledger's largest correction and, with sources, what
  /// they brought: liquid sprayed, dried and held, heat from the gas.
  /// `time`: the simulated time the account covers [s] (the check of the well-mixed gas).
  PetscErrorCode report(const FractionState &state, double time) const;
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
  ScalarSources sourceTerms;
  std::vector<double> expected; // [scalar][fraction]: the totals the ledger expects now
  std::vector<double> seen;     // the operators' added amounts at the last advance
  std::vector<double> passed;   // per scalar: its start and all its sources and operators moved in and out
  std::vector<double> decayFactor; // per scalar: exp(-k dt) of the last applySources
  std::vector<double> stepSources; // [scalar][fraction]: the sources' global change in the last step
  PetscReal tolerance = 1e-12, mixingShare = 0.05;
  PetscBool mixing = PETSC_FALSE, profiles = PETSC_FALSE;
  std::vector<double> window; // -scalar_profiles_window, empty: not given
  double largest = 0.0;
};

} // namespace rcfd
