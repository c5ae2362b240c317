// The answers' options and the monitors they ask for (src/observable/answers.hpp).
#include "observable/answers.hpp"
#include "base/petsc_compat.hpp"

#include "base/checked_options.hpp"
#include "base/collective.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace rcfd {

std::string plain(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

void TimeWindow::resolve(double tEnd) {
  if (std::isnan(begin)) {
    begin = std::max(0.0, tEnd - 1.0);
    end = tEnd;
  }
}

bool TimeWindow::contains(double t) const {
  const double slack = 1e-9 * std::max(1.0, std::fabs(end));
  return t >= begin - slack && t <= end + slack;
}

PetscErrorCode LayerSampler::masses(const MonitorContext &ctx, const std::vector<double> **perLayer) {
  PetscFunctionBeginUser;
  if (ctx.step != cachedStep || ctx.time != cachedTime) {
    PetscCall(layers.fractionMasses(ctx.state, &cached));
    cachedStep = ctx.step;
    cachedTime = ctx.time;
  }
  *perLayer = &cached;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode LayerSampler::amounts(const MonitorContext &ctx, const std::vector<double> **perLayer) {
  PetscFunctionBeginUser;
  if (ctx.step != cachedAmountStep || ctx.time != cachedAmountTime) {
    const int na = ctx.state.numScalars() * ctx.state.numFractions();
    PetscCall(layers.fractionMasses(ctx.state.amounts(), na, &cachedAmounts));
    cachedAmountStep = ctx.step;
    cachedAmountTime = ctx.time;
  }
  *perLayer = &cachedAmounts;
  PetscFunctionReturn(PETSC_SUCCESS);
}

namespace {

/// Reads "t0,t1" into a window; refuses other counts and t0 > t1.
// Inside a PetscOptionsBegin block, whose PetscOptionsObject it takes.
PetscErrorCode windowOption(PetscOptionItems *PetscOptionsObject, MPI_Comm comm, const char *name, const char *help,
                            TimeWindow *w) {
  PetscReal v[2] = {0.0, 0.0};
  PetscInt n = 2;
  PetscBool set = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(checkedRealArray(PetscOptionsObject, name, help, v, &n, &set));
  if (!set) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCheck(n == 2 && v[0] <= v[1] && v[0] >= 0, comm, PETSC_ERR_USER_INPUT,
             "%s takes two times t0,t1 in seconds with 0 <= t0 <= t1", name);
  w->begin = v[0];
  w->end = v[1];
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

PetscErrorCode Answers::setFromOptions(MPI_Comm c) {
  char text[PETSC_MAX_PATH_LEN];
  PetscBool set = PETSC_FALSE;
  std::string correlation = fluidization_.correlation.name; // -umf_correlation
  PetscFunctionBeginUser;
  comm = c;
  PetscOptionsBegin(comm, nullptr, "Answers: profiles, halves, bottom layer, mixing, bed dynamics (docs/answers.md)",
                    "rcfd");
  PetscCall(PetscOptionsInt("-observables_every", "Steps between samples of the answers' monitors", "", every,
                            &every, nullptr));
  PetscCall(PetscOptionsBool("-profiles", "Write profiles.csv: vertical profiles averaged over a window", "",
                             profiles, &profiles, nullptr));
  PetscCall(windowOption(PetscOptionsObject, comm, "-profiles_window", "Window t0,t1 [s] of the profiles (default: the last second)",
                         &profilesWindow));
  PetscCall(PetscOptionsBool("-halves", "Write halves.csv: size distribution of the bottom and top halves", "",
                             halves, &halves, nullptr));
  PetscCall(windowOption(PetscOptionsObject, comm, "-halves_window", "Window t0,t1 [s] of the halves (default: the last second)",
                         &halvesWindow));
  PetscCall(PetscOptionsString("-halves_split", "Split the halves at the mass-median layer or at a height [m]",
                               "", "median", text, sizeof text, &set));
  if (set && std::string(text) != "median") {
    char *end = nullptr;
    splitHeight = std::strtod(text, &end);
    PetscCheck(end != text && *end == '\0' && std::isfinite(splitHeight), comm, PETSC_ERR_USER_INPUT,
               "-halves_split takes median or a height in metres, not '%s'", text);
  }
  PetscCall(PetscOptionsBool("-bottom_layer", "Write bottom.csv: Sauter diameter of the bottom layer, u_mf, warning",
                             "", bottom, &bottom, nullptr));
  PetscCall(checkedReal(PetscOptionsObject, "-moisture_warning",
                        "Warn when the bottom layer's moisture (a scalar named moisture) passes this [kg/kg] while "
                        "the bed is near de-fluidization by size (0: no warning)", &moistureWarning, kNonNegative));
  PetscCall(checkedReal(PetscOptionsObject, "-moisture_warning_umf_share",
                        "Near de-fluidization for the moisture warning: u_mf of the bottom layer at least this share "
                        "of u_sup", &moistureUmfShare, kPositive));
  PetscCall(checkedReal(PetscOptionsObject, "-moisture_umf_coefficient",
                        "kappa of the bottom layer's u_mf raised by its moisture X (a scalar named moisture): "
                        "u_mf (1 + kappa X), fitted to the material (0: u_mf by size alone)", &moistureUmf,
                        kNonNegative));
  PetscCall(PetscOptionsString("-umf_correlation", "Minimum fluidization correlation", "", correlation.c_str(),
                               text, sizeof text, &set));
  if (set) correlation = text;
  PetscCall(PetscOptionsBool("-mixing_index", "Write mixing.csv: Lacey's index of each fraction", "", mixing,
                             &mixing, nullptr));
  PetscCall(PetscOptionsBool("-bed_dynamics", "Write bed_dynamics.csv: mean z_CoG and Delta z_CoG", "", dynamics,
                             &dynamics, nullptr));
  PetscReal times[64] = {0.0};
  PetscInt nt = 64;
  PetscBool snapshots = PETSC_FALSE;
  PetscCall(checkedRealArray(PetscOptionsObject, "-snapshots_times", "Times [s] of mid-plane snapshots", times,
                             &nt, &snapshots));
  if (snapshots) snapshotTimes.assign(times, times + nt);
  PetscCheck(!snapshots || nt >= 1, comm, PETSC_ERR_USER_INPUT, "-snapshots_times needs at least one time in seconds");
  PetscOptionsEnd();
  PetscCheck(every >= 1, comm, PETSC_ERR_USER_INPUT, "-observables_every must be at least 1 step, got %d",
             (int)every);
  PetscCall(collectively(comm, [&] { fluidization_.correlation = findUmfCorrelation(correlation); },
                         PETSC_ERR_USER_INPUT));
  for (double t : snapshotTimes)
    PetscCheck(t >= 0, comm, PETSC_ERR_USER_INPUT, "-snapshots_times: %g s is before the start of the run", t);
  PetscCall(OperatingConditions::fromOptions(comm, &fluidization_.given));
  PetscCall(zones.setFromOptions(comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Answers::createMonitors(const RunContext &run, double tEnd, bool quiet, std::vector<Named> *out) {
  PetscFunctionBeginUser;
  // Conditions: the case's value, else the database's (the one in use), else the default.
  used = fluidization_.resolve(run.operatingConditions(), sources);
  const double value[3] = {used.superficialVelocity, used.gasDensity, used.gasKinematicViscosity};

  for (TimeWindow *w : {&profilesWindow, &halvesWindow}) {
    const bool given_ = !std::isnan(w->begin);
    w->resolve(tEnd);
    PetscCheck(!given_ || w->begin <= tEnd * (1 + 1e-12), comm, PETSC_ERR_USER_INPUT,
               "The %s window %s,%s s begins after the run's end at %s s (-t_end)",
               w == &profilesWindow ? "-profiles" : "-halves", plain(w->begin).c_str(), plain(w->end).c_str(),
               plain(tEnd).c_str());
  }
  for (double t : snapshotTimes)
    PetscCheck(t <= tEnd * (1 + 1e-12), comm, PETSC_ERR_USER_INPUT,
               "-snapshots_times: %s s is after the run's end at %s s (-t_end)", plain(t).c_str(), plain(tEnd).c_str());
  if (!zones.all().empty()) PetscCall(zones.setUp(run.db.mesh(), run.db.layout(), run.db.metadata().gravity));

  std::shared_ptr<LayerSampler> sampler;
  if (profiles || halves || bottom || dynamics) {
    sampler = std::make_shared<LayerSampler>();
    PetscCall(sampler->setUp(run.db));
  }
  if (profiles) out->push_back({std::make_unique<ProfilesMonitor>(sampler, profilesWindow), every, "profiles.csv"});
  if (halves)
    out->push_back({std::make_unique<HalvesMonitor>(sampler, halvesWindow, splitHeight), every, "halves.csv"});
  if (bottom) {
    if (!quiet)
      PetscCall(PetscPrintf(comm,
                            "Operating conditions: u_sup = %g m/s (%s), gas density %g kg/m^3 (%s), gas kinematic "
                            "viscosity %g m^2/s (%s); u_mf by %s\n",
                            value[0], sources[0].c_str(), value[1], sources[1].c_str(), value[2],
                            sources[2].c_str(), fluidization_.correlation.citation.c_str()));
    PetscCheck(run.solidDensity > value[1], comm, PETSC_ERR_USER_INPUT,
               "u_mf needs a particle density (%s kg/m^3) above the gas density (%s kg/m^3, -gas_density)",
               plain(run.solidDensity).c_str(), plain(value[1]).c_str());
  {
    auto monitor = std::make_unique<BottomLayerMonitor>(sampler, fluidization_, &zones, quiet);
    monitor->setMoistureWarning(moistureWarning, moistureUmfShare);
    monitor->setMoistureUmf(moistureUmf);
    out->push_back({std::move(monitor), every, "bottom.csv"});
  }
  }
  if (mixing) out->push_back({std::make_unique<MixingMonitor>(), every, "mixing.csv"});
  if (dynamics) out->push_back({std::make_unique<BedDynamicsMonitor>(sampler, quiet), every, "bed_dynamics.csv"});
  if (!snapshotTimes.empty()) out->push_back({std::make_unique<SnapshotMonitor>(snapshotTimes), 1, "snapshots"});
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Answers::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  if (bottom)
    PetscCall(PetscViewerASCIIPrintf(viewer,
                                     "Operating conditions: u_sup %g m/s (%s), rho_g %g kg/m^3 (%s), nu %g m^2/s "
                                     "(%s); u_mf correlation %s\n",
                                     used.superficialVelocity, sources[0].c_str(), used.gasDensity,
                                     sources[1].c_str(), used.gasKinematicViscosity, sources[2].c_str(),
                                     fluidization_.correlation.name.c_str()));
  if (profiles)
    PetscCall(PetscViewerASCIIPrintf(viewer, "Profiles over %g to %g s\n", profilesWindow.begin, profilesWindow.end));
  if (halves)
    PetscCall(PetscViewerASCIIPrintf(viewer, "Halves over %g to %g s, split at %s\n", halvesWindow.begin,
                                     halvesWindow.end,
                                     std::isnan(splitHeight) ? "the mass-median layer"
                                                             : (std::to_string(splitHeight) + " m").c_str()));
  if (!zones.all().empty()) PetscCall(zones.view(viewer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
