// The run's side of several databases (docs/databases.md): the set, the rule,
// the signals it decides on, switches.csv and the validity warning.  The
// run (src/run/run_switching.cpp) makes its operators follow a switch.
#pragma once

#include "rcfd/database_set.hpp"
#include "rcfd/fractions.hpp"
#include "rcfd/observables.hpp"
#include "rcfd/switching.hpp"

#include "state/layer_masses.hpp"
#include "database/fluidization_model.hpp"

#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace rcfd {

class DatabaseSwitcher {
public:
  /// Collective.  Reads -db_conditions and the rule (-db_switch_type and its options).
  PetscErrorCode setFromOptions(MPI_Comm comm, const SwitchRuleRegistry &rules);
  /// Collective.  Opens the set of `paths` (one partition) and sets the rule up.
  PetscErrorCode open(MPI_Comm comm, const std::vector<std::string> &paths, const DatabaseLoadOptions &options);
  /// Collective, once the run's first database is loaded: the signals' layers,
  /// OUTPUT_DIR/switches.csv (written from the first switch or warning on).
  /// `monitors`: the run's, whose signals a rule may use (checked here).
  /// `fluidization`: the case's conditions and u_mf correlation, the bottom
  /// layer's (Answers::fluidization), so that umf_usup is bottom.csv's u_mf/u_sup.
  PetscErrorCode setUp(const Database &first, const FractionSet &fractions, double solidDensity,
                       const FluidizationModel &fluidization, const std::string &outputDir, bool quiet,
                       const std::vector<const Monitor *> &monitors);

  /// Collective.  After the step that ends at `time`: whether the next step
  /// uses other databases (`target`), from the rule and the globally reduced
  /// signals; writes the validity warning the first time the state leaves
  /// every database's envelope.
  PetscErrorCode decide(long step, double time, const FractionState &state, bool *change, SwitchDecision *target);
  /// Collective.  The database of the choice (the set's, loaded unless held;
  /// or two of them blended), recorded as the active choice from `time` on.
  PetscErrorCode activate(const SwitchDecision &choice, double time, std::shared_ptr<Database> *db);
  /// Collective.  The database of the choice, as activate() makes it, without making it the
  /// active one: a forecast's member on its own conditions (docs/live.md).
  PetscErrorCode load(const SwitchDecision &choice, std::shared_ptr<Database> *db);
  /// Whether the rule chooses by u_sup alone (schedule, blend): a forecast's member then switches
  /// by its own u_sup (choiceFor); else it stays on the database in use.
  bool choosesByVelocity() const;
  /// Not collective.  The rule's choice at u_sup u [m/s] (choosesByVelocity()).
  SwitchDecision choiceFor(double u) const;
  /// The conditions of a choice at u_sup u (NaN: the choice's own), as operatingConditions() are
  /// of the active one.
  OperatingConditions conditionsFor(const SwitchDecision &choice, double u) const;
  /// Appends the switch to switches.csv and prints it (rank 0, unless quiet).
  PetscErrorCode record(double time, const SwitchDecision &from, double seconds);

  DatabaseSet &set() { return *set_; }
  const DatabaseSet &set() const { return *set_; }
  const SwitchRule &rule() const { return *rule_; }
  const SwitchDecision &active() const { return active_; }
  /// The active choice as switches.csv names it: "1", or "0+1@0.25" (a blend).
  std::string activeName() const;
  /// The conditions the run operates at now, which it hands its monitors
  /// (RunContext::operatingConditions): conditionsAt() the time of the last decision or
  /// switch.  A reference that stays valid and follows them.
  const OperatingConditions &operatingConditions() const { return operating_; }
  SwitchDecision initial() const { return rule_->initial(); }
  /// Not collective.  A live run's measured u_sup from time t on
  /// (MeasuredSchedule::appendSchedule); refused by a rule that does not run
  /// the bed at a u_sup over time.
  PetscErrorCode appendSchedule(double t, double u);
  long numSwitches() const { return switches; }
  /// Time of the validity warning [s], NaN while the run stays inside.
  double extrapolatingSince() const { return warnedAt; }
  PetscErrorCode flush() { return csv ? csv->flush() : 0; }
  /// Checkpoint: the rule's state, the file's length, the warning, the count.
  std::vector<double> saveState() const;
  /// The active choice of a saved state ([0] database, [1] partner, [2] weight, [3] trigger).
  static SwitchDecision savedChoice(const std::vector<double> &state);
  /// Collective.  Refuses a malformed state.
  PetscErrorCode restoreState(const std::vector<double> &state);
  PetscErrorCode view(PetscViewer viewer) const;

private:
  PetscErrorCode measure(long step, double time, const FractionState &state, SwitchSignals *s) const;
  PetscErrorCode warnIfOutside(const SwitchSignals &s, double usup);
  OperatingConditions conditionsOf(const SwitchDecision &choice) const;
  OperatingConditions conditionsAt(double time) const;
  static constexpr std::size_t kSaved = 7; // words before the rule's own
  MPI_Comm comm = MPI_COMM_NULL;
  std::vector<double> conditionVelocities; // -db_conditions
  std::unique_ptr<DatabaseSet> set_;
  std::unique_ptr<SwitchRule> rule_;
  SwitchDecision active_;
  OperatingConditions operating_; // conditionsAt(the time of the last decision or switch)
  long switches = 0;
  double warnedAt = std::numeric_limits<double>::quiet_NaN();
  // Signals.
  HorizontalLayers layers;
  const FractionSet *fractions = nullptr;
  double rho = 0.0, gravity = 9.81;
  FluidizationModel fluidization; // the case's conditions over the database's, and the correlation
  std::map<std::string, const Monitor *> monitorSignals; // the signals the rule uses, by who offers them
  bool pairByRecurrence = false;            // -db_blend_pairing recurrence
  std::map<std::pair<int, int>, int> lags;  // blend pairing lag of each pair of databases, once computed
  std::unique_ptr<CsvSeries> csv;
  std::string outputDir;
  bool quiet = false;
};

} // namespace rcfd
