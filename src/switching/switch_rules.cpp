// The built-in switching rules (docs/databases.md): schedule, state, markov.
#include "rcfd/switching.hpp"
#include "base/checked_options.hpp"
#include "base/petsc_compat.hpp"
#include "base/random.hpp"
#include "base/collective.hpp"
#include "switching/measured_schedule.hpp"

#include <algorithm>
#include <array>

#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace rcfd {

double SwitchSignals::named(const std::string &name) const {
  if (name == "inventory_d32") return inventoryD32;
  if (name == "bottom_d32") return bottomD32;
  if (name == "umf_usup") return umfOverUsup;
  if (fromMonitors) return fromMonitors(name);
  return std::numeric_limits<double>::quiet_NaN();
}

PetscErrorCode SwitchRule::setFromOptions(MPI_Comm) { return PETSC_SUCCESS; }

PetscErrorCode SwitchRule::setUp(const SwitchContext &ctx) {
  conditions_ = ctx.databases;
  return PETSC_SUCCESS;
}

PetscErrorCode SwitchRule::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer, "switching rule: %s\n", describe().c_str()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SwitchRule::restoreState(const std::vector<double> &state) {
  PetscFunctionBeginUser;
  PetscCheck(state.empty(), PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG,
             "The checkpoint holds state of the switching rule %s, which keeps none", type().c_str());
  PetscFunctionReturn(PETSC_SUCCESS);
}

int nearestDatabase(const std::vector<OperatingConditions> &databases, double u) {
  int best = -1;
  for (int i = 0; i < static_cast<int>(databases.size()); ++i) {
    const double ui = databases[i].superficialVelocity;
    if (!std::isfinite(ui)) continue;
    if (best < 0 || std::fabs(ui - u) < std::fabs(databases[best].superficialVelocity - u)) best = i;
  }
  return best;
}

int bandWithHysteresis(const std::vector<double> &thresholds, double margin, int current, double value) {
  if (!std::isfinite(value)) return current; // nothing measured: stay
  int band = current;
  // Up while the value is clearly above the band's upper threshold, down while clearly below its lower one.
  while (band < static_cast<int>(thresholds.size()) && value > thresholds[band] * (1.0 + margin)) ++band;
  while (band > 0 && value < thresholds[band - 1] * (1.0 - margin)) --band;
  return band;
}

namespace {

/// "a,b,c" -> numbers; throws naming the option.
std::vector<double> numberList(const std::string &text, const std::string &option) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    char *end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0' || !std::isfinite(v))
      throw std::invalid_argument(option + " '" + text + "': '" + item + "' is not a number");
    out.push_back(v);
  }
  return out;
}

/// Whether -help was given: a rule then lists its options without asking for them.
bool helpAsked() {
  PetscBool help = PETSC_FALSE;
  return PetscOptionsHasName(nullptr, nullptr, "-help", &help) == 0 && help;
}

/// Reads a string option of the rule; `*set` says whether it was given.
PetscErrorCode stringOption(MPI_Comm comm, const std::string &prefix, const char *name, const char *help,
                            std::string *value, PetscBool *set) {
  char text[1024];
  // PETSc's -help prints a block only the first time its title is seen, so
  // each option gets its own title.
  const std::string title = std::string("Switching between databases: ") + (name + 1);
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, prefix.c_str(), title.c_str(), "rcfd");
  PetscCall(PetscOptionsString(name, help, "", value->c_str(), text, sizeof text, set));
  PetscOptionsEnd();
  if (*set) *value = text;
  PetscFunctionReturn(PETSC_SUCCESS);
}

