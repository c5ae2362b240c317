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

} // namespace

ForecastMonitor::ForecastMonitor(const OperatorRegistry &operators, const PathRegistry &paths, const Pipeline &live,
                                 std::vector<std::string> pipeline, const FluidizationModel &fluidization,
                                 bool fixedDatabase)
    : operators(operators), paths(paths), live(live), names(std::move(pipeline)), fluidization(fluidization),
      fixedDatabase(fixedDatabase) {}

PetscErrorCode ForecastMonitor::setFromOptions(MPI_Comm c) {
  PetscFunctionBeginUser;
  comm = c;
  PetscOptionsBegin(c, nullptr, "Forecasts from the current state (docs/live.md)", "rcfd");
  PetscCall(checkedReal(PetscOptionsObject, "-forecast_every", "Simulated time between forecasts [s] (0: none)", &every,
                        kNonNegative));
  PetscCall(checkedReal(PetscOptionsObject, "-forecast_horizon", "How far each forecast looks ahead [s]", &horizon,
                        {0.0, 1e9, false, true, "a positive time in s"}));
  PetscCall(checkedInt(PetscOptionsObject, "-forecast_members", "Stitched paths per forecast", &members, 1, 10000));
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
  PetscCheck(state.numScalars() == 0, comm, PETSC_ERR_USER_INPUT,
             "-forecast_every with -scalars: the forecast's members do not carry scalars yet; run without one of them");
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
  csv = std::make_unique<CsvSeries>(comm, dir + "/forecast.csv", header);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ForecastMonitor::readSchedule(const RunContext &run) {
  PetscFunctionBeginUser;
  PetscCall(schedule.readWhole(comm, "-forecast_schedule", scheduleFile, run.fractions));
  const std::string file = "-forecast_schedule " + scheduleFile + ": ";
  for (auto [q, name] : {std::make_pair(LiveInput::SprayRate, "spray_rate"),
                         std::make_pair(LiveInput::GasTemperature, "gas_temperature")})
    PetscCheck(!schedule.has(q), comm, PETSC_ERR_USER_INPUT,
               "%sthe column %s drives the scalars, which a forecast's members do not carry; leave it out",
               file.c_str(), name);
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
}

PetscErrorCode ForecastMonitor::member(const MonitorContext &ctx, int m, std::vector<double> *out) {
  const RunContext &run = ctx.run;
  const Database &db = run.db;
  const double dt = db.metadata().dtRec;
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
  PetscCall(state.create(db.layout(), run.fractions.size()));
  PetscCall(VecCopy(ctx.state.masses(), state.masses()));
  FramePath &path = *memberPaths[m];
  // Held: the gas of the moment (the drift's excess gas, the bottom layer's u_mf/u_sup), unless the
  // what-if schedule gives it.
  OperatingConditions gas = run.operatingConditions();
  OperatingConditions now = fluidization.resolve(gas);
  const DischargeOperator *discharge = findOperator<DischargeOperator>(ops);
  const std::vector<double> dischargedBefore = discharge ? discharge->discharged() : std::vector<double>{};
  int frame = ctx.frame;
  double d32 = kNaN, umfUsup = kNaN, warning = kNaN;
  std::vector<double> perLayer;
  StepInfo info;
  info.dt = dt;
  info.conditions = &gas;
  for (long s = 0; s < steps; ++s) {
    if (schedule.numRows() > 0) {
      followSchedule(s * dt, ops, &gas);
      now = fluidization.resolve(gas);
    }
    const int next = path.next() % db.numFrames();
    info.step = ctx.step + s;
    info.time = ctx.time + s * dt;
    info.frame = frame;
    info.nextFrame = next;
    // The first step leaves the run's frame for the path's: a jump unless it follows.
    info.jump = (s == 0 ? next != frame + 1 : path.lastWasJump()) || (next == frame + 1 && !db.nextFollows(frame));
    PetscCall(ops.apply(info, state));
    frame = next;
    PetscCall(layers.fractionMasses(state, &perLayer));
    d32 = layers::sauterDiameter(perLayer, 0, run.fractions);
    if (std::isfinite(d32)) // the same d32 on every rank (the layers are summed over all)
      PetscCall(collectively(PETSC_COMM_SELF, [&] {
        umfUsup = fluidization.minFluidizationVelocity(d32, run.solidDensity, now, gravity) / now.superficialVelocity;
      }, PETSC_ERR_USER_INPUT));
    if (!std::isfinite(warning) && umfUsup >= 1.0) warning = (s + 1) * dt;
  }
  BedSample end;
  PetscCall(cog.measure(ctx.time + steps * dt, state.masses(), db.alphaS(frame), run.solidDensity, &end));
  *out = {end.deltaZ, d32, umfUsup, warning};
  if (discharge) { // the product discharged over the horizon (global sums): its mass and size distribution
    const std::vector<double> after = discharge->discharged();
    double mass = 0.0;
    for (std::size_t i = 0; i < after.size(); ++i) mass += after[i] - dischargedBefore[i];
    out->push_back(mass);
    for (std::size_t i = 0; i < after.size(); ++i) out->push_back(mass > 0.0 ? (after[i] - dischargedBefore[i]) / mass : kNaN);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ForecastMonitor::sample(const MonitorContext &ctx) {
  PetscFunctionBeginUser;
  // Per answer (Delta z, d32, u_mf/u_sup, the warning's time, then the product's), each member's value.
  std::vector<std::vector<double>> answers;
  for (PetscInt m = 0; m < members; ++m) {
    std::vector<double> out;
    PetscCall(member(ctx, static_cast<int>(m), &out));
    answers.resize(out.size());
    for (std::size_t k = 0; k < out.size(); ++k) answers[k].push_back(out[k]);
  }
  const std::vector<double> &dz = answers[0], &d32 = answers[1], &ratio = answers[2], &warn = answers[3];
  ++issued;
  std::vector<double> row{ctx.time, horizon, static_cast<double>(members)};
  int n;
  double mean, spread, first = kNaN;
  for (const auto *v : {&dz, &d32, &ratio}) {
    meanSpread(*v, &mean, &spread, &n);
    row.push_back(mean);
    row.push_back(spread);
  }
  meanSpread(warn, &mean, &spread, &n);
  for (double w : warn)
    if (std::isfinite(w) && !(w >= first)) first = w;
  row.push_back(n);
  row.push_back(mean); // NaN: no member's bottom layer de-fluidizes within the horizon
  row.push_back(first); // what it costs is the run's summary's (monitors: forecast.csv)
  for (std::size_t k = 4; k < answers.size(); ++k) { // the product: NaN shares where a member discharged nothing
    meanSpread(answers[k], &mean, &spread, &n);
    row.push_back(mean);
    row.push_back(spread);
  }
  PetscCall(csv->add(numberRow(row)));
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
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
