// Forecasts from the current state (docs/live.md, "Forecasts").
#include "run/forecast_monitor.hpp"
#include "run/find_operator.hpp"
#include "rcfd/granulation.hpp"
#include "base/checked_options.hpp"
#include "base/collective.hpp"
#include "base/number_rows.hpp"
#include "base/petsc_compat.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>

namespace rcfd {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// The granulator's rates of the moment (a live run changes them as it goes):
/// what the options made the members' operators with is the start's.
void holdRates(const Pipeline &from, const Pipeline &to) {
  if (auto *a = findOperator<FeedOperator>(from))
    if (auto *b = findOperator<FeedOperator>(to)) b->setFeed(a->feedRate(), a->feedShares());
  if (auto *a = findOperator<DischargeOperator>(from))
    if (auto *b = findOperator<DischargeOperator>(to)) b->setRate(a->dischargeRate());
  if (auto *a = findOperator<GrowthOperator>(from))
    if (auto *b = findOperator<GrowthOperator>(to)) b->setRate(a->growthRate(), a->transferFraction());
}

/// Mean and sample standard deviation of the finite values; their count.
void meanSpread(const std::vector<double> &v, double *mean, double *spread, int *count) {
  double s = 0.0, q = 0.0;
  int n = 0;
  for (double x : v)
    if (std::isfinite(x)) s += x, ++n;
  *mean = n ? s / n : kNaN;
  for (double x : v)
    if (std::isfinite(x)) q += (x - *mean) * (x - *mean);
  *spread = n > 1 ? std::sqrt(q / (n - 1)) : (n ? 0.0 : kNaN);
  *count = n;
}

/// A warning's columns from each member's time until it fires (NaN: not within the horizon): how
/// many members see it, after how long on average, the earliest.
void appendWarning(const std::vector<double> &times, std::vector<double> *row) {
  int n;
  double mean, spread, first = kNaN;
  meanSpread(times, &mean, &spread, &n);
  for (double w : times)
    if (std::isfinite(w) && !(w >= first)) first = w;
  row->push_back(n);
  row->push_back(mean);
  row->push_back(first);
}

} // namespace

ForecastMonitor::ForecastMonitor(const OperatorRegistry &operators, const PathRegistry &paths, const Pipeline &live,
                                 std::vector<std::string> pipeline, const FluidizationModel &fluidization,
                                 DatabaseSwitcher *switcher, const ScalarSet &scalars)
    : operators(operators), paths(paths), live(live), names(std::move(pipeline)), fluidization(fluidization),
      switcher(switcher), fixedDatabase(switcher == nullptr), liveScalars(scalars) {}

PetscErrorCode ForecastMonitor::setFromOptions(MPI_Comm c) {
  PetscFunctionBeginUser;
  comm = c;
  PetscOptionsBegin(c, nullptr, "Forecasts from the current state (docs/live.md)", "rcfd");
  PetscCall(checkedReal(PetscOptionsObject, "-forecast_every", "Simulated time between forecasts [s] (0: none)", &every,
                        kNonNegative));
  PetscCall(checkedReal(PetscOptionsObject, "-forecast_horizon", "How far each forecast looks ahead [s]", &horizon,
                        {0.0, 1e9, false, true, "a positive time in s"}));
  PetscCall(checkedInt(PetscOptionsObject, "-forecast_members", "Stitched paths per forecast", &members, 1, 10000));
  PetscCall(checkedInt(PetscOptionsObject, "-forecast_digits", "Significant digits of forecast.csv's numbers", &digits, 3,
                       17));
  PetscCall(checkedInt(PetscOptionsObject, "-forecast_seed", "Seed of the first member's path (the others s+1, ...)",
                       &seed, 0, 2000000000));
  char file[PETSC_MAX_PATH_LEN] = "";
  PetscBool given = PETSC_FALSE;
  PetscCall(PetscOptionsString("-forecast_schedule", "What-if conditions the members follow instead of holding the "
                               "latest (CSV as -live's, times from each forecast's start)", "", file, file, sizeof file,
                               &given));
  if (given) scheduleFile = file;
  PetscOptionsEnd();
  PetscFunctionReturn(PETSC_SUCCESS);
}

long ForecastMonitor::everySteps(double dt) const { return every > 0 ? std::max(1L, std::lround(every / dt)) : 0L; }

