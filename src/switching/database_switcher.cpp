// The run's side of several databases: signals, decisions, switches.csv and
// the validity warning (docs/databases.md).
#include "switching/database_switcher.hpp"
#include "base/collective.hpp"
#include "base/petsc_compat.hpp"
#include "base/checked_options.hpp"
#include "switching/measured_schedule.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace rcfd {

PetscErrorCode DatabaseSwitcher::setFromOptions(MPI_Comm c, const SwitchRuleRegistry &rules) {
  PetscReal given[64] = {0.0};
  PetscInt n = 64;
  PetscBool set = PETSC_FALSE;
  PetscFunctionBeginUser;
  comm = c;
  PetscOptionsBegin(comm, nullptr, "Several databases", "rcfd");
  PetscCall(checkedRealArray(PetscOptionsObject, "-db_conditions",
                             "Superficial velocity [m/s] each database of -db was recorded at, in its order "
                             "(default: the files' metadata)",
                             given, &n, &set));
  const char *const pairings[] = {"index", "recurrence"};
  PetscInt pairing = pairByRecurrence ? 1 : 0;
  PetscCall(PetscOptionsEList("-db_blend_pairing",
                              "How a blend pairs the frames of its two databases: by index, or shifted by the lag "
                              "that makes the paired alpha_s fields most alike",
                              "", pairings, 2, pairings[pairing], &pairing, nullptr));
  pairByRecurrence = pairing == 1;
  PetscOptionsEnd();
  conditionVelocities.clear();
  if (set)
    for (PetscInt i = 0; i < n; ++i) {
      PetscCheck(given[i] > 0 && std::isfinite(given[i]), comm, PETSC_ERR_USER_INPUT,
                 "-db_conditions: value %d is %g, expected a positive superficial velocity in m/s", (int)i + 1,
                 (double)given[i]);
      conditionVelocities.push_back(given[i]);
    }
  PetscCall(rules.createFromOptions(comm, &rule_));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode DatabaseSwitcher::open(MPI_Comm c, const std::vector<std::string> &paths,
                                      const DatabaseLoadOptions &options) {
  PetscFunctionBeginUser;
  comm = c;
  PetscCall(DatabaseSet::open(comm, paths, options, conditionVelocities, &set_));
  std::vector<OperatingConditions> conditions;
  for (int i = 0; i < set_->size(); ++i) conditions.push_back(set_->entry(i).conditions);
  PetscCall(rule_->setUp(SwitchContext{comm, conditions}));
  active_ = rule_->initial();
  operating_ = conditionsAt(0.0);
  for (int i : {active_.database, active_.partner})
    PetscCheck(i < set_->size(), comm, PETSC_ERR_USER_INPUT, "The %s switching rule starts on database %d of %d",
               rule_->type().c_str(), i, set_->size());
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode DatabaseSwitcher::setUp(const Database &first, const FractionSet &set, double solidDensity,
                                       const FluidizationModel &model, const std::string &directory, bool beQuiet,
                                       const std::vector<const Monitor *> &monitors) {
  PetscFunctionBeginUser;
  monitorSignals.clear();
  for (const std::string &name : rule_->signalsUsed()) {
    if (SwitchSignals::isBuiltIn(name)) continue;
    std::string offered;
    for (const Monitor *m : monitors)
      for (const std::string &n : m->signalNames()) {
        if (n == name && !monitorSignals.count(name)) monitorSignals[name] = m;
        offered += (offered.empty() ? "" : ", ") + n;
      }
    PetscCheck(monitorSignals.count(name), comm, PETSC_ERR_USER_INPUT,
               "The %s switching rule decides on '%s', which is neither a built-in signal (%s) nor one of this "
               "run's monitors' (%s)", rule_->type().c_str(), name.c_str(), SwitchSignals::names(),
               offered.empty() ? "none" : offered.c_str());
  }
  // Two answers to "what is u_sup" would give bottom.csv one and the switch
  // signal the other.
  PetscCheck(!std::isfinite(model.given.superficialVelocity) || !std::isfinite(rule_->superficialVelocity(0.0)),
             comm, PETSC_ERR_USER_INPUT,
             "-superficial_velocity %g and the %s rule's -db_switch_schedule both give u_sup; give it once (the "
             "schedule sets it over time)",
             model.given.superficialVelocity, rule_->type().c_str());
  fractions = &set;
  rho = solidDensity;
  fluidization = model;
  outputDir = directory;
  quiet = beQuiet;
  const Vec3 &g = first.metadata().gravity;
  gravity = std::hypot(g[0], g[1], g[2]);
  PetscCall(layers.setUp(first));
  csv = std::make_unique<CsvSeries>(
      comm, outputDir + "/switches.csv",
      "# database switches (" + rule_->describe() + "); event extrapolating: the state left every database's "
      "envelope\ntime_s,from,to,trigger,event");
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The signals, reduced over all ranks: one reduction of the masses per layer.
PetscErrorCode DatabaseSwitcher::measure(long step, double time, const FractionState &state, SwitchSignals *s) const {
  const int nf = fractions->size();
  std::vector<double> perLayer, totals(nf, 0.0);
  PetscFunctionBeginUser;
  s->step = step;
  s->time = time;
  s->fromMonitors = [this](const std::string &name) {
    const auto who = monitorSignals.find(name);
    // Names are checked before the first step; NaN as SwitchSignals::named.
    return who == monitorSignals.end() ? std::numeric_limits<double>::quiet_NaN() : who->second->signal(name);
  };
  PetscCall(layers.fractionMasses(state.masses(), nf, &perLayer));
  for (std::size_t k = 0; k < perLayer.size(); ++k) totals[k % nf] += perLayer[k];
  double mass = 0.0, massOverD = 0.0;
  for (int i = 0; i < nf; ++i) {
    mass += totals[i];
    massOverD += totals[i] / fractions->diameter(i);
  }
  s->inventoryD32 = mass > 0 ? mass / massOverD : std::numeric_limits<double>::quiet_NaN();
  s->bottomD32 = layers::sauterDiameter(perLayer, 0, *fractions);
  // The bottom layer's conditions at `time` (decide() has set them), resolved
  // as it resolves them, and its correlation: bottom.csv's u_mf/u_sup.
  const OperatingConditions now = fluidization.resolve(operating_);
  if (std::isfinite(s->bottomD32) && rho > now.gasDensity)
    s->umfOverUsup = fluidization.minFluidizationVelocity(s->bottomD32, rho, now, gravity) / now.superficialVelocity;
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The one place that says what u_sup the run operates at: the rule's at
// `time` where it sets one (a schedule's, also between or outside the
// databases' u_sup), else that of the databases in use.  The gas is always
// theirs (a blend's interpolated).
OperatingConditions DatabaseSwitcher::conditionsAt(double time) const {
  OperatingConditions c = conditionsOf(active_);
  const double scheduled = rule_->superficialVelocity(time);
  if (std::isfinite(scheduled)) c.superficialVelocity = scheduled;
  return c;
}

// A blend stands for the conditions between its two databases' at its weight
// (its u_sup is the blend rule's schedule's to round-off; conditionsAt() puts
// the schedule's own); a quantity only one of them recorded is that one's.
OperatingConditions DatabaseSwitcher::conditionsOf(const SwitchDecision &d) const {
  const OperatingConditions &a = set_->entry(d.database).conditions;
  if (d.partner < 0) return a;
  const OperatingConditions &b = set_->entry(d.partner).conditions;
  auto mix = [w = d.weight](double x, double y) {
    return std::isfinite(x) && std::isfinite(y) ? w * x + (1.0 - w) * y : std::isfinite(x) ? x : y;
  };
  return {mix(a.superficialVelocity, b.superficialVelocity), mix(a.gasDensity, b.gasDensity),
          mix(a.gasKinematicViscosity, b.gasKinematicViscosity)};
}

namespace {

/// "1" or "0+1@0.25" (database 0 at weight 0.25 blended with 1).
std::string choiceText(const SwitchDecision &d) {
  if (d.partner < 0) return std::to_string(d.database);
  char text[64];
  std::snprintf(text, sizeof text, "%d+%d@%.6g", d.database, d.partner, d.weight);
  return text;
}

} // namespace

std::string DatabaseSwitcher::activeName() const { return choiceText(active_); }

// Each database's envelope is the condition it was recorded at: its u_sup,
// with a fluidized bottom (u_mf < u_sup).  The set covers u_sup between its
// smallest and largest; a run outside, or with a de-fluidized bottom, which
// no database recorded, is extrapolating.
PetscErrorCode DatabaseSwitcher::warnIfOutside(const SwitchSignals &s, double usup) {
  PetscFunctionBeginUser;
  if (std::isfinite(warnedAt)) PetscFunctionReturn(PETSC_SUCCESS);
  double low = HUGE_VAL, high = -HUGE_VAL;
  for (int i = 0; i < set_->size(); ++i) {
    const double u = set_->entry(i).conditions.superficialVelocity;
    if (std::isfinite(u)) low = std::min(low, u), high = std::max(high, u);
  }
  char what[256] = "";
  double value = NAN;
  if (std::isfinite(usup) && low <= high && (usup < low * (1 - 1e-12) || usup > high * (1 + 1e-12))) {
    value = usup;
    std::snprintf(what, sizeof what, "u_sup = %g m/s is outside the databases' %g to %g m/s", usup, low, high);
  } else if (s.umfOverUsup >= 1.0) {
    value = s.umfOverUsup;
    std::snprintf(what, sizeof what,
                  "the bottom layer's d32 = %.4g mm gives u_mf/u_sup = %.4g >= 1 (de-fluidized), which no database "
                  "recorded", s.bottomD32 * 1e3, s.umfOverUsup);
  }
  if (!*what) PetscFunctionReturn(PETSC_SUCCESS);
  warnedAt = s.time;
  if (!quiet) PetscCall(PetscPrintf(comm, "Warning: rcfd is extrapolating from t = %g s (step %ld): %s\n", s.time, s.step, what));
  char row[160];
  std::snprintf(row, sizeof row, "%.9g,%s,%s,%.10g,extrapolating", s.time, choiceText(active_).c_str(),
                choiceText(active_).c_str(), value);
  PetscCall(csv->add(row));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode DatabaseSwitcher::decide(long step, double time, const FractionState &state, bool *change,
                                        SwitchDecision *target) {
  SwitchSignals s;
  PetscFunctionBeginUser;
  s.step = step;
  s.time = time;
  operating_ = conditionsAt(time); // what the monitors see at `time`, a switch or not
  PetscCall(measure(step, time, state, &s)); // also for the validity warning
  PetscCall(warnIfOutside(s, fluidization.resolve(operating_).superficialVelocity));
  SwitchDecision d;
  PetscCall(collectively(comm, [&] { d = rule_->decide(active_, s); }));
  PetscCheck(d.database >= 0 && d.database < set_->size() && d.partner < set_->size() && d.weight >= 0 && d.weight <= 1,
             comm, PETSC_ERR_PLIB, "The %s switching rule chose database %d (and %d at weight %g) of %d",
             rule_->type().c_str(), d.database, d.partner, d.weight, set_->size());
  *change = !d.sameAs(active_);
  *target = d;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode DatabaseSwitcher::activate(const SwitchDecision &choice, double time, std::shared_ptr<Database> *db) {
  PetscFunctionBeginUser;
  PetscCall(load(choice, db));
  active_ = choice;
  operating_ = conditionsAt(time);
  PetscFunctionReturn(PETSC_SUCCESS);
}

bool DatabaseSwitcher::choosesByVelocity() const { return dynamic_cast<const MeasuredSchedule *>(rule_.get()) != nullptr; }

SwitchDecision DatabaseSwitcher::choiceFor(double u) const {
  const auto *schedule = dynamic_cast<const MeasuredSchedule *>(rule_.get());
  return schedule ? schedule->choiceFor(u) : active_;
}

OperatingConditions DatabaseSwitcher::conditionsFor(const SwitchDecision &choice, double u) const {
  OperatingConditions c = conditionsOf(choice);
  if (std::isfinite(u)) c.superficialVelocity = u;
  return c;
}

PetscErrorCode DatabaseSwitcher::load(const SwitchDecision &choice, std::shared_ptr<Database> *db) {
  PetscFunctionBeginUser;
  if (choice.partner < 0) PetscCall(set_->get(choice.database, db));
  else { // the two are dropped once the blend is made, unless somebody else holds them
    std::shared_ptr<Database> a, b;
    std::unique_ptr<Database> blend;
    PetscCall(set_->get(choice.database, &a));
    PetscCall(set_->get(choice.partner, &b));
    int lag = 0;
    if (pairByRecurrence) {
      const auto key = std::make_pair(choice.database, choice.partner);
      if (!lags.count(key)) PetscCall(pairingLag(*a, *b, &lags[key]));
      lag = lags[key];
    }
    PetscCall(blendDatabases(*a, *b, choice.weight, &blend, lag));
    *db = std::move(blend);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}


PetscErrorCode DatabaseSwitcher::record(double time, const SwitchDecision &from, double seconds) {
  char row[200];
  PetscFunctionBeginUser;
  ++switches;
  std::snprintf(row, sizeof row, "%.9g,%s,%s,%.10g,switch", time, choiceText(from).c_str(), choiceText(active_).c_str(),
                active_.trigger);
  PetscCall(csv->add(row));
  if (!quiet)
    PetscCall(PetscPrintf(comm, "Switched from database %s to %s at t = %g s by the %s rule (trigger %g); loaded "
                                "and set up in %.3g s\n",
                          choiceText(from).c_str(), choiceText(active_).c_str(), time, rule_->type().c_str(),
                          active_.trigger, seconds));
  PetscFunctionReturn(PETSC_SUCCESS);
}

SwitchDecision DatabaseSwitcher::savedChoice(const std::vector<double> &state) {
  if (state.size() < kSaved) return {};
  return {static_cast<int>(state[0]), state[3], static_cast<int>(state[1]), state[2]};
}

PetscErrorCode DatabaseSwitcher::appendSchedule(double t, double u) {
  PetscFunctionBeginUser;
  auto *measured = dynamic_cast<MeasuredSchedule *>(rule_.get());
  PetscCheck(measured, PETSC_COMM_SELF, PETSC_ERR_SUP,
             "the %s switching rule does not run the bed at a u_sup over time; -db_switch_type schedule or blend does",
             rule_->type().c_str());
  PetscCall(measured->appendSchedule(t, u));
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::vector<double> DatabaseSwitcher::saveState() const {
  const std::vector<double> file = csv ? csv->state() : std::vector<double>{};
  std::vector<double> out{static_cast<double>(active_.database), static_cast<double>(active_.partner),
                          active_.weight, active_.trigger, static_cast<double>(switches), warnedAt,
                          file.empty() ? -1.0 : file.front()};
  const auto words = rule_->saveState();
  out.insert(out.end(), words.begin(), words.end());
  return out;
}

PetscErrorCode DatabaseSwitcher::restoreState(const std::vector<double> &state) {
  PetscFunctionBeginUser;
  PetscCheck(state.size() >= kSaved, comm, PETSC_ERR_USER_INPUT, "the checkpoint's switching state is malformed");
  PetscCall(agreeOnStatus(comm, rule_->restoreState(std::vector<double>(state.begin() + kSaved, state.end()))));
  switches = static_cast<long>(state[4]);
  warnedAt = state[5];
  if (state[6] >= 0) PetscCall(csv->resume(state[6]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode DatabaseSwitcher::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer, "Databases: %d on one partition, switched by %s\n", set_->size(),
                                   rule_->describe().c_str()));
  PetscCall(PetscViewerASCIIPushTab(viewer));
  for (int i = 0; i < set_->size(); ++i)
    PetscCall(PetscViewerASCIIPrintf(viewer, "%d: %s, %d frames, recorded at u_sup %g m/s%s\n", i,
                                     set_->entry(i).path.c_str(), set_->entry(i).numFrames,
                                     set_->entry(i).conditions.superficialVelocity,
                                     i == active_.database || i == active_.partner ? " (active)" : ""));
  PetscCall(PetscViewerASCIIPrintf(viewer, "%d loads of a database, %.3g s in all; %d held now, at most %d at once\n",
                                   set_->numLoads(), set_->loadSeconds(), set_->numHeld(), set_->maxHeld()));
  for (const auto &[pair, lag] : lags) // blends paired by recurrence: frame k with the partner's k + lag
    PetscCall(PetscViewerASCIIPrintf(viewer, "blend of %d and %d paired by recurrence: frame k with frame k + %d of %d\n",
                                     pair.first, pair.second, lag, pair.second));
  PetscCall(PetscViewerASCIIPopTab(viewer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
