// The `markov` monitor of a run (`rcfd run -monitors markov -zones ...`,
// docs/markov.md, "In a run"): the zones' time per visit and time away from
// the run's database as the solid's Markov chain, for the bulk and, with
// several size classes, for each class with the run's drift linearised on the
// mean composition (or, with -markov_class_background stationary, on the bed
// the classes' chains give), the wrap carried as the run carries its state.  The
// chain's answers do not depend on the run's state: they are worked out once,
// at set-up, and written to the run's output directory (markov.csv,
// markov_zone_NAME[_CLASS].csv).
#pragma once

#include "markov/class_background.hpp"
#include "markov/class_drift.hpp"
#include "markov/spectrum.hpp"
#include "markov/wrap_carry.hpp"
#include "markov/zone_passages.hpp"
#include "rcfd/observables.hpp"
#include "rcfd/zone.hpp"

namespace rcfd {

class MarkovMonitor : public Monitor {
public:
  std::string type() const override { return "markov"; }
  /// Collective.  Its own options (-markov_departures, -markov_passage_horizon,
  /// -markov_passage_tail, -markov_class_background with its iterations and
  /// tolerance, and for the stationary background SLEPc's -markov_eps_*) and the run's: its zones (-zones, the zones' shapes),
  /// drift (-drift_*) and carry (-carry_type).
  PetscErrorCode setFromOptions(MPI_Comm comm) override;
  /// Collective.  Works the chain out on the run's database and writes the
  /// files (once per database: a second call on the same one does nothing).
  PetscErrorCode setUp(const RunContext &run, const FractionState &state, const std::string &outputDirectory) override;
  PetscErrorCode sample(const MonitorContext &) override { return 0; } // nothing depends on the state
  PetscErrorCode view(PetscViewer viewer) const override;

private:
  ZoneSet zones_;
  PassageSettings passages_;
  PetscInt departures_ = 16;
  ClassDrift drift_;
  WrapCarry carry_;
  bool stationaryBackground_ = false; // -markov_class_background stationary
  BackgroundSettings background_;
  ChainEigensolver solver_; // with the stationary background: the absorbing cells and the period chains
  std::string done_; // identity of the database the files were written for
  std::vector<std::string> written_;
};

} // namespace rcfd