PetscErrorCode ForecastMonitor::setUp(const RunContext &run, const FractionState &state, const std::string &dir) {
  PetscFunctionBeginUser;
  const Vec3 &g = run.db.metadata().gravity;
  gravity = std::hypot(g[0], g[1], g[2]);
  PetscCall(layers.setUp(run.db));
  PetscCall(cog.setUp(run.db, run.fractions));
  // Each member's stitched path, made once: a forecast goes on along it from where the last one
  // left (a recurrence matrix per member, not per forecast).
  memberPaths.clear();
  for (PetscInt m = 0; m < members; ++m) {
    std::unique_ptr<FramePath> path;
    PetscCall(agreeOnStatus(comm, paths.create("random", &path)));
    path->setOptionsPrefix("forecast_path_");
    PetscCall(path->setFromOptions(comm));
    path->setSeed(static_cast<std::uint64_t>(seed + m));
    PetscCall(path->setUp(PathContext{run.db, true}));
    memberPaths.push_back(std::move(path));
  }
  if (!scheduleFile.empty()) PetscCall(readSchedule(run));
  moisture = -1;
  memberScalars.reset();
  if (state.numScalars() > 0) {
    for (int s = 0; s < state.numScalars(); ++s)
      if (state.scalarNames()[s] == "moisture") moisture = s;
    PetscCall(setUpScalars(run));
  }
  std::string header = "time_s,horizon_s,members,delta_z_mean_m,delta_z_spread_m,d32_bottom_mean_m,d32_bottom_spread_m,"
                       "umf_usup_mean,umf_usup_spread,warning_members,warning_in_mean_s,warning_in_first_s";
  labels.clear();
  if (findOperator<DischargeOperator>(live)) { // the product over the horizon
    header += ",product_mass_mean_kg,product_mass_spread_kg";
    for (int i = 0; i < run.fractions.size(); ++i) {
      labels.push_back(run.fractions.label(i));
      header += ",product_share_" + labels.back() + "_mean,product_share_" + labels.back() + "_spread";
    }
  }
  scalarLabels.clear();
  if (!labels.empty()) // the product's value of each scalar: its amount discharged over the mass
    for (const std::string &name : state.scalarNames()) {
      scalarLabels.push_back(name);
      header += ",product_" + name + "_mean,product_" + name + "_spread";
    }
  if (moisture >= 0) header += ",moisture_bottom_mean,moisture_bottom_spread";
  if (moisture >= 0 && wetThreshold > 0.0) header += ",wet_warning_members,wet_warning_in_mean_s,wet_warning_in_first_s";
  columns.clear();
  for (std::size_t at = 0; at <= header.size();) {
    const std::size_t comma = std::min(header.find(',', at), header.size());
    columns.push_back(header.substr(at, comma - at));
    at = comma + 1;
  }
  csv = std::make_unique<CsvSeries>(comm, dir + "/forecast.csv", header);
  PetscFunctionReturn(PETSC_SUCCESS);
}

int ForecastMonitor::column(const std::string &name) const {
  const auto at = std::find(columns.begin(), columns.end(), name);
  return at == columns.end() ? -1 : static_cast<int>(at - columns.begin());
}