// schedule: the operating condition over time; the database recorded nearest to it.
class ScheduleRule : public SwitchRule, public MeasuredSchedule {
public:
  std::string type() const override { return "schedule"; }
  PetscErrorCode setFromOptions(MPI_Comm comm) override {
    PetscBool set = PETSC_FALSE;
    std::string text;
    PetscFunctionBeginUser;
    PetscCall(stringOption(comm, optionsPrefix(), "-schedule",
                           "Superficial velocity over time, t0:u0,t1:u1,... [s:m/s] from t0 = 0, held until the next",
                           &text, &set));
    if (!set && helpAsked()) text = "0:1";
    // A live run appends its measured u_sup instead (appendSchedule); setUp
    // checks that one of the two gave the schedule.
    fromOptions = set || helpAsked();
    if (!fromOptions) {
      times.clear();
      velocities.clear();
      PetscFunctionReturn(PETSC_SUCCESS);
    }
    const std::string option = "-" + optionsPrefix() + "schedule";
    PetscCall(collectively(comm, [&] {
      times.clear();
      velocities.clear();
      std::stringstream ss(text);
      std::string item;
      while (std::getline(ss, item, ',')) {
        const auto colon = item.find(':');
        if (colon == std::string::npos)
          throw std::invalid_argument(option + " '" + text + "': '" + item + "' is not time:velocity");
        const auto pair = numberList(item.substr(0, colon) + "," + item.substr(colon + 1), option);
        if (!times.empty() && !(pair[0] > times.back()))
          throw std::invalid_argument(option + " '" + text + "': the times must increase");
        if (!(pair[1] > 0)) throw std::invalid_argument(option + " '" + text + "': velocities must be positive");
        times.push_back(pair[0]);
        velocities.push_back(pair[1]);
      }
      if (times.empty() || times.front() != 0.0)
        throw std::invalid_argument(option + " '" + text + "' must start at time 0 (0:u0,...)");
    }, PETSC_ERR_USER_INPUT));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscErrorCode setUp(const SwitchContext &ctx) override {
    const MPI_Comm comm = ctx.comm;
    const std::vector<OperatingConditions> &databases = ctx.databases;
    PetscFunctionBeginUser;
    PetscCall(SwitchRule::setUp(ctx));
    PetscCheck(!times.empty(), comm, PETSC_ERR_USER_INPUT,
               "-%sschedule is needed by the %s rule, e.g. -%sschedule 0:1.1,30:1.2 (s:m/s), or a live file with a "
               "u_sup column (-live FILE)", optionsPrefix().c_str(), type().c_str(), optionsPrefix().c_str());
    PetscCheck(nearestDatabase(databases, 1.0) >= 0, comm, PETSC_ERR_USER_INPUT,
               "The schedule rule needs the databases' superficial velocities: none records one; give them "
               "with -db_conditions u1,u2,... in the order of -db");
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  double superficialVelocity(double t) const override {
    if (times.empty()) return std::numeric_limits<double>::quiet_NaN();
    // The last entry at or before t (to round-off); a live schedule grows long.
    const auto after = std::upper_bound(times.begin(), times.end(), t * (1.0 + 1e-12));
    return velocities[after == times.begin() ? 0 : static_cast<std::size_t>(after - times.begin()) - 1];
  }
  PetscErrorCode appendSchedule(double t, double u) override { // a live run's u_sup
    PetscFunctionBeginUser;
    PetscCheck(!fromOptions, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
               "-%sschedule and the live file's u_sup column both give u_sup; give it once", optionsPrefix().c_str());
    PetscCheck(times.empty() ? t == 0.0 : t > times.back(), PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
               "the %s rule's schedule must start at time 0 and increase (got %g s after %g s)", type().c_str(), t,
               times.empty() ? -1.0 : times.back());
    PetscCheck(u > 0, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "a superficial velocity must be positive (got %g m/s)", u);
    if (!velocities.empty() && velocities.back() == u) PetscFunctionReturn(PETSC_SUCCESS); // held: the same schedule
    times.push_back(t);
    velocities.push_back(u);
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  SwitchDecision initial() const override { return choose(velocities.front()); }
  SwitchDecision choiceFor(double u) const override { return choose(u); }
  SwitchDecision decide(const SwitchDecision &, const SwitchSignals &s) override {
    return choose(superficialVelocity(s.time));
  }
  std::string describe() const override {
    // A live schedule grows as the run goes: the rule is the same whatever of it has arrived
    // (switches.csv's header, the checkpoint's record of the physics).
    if (!fromOptions) return "schedule of u_sup: measured, from the live file (-live); the database recorded nearest";
    std::string text = "schedule of u_sup:";
    char item[64];
    for (std::size_t k = 0; k < times.size(); ++k) {
      std::snprintf(item, sizeof item, " %g m/s from %g s%s", velocities[k], times[k], k + 1 < times.size() ? "," : "");
      text += item;
    }
    return text + "; the database recorded nearest";
  }

protected:
  /// The database for superficial velocity u.
  virtual SwitchDecision choose(double u) const { return {std::max(0, nearestDatabase(databasesConditions(), u)), u}; }
  std::vector<OperatingConditions> databasesConditions() const {
    std::vector<OperatingConditions> c;
    for (int i = 0; i < numDatabases(); ++i) c.push_back(conditions(i));
    return c;
  }
  std::vector<double> times, velocities;
  bool fromOptions = false; // -db_switch_schedule gave it (else a live run appends it)
};

// blend: the schedule's condition between the two databases that bracket it,
// weighted linearly in u_sup; outside the databases' range the nearest alone.
class BlendRule final : public ScheduleRule {
public:
  std::string type() const override { return "blend"; }
  std::string describe() const override {
    std::string text = ScheduleRule::describe();
    return "blend: " + text.substr(0, text.find(';')) + "; the two databases that bracket it, weighted linearly";
  }

protected:
  SwitchDecision choose(double u) const override {
    int below = -1, above = -1; // the nearest recorded at or below u, and above it
    for (int i = 0; i < numDatabases(); ++i) {
      const double ui = conditions(i).superficialVelocity;
      if (!std::isfinite(ui)) continue;
      if (ui <= u && (below < 0 || ui > conditions(below).superficialVelocity)) below = i;
      if (ui > u && (above < 0 || ui < conditions(above).superficialVelocity)) above = i;
    }
    if (below < 0 || above < 0 || conditions(below).superficialVelocity == u) return ScheduleRule::choose(u);
    const double lo = conditions(below).superficialVelocity, hi = conditions(above).superficialVelocity;
    SwitchDecision d{below, u, above, (hi - u) / (hi - lo)};
    return d;
  }
};

// state: a monitored quantity in bands separated by thresholds, with hysteresis.
class StateRule final : public SwitchRule {
public:
  std::string type() const override { return "state"; }
  PetscErrorCode setFromOptions(MPI_Comm comm) override {
    PetscBool set = PETSC_FALSE;
    std::string text;
    PetscFunctionBeginUser;
    PetscCall(stringOption(comm, optionsPrefix(), "-quantity",
                           "Signal that selects the database: inventory_d32, bottom_d32, umf_usup or a monitor's "
                           "(delta_z, z_cog_bed of cog.csv)", &quantity, &set));
    PetscCall(stringOption(comm, optionsPrefix(), "-thresholds",
                           "Ascending values between the databases' bands, one fewer than databases (in -db order)",
                           &text, &set));
    if (!set && helpAsked()) text = "1";
    PetscCheck(set || helpAsked(), comm, PETSC_ERR_USER_INPUT,
               "-%sthresholds is needed by the state rule: the values of -%squantity between the databases, in -db order",
               optionsPrefix().c_str(), optionsPrefix().c_str());
    const std::string option = "-" + optionsPrefix() + "thresholds";
    PetscCall(collectively(comm, [&] {
      thresholds = numberList(text, option);
      for (std::size_t k = 1; k < thresholds.size(); ++k)
        if (!(thresholds[k] > thresholds[k - 1])) throw std::invalid_argument(option + " '" + text + "' must increase");
    }, PETSC_ERR_USER_INPUT));
    PetscInt first = start;
    PetscOptionsBegin(comm, optionsPrefix().c_str(), "Switching by the state", "rcfd");
    PetscCall(checkedReal(PetscOptionsObject, "-hysteresis",
                          "Relative margin a value must pass a threshold by before the database changes",
                          &margin, {0.0, 1.0, true, false, "a number in [0, 1)"}));
    PetscCall(checkedInt(PetscOptionsObject, "-initial", "Database (index in -db) the run starts on", &first, 0, 1000));
    PetscOptionsEnd();
    start = static_cast<int>(first);
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscErrorCode setUp(const SwitchContext &ctx) override {
    const MPI_Comm comm = ctx.comm;
    const std::vector<OperatingConditions> &databases = ctx.databases;
    PetscFunctionBeginUser;
    PetscCall(SwitchRule::setUp(ctx));
    PetscCheck(thresholds.size() + 1 == databases.size(), comm, PETSC_ERR_USER_INPUT,
               "-%sthresholds has %zu values for %zu databases; give one fewer than databases", optionsPrefix().c_str(),
               thresholds.size(), databases.size());
    PetscCheck(start < numDatabases(), comm, PETSC_ERR_USER_INPUT, "-%sinitial %d: there are %d databases",
               optionsPrefix().c_str(), start, numDatabases());
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  bool needsSignals() const override { return true; }
  std::vector<std::string> signalsUsed() const override { return {quantity}; }
  SwitchDecision initial() const override { return {start}; }
  SwitchDecision decide(const SwitchDecision &active, const SwitchSignals &s) override {
    const double value = s.named(quantity);
    return {bandWithHysteresis(thresholds, margin, active.database, value), value};
  }
  std::string describe() const override {
    std::string text = "state: " + quantity + " in bands split at";
    char item[64];
    for (double x : thresholds) {
      std::snprintf(item, sizeof item, " %g", x);
      text += item;
    }
    std::snprintf(item, sizeof item, ", hysteresis %g, starting on database %d", margin, start);
    return text + item;
  }

private:
  std::string quantity = "umf_usup";
  std::vector<double> thresholds;
  double margin = 0.05;
  int start = 0;
};

// markov: every interval a database drawn by its weight, seeded (CFDEMcoupling's rule).
class MarkovRule final : public SwitchRule {
public:
  std::string type() const override { return "markov"; }
  PetscErrorCode setFromOptions(MPI_Comm comm) override {
    PetscBool set = PETSC_FALSE;
    std::string text;
    PetscInt seedValue = static_cast<PetscInt>(seed);
    PetscFunctionBeginUser;
    PetscCall(stringOption(comm, optionsPrefix(), "-weights", "Weight of each database (in -db order; default equal)",
                           &text, &set));
    const std::string option = "-" + optionsPrefix() + "weights";
    if (set)
      PetscCall(collectively(comm, [&] {
        weights = numberList(text, option);
        double total = 0.0;
        for (double w : weights) {
          if (w < 0) throw std::invalid_argument(option + " '" + text + "': weights must not be negative");
          total += w;
        }
        if (!(total > 0)) throw std::invalid_argument(option + " '" + text + "': some weight must be positive");
      }, PETSC_ERR_USER_INPUT));
    PetscOptionsBegin(comm, optionsPrefix().c_str(), "Random switching", "rcfd");
    PetscCall(checkedReal(PetscOptionsObject, "-interval", "Simulated time between draws [s]", &interval, kPositive));
    PetscCall(checkedInt(PetscOptionsObject, "-seed", "Seed of the draws", &seedValue, 0, PETSC_MAX_INT));
    PetscOptionsEnd();
    seed = static_cast<std::uint64_t>(seedValue);
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscErrorCode setUp(const SwitchContext &ctx) override {
    const MPI_Comm comm = ctx.comm;
    const std::vector<OperatingConditions> &databases = ctx.databases;
    PetscFunctionBeginUser;
    PetscCall(SwitchRule::setUp(ctx));
    if (weights.empty()) weights.assign(databases.size(), 1.0);
    PetscCheck(weights.size() == databases.size(), comm, PETSC_ERR_USER_INPUT,
               "-%sweights has %zu values for %zu databases", optionsPrefix().c_str(), weights.size(), databases.size());
    random = Xoshiro256(seed);
    nextDraw = interval;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  SwitchDecision decide(const SwitchDecision &active, const SwitchSignals &s) override {
    if (s.time < nextDraw * (1.0 - 1e-12)) return active;
    nextDraw += interval;
    double total = 0.0;
    for (double w : weights) total += w;
    const double u = random.uniform();
    double below = 0.0;
    for (int i = 0; i < numDatabases(); ++i) {
      below += weights[i] / total;
      if (u < below && weights[i] > 0) return {i, u};
    }
    for (int i = numDatabases() - 1; i >= 0; --i) // round-off at the top: the last with weight
      if (weights[i] > 0) return {i, u};
    return {active.database, u};
  }
  std::string describe() const override {
    std::string text = "markov: every " + std::to_string(interval) + " s a database drawn with weights";
    char item[48];
    for (double w : weights) {
      std::snprintf(item, sizeof item, " %g", w);
      text += item;
    }
    return text + ", seed " + std::to_string(seed);
  }
  // The generator's four words as eight exact 32-bit halves, and the next draw's time.
  std::vector<double> saveState() const override {
    std::vector<double> words;
    for (std::uint64_t w : random.state()) {
      words.push_back(static_cast<double>(w >> 32));
      words.push_back(static_cast<double>(w & 0xffffffffULL));
    }
    words.push_back(nextDraw);
    return words;
  }
  PetscErrorCode restoreState(const std::vector<double> &words) override {
    PetscFunctionBeginUser;
    PetscCheck(words.size() == 9, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG,
               "the markov switching rule's saved state has the wrong size");
    std::array<std::uint64_t, 4> s{};
    for (int k = 0; k < 4; ++k)
      s[k] = (static_cast<std::uint64_t>(words[2 * k]) << 32) | static_cast<std::uint64_t>(words[2 * k + 1]);
    random.setState(s);
    nextDraw = words[8];
    PetscFunctionReturn(PETSC_SUCCESS);
  }

private:
  std::vector<double> weights;
  double interval = 1.0, nextDraw = 1.0;
  std::uint64_t seed = 1;
  Xoshiro256 random;
};

} // namespace

SwitchRuleRegistry SwitchRuleRegistry::withBuiltins() {
  SwitchRuleRegistry r;
  // The built-in names are identifiers and distinct: add() cannot fail here.
  PetscCallAbort(PETSC_COMM_SELF, r.add("schedule", [] { return std::make_unique<ScheduleRule>(); },
        "the superficial velocity over time (-db_switch_schedule); the database recorded nearest to it"));
  PetscCallAbort(PETSC_COMM_SELF, r.add("blend", [] { return std::make_unique<BlendRule>(); },
        "the schedule's u_sup between the two databases that bracket it: their frames blended as mass fluxes"));
  PetscCallAbort(PETSC_COMM_SELF, r.add("state", [] { return std::make_unique<StateRule>(); },
        "a monitored quantity (-db_switch_quantity) in bands (-db_switch_thresholds) with hysteresis"));
  PetscCallAbort(PETSC_COMM_SELF, r.add("markov", [] { return std::make_unique<MarkovRule>(); },
        "every -db_switch_interval a database drawn by -db_switch_weights, seeded (-db_switch_seed)"));
  return r;
}

PetscErrorCode SwitchRuleRegistry::createFromOptions(MPI_Comm comm, std::unique_ptr<SwitchRule> *rule) const {
  char text[256];
  PetscBool set = PETSC_FALSE;
  PetscFunctionBeginUser;
  const std::string help = "How the run moves between the databases of -db: " + listing();
  PetscOptionsBegin(comm, nullptr, "Switching between databases", "rcfd");
  PetscCall(PetscOptionsString("-db_switch_type", help.c_str(), "", "schedule", text, sizeof text, &set));
  PetscOptionsEnd();
  const std::string name = set ? text : "schedule";
  PetscCall(agreeOnStatus(comm, create(name, rule)));
  PetscCall((*rule)->setFromOptions(comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
