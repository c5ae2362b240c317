// Switching rules: which database of a set (rcfd/database_set.hpp) a run
// uses at each step (docs/databases.md).  Rules have the life cycle of every
// extension point (docs/extending.md): created by name from a
// SwitchRuleRegistry (-db_switch_type), setFromOptions with the prefix
// "db_switch_", setUp once the set is open (re-entrant), then decide() after
// every step, view (-db_switch_view).  Built-in rules: schedule, blend,
// state, markov.
//
// A rule must decide the same on every rank without communication: it sees
// only globally reduced signals, and what decides its continuation is in
// saveState() (written into checkpoints).
//
// Adding a rule: derive from SwitchRule (type, describe, decide), add a
// factory to a SwitchRuleRegistry and hand it to Run::useSwitchRules;
// docs/examples/user-switch-rule is such a project, built against the
// installed library by the test suite.
#pragma once

#include "rcfd/database.hpp"
#include "rcfd/registry.hpp"

#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace rcfd {

/// What a rule may decide on: the run's time and quantities reduced over all
/// ranks (NaN when not measured).
struct SwitchSignals {
  long step = 0;
  double time = 0.0;                                             ///< [s], after the step
  double inventoryD32 = std::numeric_limits<double>::quiet_NaN(); ///< Sauter diameter of the bed [m]
  double bottomD32 = std::numeric_limits<double>::quiet_NaN();    ///< of the bottom cell layer [m]
  double umfOverUsup = std::numeric_limits<double>::quiet_NaN();  ///< u_mf(bottom d32) / u_sup
  /// A monitor's signal by name (Monitor::signal: its latest sample), set by the run.
  std::function<double(const std::string &)> fromMonitors;
  /// A signal by name: inventory_d32, bottom_d32, umf_usup, else a monitor's;
  /// NaN for a name nobody offers (the run refuses such a name before its
  /// first step, SwitchRule::signalsUsed).
  double named(const std::string &name) const;
  static const char *names() { return "inventory_d32, bottom_d32, umf_usup"; }
  static bool isBuiltIn(const std::string &name) {
    return name == "inventory_d32" || name == "bottom_d32" || name == "umf_usup";
  }
};

/// A rule's choice for the next step: one database, or the blend of two
/// (rcfd/database_set.hpp, blendDatabases); `trigger` is the value that
/// decided it (written to switches.csv).
struct SwitchDecision {
  int database = 0;
  double trigger = std::numeric_limits<double>::quiet_NaN();
  int partner = -1;    ///< blend: the second database (-1: none)
  double weight = 1.0; ///< blend: the weight of `database`; the partner has 1 - weight
  /// The same databases (and weight): no switch.
  bool sameAs(const SwitchDecision &o) const {
    return database == o.database && partner == o.partner && (partner < 0 || weight == o.weight);
  }
};

/// What a rule may read while it is set up.
struct SwitchContext {
  MPI_Comm comm;
  const std::vector<OperatingConditions> &databases; ///< the set's conditions, in -db order
};

class SwitchRule {
public:
  virtual ~SwitchRule() = default;
  void setOptionsPrefix(const std::string &p) { prefix_ = p; }
  const std::string &optionsPrefix() const { return prefix_; }
  /// Collective.  Reads the rule's own options (the base: none).
  virtual PetscErrorCode setFromOptions(MPI_Comm comm);
  /// Collective.  The base keeps the conditions of the set's databases.
  /// Re-entrant: a second call with the same databases gives the same rule.
  virtual PetscErrorCode setUp(const SwitchContext &ctx);
  /// Collective on the viewer.  The base prints "switching rule: <describe()>".
  virtual PetscErrorCode view(PetscViewer viewer) const;
  /// The database the run starts on (the base: the first).
  virtual SwitchDecision initial() const { return {}; }
  /// The database for the next step: `active` is the current choice.
  virtual SwitchDecision decide(const SwitchDecision &active, const SwitchSignals &signals) = 0;
  /// The superficial velocity the rule runs the bed at, at time t [m/s]; NaN
  /// (the default): the active database's.
  virtual double superficialVelocity(double) const { return std::numeric_limits<double>::quiet_NaN(); }
  /// Whether decide() reads the quantities of SwitchSignals (they cost a
  /// reduction per step); time and step are always there.
  virtual bool needsSignals() const { return false; }
  /// The signals decide() reads by name (checked against the built-in ones
  /// and the run's monitors before the first step).
  virtual std::vector<std::string> signalsUsed() const { return {}; }
  /// The registered name of the rule.
  virtual std::string type() const = 0;
  /// One line: the rule and its resolved parameters.
  virtual std::string describe() const = 0;
  /// Everything that decides the continuation (a generator's state), the same on every rank.
  virtual std::vector<double> saveState() const { return {}; }
  /// Not collective.  Refuses a malformed state with PETSC_ERR_ARG_WRONG
  /// (the base: a non-empty one).
  virtual PetscErrorCode restoreState(const std::vector<double> &state);

  int numDatabases() const { return static_cast<int>(conditions_.size()); }
  const OperatingConditions &conditions(int i) const { return conditions_.at(i); }

private:
  std::string prefix_ = "db_switch_";
  std::vector<OperatingConditions> conditions_;
};

using SwitchRuleFactory = std::function<std::unique_ptr<SwitchRule>()>;

/// Name -> factory of switching rules, owned by the program (no global).
class SwitchRuleRegistry : public Registry<SwitchRule> {
public:
  SwitchRuleRegistry() : Registry("-db_switch_type", "switching rule") {}
  /// schedule, blend, state and markov.
  static SwitchRuleRegistry withBuiltins();
  /// Collective.  Reads -db_switch_type (default schedule), creates the rule
  /// and lets it read its own options.
  PetscErrorCode createFromOptions(MPI_Comm comm, std::unique_ptr<SwitchRule> *rule) const;
};

/// The database whose superficial velocity is nearest to u (the first of a
/// tie); databases without a recorded u_sup are never nearest.  -1 when none has one.
int nearestDatabase(const std::vector<OperatingConditions> &databases, double u);

/// A band rule with hysteresis: bands are separated by ascending thresholds
/// x_1 < ... < x_{n-1}; the value stays in the current band until it passes a
/// threshold by more than the relative margin h, so a value dithering around
/// a threshold does not flicker between two bands.
int bandWithHysteresis(const std::vector<double> &thresholds, double margin, int current, double value);

} // namespace rcfd