PetscErrorCode ForecastMonitor::setUpScalars(const RunContext &run) {
  PetscFunctionBeginUser;
  memberScalars = std::make_unique<ScalarSet>();
  PetscCall(memberScalars->setFromOptions(comm));
  const ScalarSources &held = liveScalars.sources();
  // The spray zone wherever the run's or the what-if's spray may be on, even at a rate of 0 now.
  if (held.canSpray() && (held.followsSpray() || schedule.has(LiveInput::SprayRate))) memberScalars->sources().followSpray();
  PetscCall(memberScalars->setUp(run.db, run.fractions, run.solidDensity));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ForecastMonitor::readSchedule(const RunContext &run) {
  PetscFunctionBeginUser;
  PetscCall(schedule.readWhole(comm, "-forecast_schedule", scheduleFile, run.fractions));
  const std::string file = "-forecast_schedule " + scheduleFile + ": ";
  // The scalars' columns, as the live file's (docs/live.md): the members carry the run's scalars.
  const ScalarSources &sources = liveScalars.sources();
  PetscCheck(!schedule.has(LiveInput::SprayRate) || (liveScalars.size() > 0 && sources.canSpray()), comm,
             PETSC_ERR_USER_INPUT, "%sthe column spray_rate needs a scalar named moisture in -scalars (the liquid it "
             "adds, kg per kg solid)", file.c_str());
  PetscCheck(!schedule.has(LiveInput::GasTemperature) || (liveScalars.size() > 0 && sources.exchanges()), comm,
             PETSC_ERR_USER_INPUT, "%sthe column gas_temperature needs the scalars' exchange with the gas (-scalars "
             "temperature and -scalar_exchange_model gunn or constant)", file.c_str());
  const std::string missing = granulatorColumnWithoutOperator(schedule, live);
  PetscCheck(missing.empty(), comm, PETSC_ERR_USER_INPUT, "%s%s", file.c_str(), missing.c_str());
  // Two answers to "what is u_sup": -superficial_velocity wins over any other wherever the gas is resolved.
  PetscCheck(!schedule.has(LiveInput::SuperficialVelocity) || !std::isfinite(fluidization.given.superficialVelocity),
             comm, PETSC_ERR_USER_INPUT, "%sthe column u_sup and -superficial_velocity %g both give the forecast's u_sup; "
             "give it once", file.c_str(), fluidization.given.superficialVelocity);
  PetscFunctionReturn(PETSC_SUCCESS);
}

void ForecastMonitor::followSchedule(double t, const Pipeline &ops, OperatingConditions *gas) const {
  if (schedule.has(LiveInput::SuperficialVelocity)) gas->superficialVelocity = schedule.at(LiveInput::SuperficialVelocity, t);
  setGranulatorRates(schedule, t, ops);
  if (!memberScalars) return;
  ScalarSources &sources = memberScalars->sources();
  if (schedule.has(LiveInput::SprayRate)) sources.setSprayRate(schedule.at(LiveInput::SprayRate, t));
  if (schedule.has(LiveInput::GasTemperature)) sources.setGasTemperature(schedule.at(LiveInput::GasTemperature, t));
}

PetscErrorCode ForecastMonitor::switchMember(const SwitchDecision &choice, int pathFrame, const RunContext &run,
                                             const OperatingConditions &gas, Pipeline &ops, FractionState &state,
                                             std::shared_ptr<Database> *db) {
  PetscFunctionBeginUser;
  std::vector<std::vector<double>> kept; // what each operator keeps across a switch, as the run's
  for (const auto &op : ops.operators()) kept.push_back(op->saveState());
  char key[64];
  std::snprintf(key, sizeof key, "%d+%d@%.17g", choice.database, choice.partner, choice.partner < 0 ? 1.0 : choice.weight);
  std::shared_ptr<Database> &found = loaded[key]; // loaded once per forecast, whichever member comes first
  if (!found) PetscCall(switcher->load(choice, &found));
  *db = found;
  RunContext on{**db, run.fractions, run.solidDensity, &gas};
  on.numScalars = run.numScalars;
  on.scalarNames = run.scalarNames;
  for (std::size_t k = 0; k < ops.operators().size(); ++k) {
    PetscCall(ops.operators()[k]->setUp(on));
    PetscCall(ops.operators()[k]->restoreState(kept[k]));
  }
  // The scalars' sources hold the database (spray zone, layers, gas): set up on the new one as the
  // run's are (their rates kept; their u_sup follows the member's gas from its next step).
  if (memberScalars) PetscCall(memberScalars->setUp(**db, run.fractions, run.solidDensity));
  if (!remap) {
    remap = std::make_unique<CarryOperator>();
    PetscCall(remap->setKind(comm, "remap"));
  }
  PetscCall(remap->setUp(on));
  StepInfo jump;
  jump.jump = true;
  jump.frame = jump.nextFrame = pathFrame % (*db)->numFrames();
  PetscCall(remap->apply(jump, state));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ForecastMonitor::member(const MonitorContext &ctx, int m, Outcome *out) {
  const RunContext &run = ctx.run;
  const Database *db = &run.db; // the member's: another after its switches
  std::shared_ptr<Database> switched;
  const double dt = db->metadata().dtRec;
  const long steps = std::max(1L, std::lround(horizon / dt));
  PetscFunctionBeginUser;
  // Operators of its own from the run's options, continuing the run's saved state at its rates:
  // made once on one database; on a set, afresh for each member (the database in use may be another).
  if (!memberOps || !fixedDatabase) {
    memberOps = std::make_unique<Pipeline>();
    for (const auto &name : names) {
      std::unique_ptr<Operator> op;
      PetscCall(agreeOnStatus(comm, operators.create(name, &op)));
      PetscCall(memberOps->add(std::move(op)));
    }
    PetscCall(memberOps->setFromOptions(comm));
    PetscCall(memberOps->setUp(run));
    if (memberScalars && !fixedDatabase) // their sources on the database in use
      PetscCall(memberScalars->setUp(run.db, run.fractions, run.solidDensity));
  }
  Pipeline &ops = *memberOps;
  // The same options leave out the same operators at set-up: the run's and the member's lists match.
  PetscCheck(ops.operators().size() == live.operators().size(), comm, PETSC_ERR_PLIB,
             "A forecast member's pipeline has %zu operators, the run's %zu", ops.operators().size(),
             live.operators().size());
  for (std::size_t k = 0; k < ops.operators().size(); ++k)
    PetscCall(ops.operators()[k]->restoreState(live.operators()[k]->saveState()));
  holdRates(live, ops);
  FractionState state;
  PetscCall(state.create(db->layout(), run.fractions.size()));
  PetscCall(VecCopy(ctx.state.masses(), state.masses()));
  if (memberScalars) {
    PetscCall(state.createScalars(ctx.state.scalarNames()));
    PetscCall(VecCopy(ctx.state.amounts(), state.amounts()));
  }
  FramePath &path = *memberPaths[m];
  // Held: the gas of the moment (the drift's excess gas, the bottom layer's u_mf/u_sup), unless the
  // what-if schedule gives it.
  OperatingConditions gas = run.operatingConditions();
  OperatingConditions now = fluidization.resolve(gas);
  // The scalars' sources hold the run's conditions of the moment: the spray rate, the gas's inlet
  // temperature and the u_sup of its exchange; they follow the gas's u_sup where the run's do (a live
  // u_sup, a database set) or a what-if gives one.
  ScalarSources *sources = memberScalars ? &memberScalars->sources() : nullptr;
  const bool followVelocity = run.conditions != nullptr || schedule.has(LiveInput::SuperficialVelocity);
  if (sources) {
    const ScalarSources &held = liveScalars.sources();
    sources->setSprayRate(held.sprayRateNow());
    sources->setGasTemperature(held.gasInletTemperature());
    sources->setSuperficialVelocity(held.superficialVelocity());
  }
  const DischargeOperator *discharge = findOperator<DischargeOperator>(ops);
  const std::vector<double> dischargedBefore = discharge ? discharge->discharged() : std::vector<double>{};
  const std::vector<double> amountsBefore = discharge && sources ? discharge->dischargedAmounts() : std::vector<double>{};
  const bool watchWet = moisture >= 0 && wetThreshold > 0.0;
  // On a set whose rule chooses by u_sup, the member switches by its own: held, or the what-if's.
  const bool switches = switcher && switcher->choosesByVelocity();
  SwitchDecision choice = switcher ? switcher->active() : SwitchDecision{};
  const double heldVelocity = gas.superficialVelocity;
  int frame = ctx.frame, pathFrame = ctx.frame;
  double d32 = kNaN, umfUsup = kNaN, warning = kNaN, wet = kNaN, wetWarning = kNaN;
  std::vector<double> amounts; // the bottom layer's scalars
  std::vector<double> perLayer;
  StepInfo info;
  info.dt = dt;
  info.conditions = &gas;
  for (long s = 0; s < steps; ++s) {
    if (schedule.numRows() > 0) {
      followSchedule(s * dt, ops, &gas);
      now = fluidization.resolve(gas);
    }
    if (switches) { // as the run decides after each step, on the u_sup of the next one's start
      const double u = schedule.has(LiveInput::SuperficialVelocity) ? gas.superficialVelocity : heldVelocity;
      const SwitchDecision wanted = switcher->choiceFor(u);
      const bool change = !wanted.sameAs(choice);
      if (change) choice = wanted;
      gas = switcher->conditionsFor(choice, u);
      now = fluidization.resolve(gas);
      if (change) {
        PetscCall(switchMember(choice, pathFrame, run, gas, ops, state, &switched));
        db = switched.get();
        frame = pathFrame % db->numFrames();
      }
    }
    pathFrame = path.next();
    const int next = pathFrame % db->numFrames();
    info.step = ctx.step + s;
    info.time = ctx.time + s * dt;
    info.frame = frame;
    info.nextFrame = next;
    // The first step leaves the run's frame for the path's: a jump unless it follows.
    info.jump = (s == 0 ? next != frame + 1 : path.lastWasJump()) || (next == frame + 1 && !db->nextFollows(frame));
    PetscCall(ops.apply(info, state));
    if (sources) { // as the run's time loop: the sources after the operators
      if (followVelocity) sources->setSuperficialVelocity(gas.superficialVelocity);
      PetscCall(memberScalars->applySources(dt, next, state));
    }
    frame = next;
    PetscCall(layers.fractionMasses(state, &perLayer));
    d32 = layers::sauterDiameter(perLayer, 0, run.fractions);
    if (std::isfinite(d32)) // the same d32 on every rank (the layers are summed over all)
      PetscCall(collectively(PETSC_COMM_SELF, [&] {
        umfUsup = fluidization.minFluidizationVelocity(d32, run.solidDensity, now, gravity) / now.superficialVelocity;
      }, PETSC_ERR_USER_INPUT));
    if (!std::isfinite(warning) && umfUsup >= 1.0) warning = (s + 1) * dt;
    if (moisture >= 0 && (watchWet || s + 1 == steps)) { // the bottom layer's liquid over its solid
      PetscCall(layers.layerAmounts(state, 0, &amounts));
      const int nf = run.fractions.size();
      double water = 0.0, solid = 0.0;
      for (int i = 0; i < nf; ++i) water += amounts[moisture * nf + i], solid += perLayer[i];
      wet = solid > 0.0 ? water / solid : kNaN;
      // The run's wet-bottom warning (BottomLayerMonitor): wet while u_mf is near u_sup.
      if (watchWet && !std::isfinite(wetWarning) && wet > wetThreshold && umfUsup >= wetShare) wetWarning = (s + 1) * dt;
    }
  }
  BedSample end;
  PetscCall(cog.measure(ctx.time + steps * dt, state.masses(), db->alphaS(frame), run.solidDensity, &end));
  *out = Outcome{end.deltaZ, d32, umfUsup, warning, {}, wet, wetWarning};
  if (discharge) { // the product discharged over the horizon (global sums): its mass and size distribution
    std::vector<double> &product = out->product;
    const std::vector<double> after = discharge->discharged();
    double mass = 0.0;
    for (std::size_t i = 0; i < after.size(); ++i) mass += after[i] - dischargedBefore[i];
    product.push_back(mass);
    for (std::size_t i = 0; i < after.size(); ++i) product.push_back(mass > 0.0 ? (after[i] - dischargedBefore[i]) / mass : kNaN);
    if (sources) { // each scalar's value in it: its amount discharged over the horizon over the mass
      const std::vector<double> taken = discharge->dischargedAmounts();
      const std::size_t nf = after.size();
      for (std::size_t k = 0; k < scalarLabels.size(); ++k) {
        double amount = 0.0;
        for (std::size_t i = 0; i < nf; ++i) amount += taken[k * nf + i] - amountsBefore[k * nf + i];
        product.push_back(mass > 0.0 ? amount / mass : kNaN);
      }
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ForecastMonitor::sample(const MonitorContext &ctx) {
  PetscFunctionBeginUser;
  // Per answer, each member's value: Delta z, d32, u_mf/u_sup, the warning's time, the bottom
  // layer's moisture, the wet warning's time, then the product's (mass, shares, scalars).
  std::vector<double> dz, d32, ratio, warn, wet, wetWarn;
  std::vector<std::vector<double>> product;
  for (PetscInt m = 0; m < members; ++m) {
    Outcome out;
    PetscCall(member(ctx, static_cast<int>(m), &out));
    dz.push_back(out.deltaZ), d32.push_back(out.d32), ratio.push_back(out.umfUsup), warn.push_back(out.warning);
    wet.push_back(out.wetBottom), wetWarn.push_back(out.wetWarning);
    product.resize(out.product.size());
    for (std::size_t k = 0; k < out.product.size(); ++k) product[k].push_back(out.product[k]);
  }
  if (!fixedDatabase) memberOps.reset(); // made afresh by the next forecast's members, before the databases go
  loaded.clear(); // the databases members switched to: not held between forecasts
  if (switcher) switcher->set().dropUnused(); // the run holds only its own (docs/databases.md, "Memory")
  ++issued;
  std::vector<double> row{ctx.time, horizon, static_cast<double>(members)};
  int n;
  double mean, spread;
  const auto appendMean = [&](const std::vector<double> &v) {
    meanSpread(v, &mean, &spread, &n);
    row.push_back(mean);
    row.push_back(spread);
  };
  for (const auto *v : {&dz, &d32, &ratio}) appendMean(*v);
  appendWarning(warn, &row); // NaN: no member's bottom layer de-fluidizes within the horizon
  // What it costs is the run's summary's (monitors: forecast.csv).
  for (const auto &v : product) appendMean(v); // NaN shares and values where a member discharged nothing
  if (moisture >= 0) appendMean(wet);
  if (moisture >= 0 && wetThreshold > 0.0) appendWarning(wetWarn, &row); // NaN: not wet within the horizon
  PetscCall(csv->add(numberRow(row, static_cast<int>(digits))));
  latest = row;
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::vector<double> ForecastMonitor::saveState() const {
  const std::vector<double> file = csv->state();
  std::vector<double> out{file.empty() ? -1.0 : file[0], static_cast<double>(issued),
                          static_cast<double>(memberPaths.size())};
  for (const auto &path : memberPaths) { // 64-bit words as two 32-bit halves: doubles hold them exactly
    const std::vector<std::uint64_t> words = path->saveState();
    out.push_back(static_cast<double>(words.size()));
    for (std::uint64_t w : words) {
      out.push_back(static_cast<double>(w >> 32));
      out.push_back(static_cast<double>(w & 0xffffffffu));
    }
  }
  return out;
}

PetscErrorCode ForecastMonitor::restoreState(const std::vector<double> &state) {
  PetscFunctionBeginUser;
  if (state.empty()) PetscFunctionReturn(PETSC_SUCCESS); // not in the checkpoint's run: starts anew
  const char *bad = "The checkpoint's forecast state is malformed or was made with another -forecast_members";
  PetscCheck(state.size() >= 3 && state[2] == static_cast<double>(memberPaths.size()), PETSC_COMM_SELF,
             PETSC_ERR_FILE_UNEXPECTED, "%s", bad);
  if (state[0] >= 0) PetscCall(csv->resume(state[0]));
  issued = static_cast<long>(state[1]);
  std::size_t at = 3;
  for (const auto &path : memberPaths) {
    PetscCheck(at < state.size(), PETSC_COMM_SELF, PETSC_ERR_FILE_UNEXPECTED, "%s", bad);
    const std::size_t n = static_cast<std::size_t>(state[at++]);
    PetscCheck(at + 2 * n <= state.size(), PETSC_COMM_SELF, PETSC_ERR_FILE_UNEXPECTED, "%s", bad);
    std::vector<std::uint64_t> words(n);
    for (std::size_t k = 0; k < n; ++k, at += 2)
      words[k] = (static_cast<std::uint64_t>(state[at]) << 32) | static_cast<std::uint64_t>(state[at + 1]);
    PetscCall(path->restoreState(words));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ForecastMonitor::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer, "Forecast: every %g s, %d stitched members %g s ahead, seeds from %d, %s\n",
                                   every, static_cast<int>(members), horizon, static_cast<int>(seed),
                                   scheduleFile.empty() ? "holding the latest conditions"
                                                        : ("what-if conditions of " + scheduleFile).c_str()));
  if (memberScalars)
    PetscCall(PetscViewerASCIIPrintf(viewer, "  the members carry %d scalars and their sources\n", memberScalars->size()));
  if (switcher && switcher->choosesByVelocity())
    PetscCall(PetscViewerASCIIPrintf(viewer, "  each member switches databases by its own u_sup (the %s rule)\n",
                                     switcher->rule().type().c_str()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
