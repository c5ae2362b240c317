#include "run/run_impl.hpp"
#include "rcfd/database_set.hpp"
#include "rcfd/plugin.hpp"
#include "base/checked_options.hpp"
#include "state/initial_state.hpp"
#include "observable/scalar_mixing_monitor.hpp"
#include "observable/scalar_profiles_monitor.hpp"
#include "observable/scalar_monitor.hpp"
#include "base/petsc_compat.hpp"

#include "base/atomic_file.hpp"
#include "base/collective.hpp"

#include <algorithm>
#include <filesystem>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <sys/resource.h>

namespace rcfd {
namespace {

// Steps between looks at the wall clock for the periodic flush of the files
// (one reduction each: the slowest rank's clock decides for all).
constexpr long kFlushCheckSteps = 16;
// A live run without an end (-live_end, -t_end) ends by its stop file or a
// signal; its step count is this many, below the 1e12 any run may have.
constexpr double kLiveStepsWithoutEnd = 1e11;

std::vector<std::string> splitList(const std::string &text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

/// A MonitorFn in the monitor list.
class FunctionMonitor final : public Monitor {
public:
  explicit FunctionMonitor(MonitorFn fn) : fn(std::move(fn)) {}
  PetscErrorCode sample(const MonitorContext &ctx) override { return fn(ctx); }

private:
  MonitorFn fn;
};

} // namespace

Run::Run(MPI_Comm comm, const OperatorRegistry &operators)
    : impl(std::make_unique<Impl>(comm, operators)) {
  auto cog = std::make_unique<CogMonitor>();
  impl->cog = cog.get();
  impl->monitors.push_back({std::move(cog), 1, "cog.csv"});
}

Run::Run(MPI_Comm comm, const Registries &registries) : Run(comm, registries.operators, registries.paths) {
  impl->rules = &registries.switchRules;
  impl->monitorKinds = &registries.monitors;
}

Run::Run(MPI_Comm comm, const OperatorRegistry &operators, const PathRegistry &paths)
    : impl(std::make_unique<Impl>(comm, operators, paths)) {
  auto cog = std::make_unique<CogMonitor>();
  impl->cog = cog.get();
  impl->monitors.push_back({std::move(cog), 1, "cog.csv"});
}

Run::~Run() = default;

void Run::setDefaultOutputDirectory(const std::string &directory) { impl->outputDir = directory; }
void Run::setOutputDirectory(const std::string &directory) { impl->outputDir = directory; }
void Run::keepHistory(bool keep) { impl->keepHistory = keep; }
void Run::setQuiet(bool quiet) { impl->quiet = quiet ? PETSC_TRUE : PETSC_FALSE; }
bool Run::quiet() const { return impl->quiet == PETSC_TRUE; }
void Run::setWriteFields(bool write) { impl->writeFields = write ? PETSC_TRUE : PETSC_FALSE; }
void Run::useDatabase(std::shared_ptr<Database> database) { impl->db = std::move(database); }
void Run::useSwitchRules(const SwitchRuleRegistry &rules) { impl->rules = &rules; }
bool Run::switchesDatabases() const { return impl->switching != nullptr; }
bool Run::followsLive() const { return impl->live.enabled(); }

const Database &Run::database() const { return *impl->db; }
std::shared_ptr<Database> Run::sharedDatabase() const { return impl->db; }
const FractionSet &Run::fractions() const { return impl->set; }
RunContext Run::context() const { return impl->context(); }
const FractionState &Run::state() const { return impl->fstate; }
FractionState &Run::state() { return impl->fstate; }
Pipeline &Run::pipeline() { return impl->ops; }
const FramePath &Run::path() const { return *impl->path; }
const std::vector<BedSample> &Run::history() const { return impl->cog->samples(); }
const std::vector<int> &Run::framesUsed() const { return impl->frames; }
std::vector<double> Run::scalarSourceAccount() const { return impl->scalars.sources().account(); }
long Run::numSteps() const { return impl->steps; }
const std::string &Run::outputDirectory() const { return impl->outputDir; }

PetscErrorCode Run::setPathSeed(std::uint64_t seed) {
  PetscFunctionBeginUser;
  PetscCheck(impl->path && !impl->isSetUp, impl->comm, PETSC_ERR_ORDER,
             "Run::setPathSeed() goes between setFromOptions() and setUp()");
  PetscCheck(impl->path->hasSeed(), impl->comm, PETSC_ERR_USER_INPUT,
             "The %s path has no seed: several paths (-ensemble) need a stochastic -path_type "
             "such as random or markov",
             impl->path->type().c_str());
  impl->path->setSeed(seed);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Run::addMonitor(MonitorFn fn, long every, const std::string &name) {
  return addMonitor(std::make_unique<FunctionMonitor>(std::move(fn)), every, name);
}

PetscErrorCode Run::addMonitor(std::unique_ptr<Monitor> monitor, long every, const std::string &name) {
  PetscFunctionBeginUser;
  PetscCheck(every >= 0, impl->comm, PETSC_ERR_ARG_OUTOFRANGE,
             "Monitor %s: every must be >= 0 steps (0: first and last only), got %ld", name.c_str(), every);
  PetscCheck(!impl->solved, impl->comm, PETSC_ERR_ORDER, "Monitor %s added after Run::solve()", name.c_str());
  if (impl->isSetUp) PetscCall(monitor->setUp(impl->context(), impl->fstate, impl->outputDir));
  impl->monitors.push_back({std::move(monitor), every, name});
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Run::setFromOptions() {
  Impl &r = *impl;
  char text[PETSC_MAX_PATH_LEN];
  PetscBool set_;
  PetscFunctionBeginUser;
  PetscOptionsBegin(r.comm, nullptr, "rcfd run", "rcfd");
  text[0] = '\0';
  PetscCall(PetscOptionsString("-db", "Database file (HDF5), e.g. from rcfd synth; several, comma-separated, "
                               "on one mesh: switched by -db_switch_type (docs/databases.md)", "", "", text,
                               sizeof text, &set_));
  if (set_) r.dbPath = text;
  PetscCall(checkedReal(PetscOptionsObject, "-t_end",
                        "Simulated time to run [s] (default: one pass over the frames)", &r.tEnd,
                        {0.0, 1e15, false, true, "a positive time in s"}));
  PetscCall(PetscOptionsString("-output_dir", "Directory for results", "", r.outputDir.c_str(), text,
                               sizeof text, &set_));
  if (set_) r.outputDir = text;
  PetscCall(PetscOptionsString("-pipeline", "Operators applied each step, in order", "",
                               r.pipelineSpec.c_str(), text, sizeof text, &set_));
  if (set_) r.pipelineSpec = text;
  PetscCall(PetscOptionsBool("-fields", "Write HDF5 + XDMF fields", "", r.writeFields, &r.writeFields,
                             nullptr));
  PetscCall(checkedReal(PetscOptionsObject, "-fields_every",
                        "Simulated time between field outputs [s] (0: start and end only)", &r.fieldsEvery,
                        kNonNegative));
  PetscCall(PetscOptionsString("-init", "Initial state: mixed, layered or file", "",
                               r.initKind.c_str(), text, sizeof text, &set_));
  if (set_) r.initKind = text;
  PetscCall(PetscOptionsString("-init_file", "HDF5 file with dataset /masses [cells x fractions] in kg",
                               "", "", text, sizeof text, &set_));
  if (set_) r.initFile = text;
  PetscCall(checkedReal(PetscOptionsObject, "-checkpoint_every",
                        "Simulated time between checkpoints [s] (0: none)", &r.checkpointEvery, kNonNegative));
  PetscCall(PetscOptionsString("-checkpoint_file", "Checkpoint file (default: OUTPUT_DIR/checkpoint.h5)",
                               "", "", text, sizeof text, &set_));
  if (set_) r.checkpointFile = text;
  PetscCall(PetscOptionsString("-restart", "Continue from this checkpoint file", "", "", text,
                               sizeof text, &set_));
  if (set_) r.restartFile = text;
  PetscCall(checkedReal(PetscOptionsObject, "-solid_density",
                        "Particle density [kg/m^3] (default: the database's)", &r.solidDensity,
                        {0.0, 1e6, false, true, "a positive density in kg/m^3"}));
  PetscCall(PetscOptionsBool("-quiet", "No progress or summary output", "", r.quiet, &r.quiet, nullptr));
  PetscCall(PetscOptionsBool("-stop_at_steady", "End the run when a steady-state criterion is met (the "
                             "granulator's product, docs/granulation.md)", "", r.stopAtSteady, &r.stopAtSteady, nullptr));
  PetscCall(checkedReal(PetscOptionsObject, "-progress_interval", "Wall seconds between progress lines",
                        &r.progressInterval, kNonNegative));
  PetscOptionsEnd();
  PetscCall(PetscOptionsGetViewer(r.comm, nullptr, nullptr, "-run_view", r.viewer.put(), &r.viewFormat,
                                  nullptr));
  PetscBool help = PETSC_FALSE;
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-help", &help));
  PetscCheck(!r.dbPath.empty() || r.db || help, r.comm, PETSC_ERR_USER_INPUT,
             "No database given: pass -db FILE (make one with 'rcfd synth -o FILE')");
  PetscCheck(r.initKind == "mixed" || r.initKind == "layered" || r.initKind == "file", r.comm,
             PETSC_ERR_USER_INPUT, "-init %s is not known; use mixed, layered or file", r.initKind.c_str());
  PetscCheck(r.initKind != "file" || !r.initFile.empty(), r.comm, PETSC_ERR_USER_INPUT,
             "-init file needs -init_file FILE");
  PetscCheck(!r.outputDir.empty(), r.comm, PETSC_ERR_USER_INPUT,
             "-output_dir is empty; give the directory for the results (default rcfd-output)");
  PetscCall(Database::optionsFromCommandLine(&r.loadOptions));
  if (splitList(r.dbPath).size() > 1) { // several databases: a rule moves between them
    PetscCheck(!r.db, r.comm, PETSC_ERR_USER_INPUT,
               "-db names %zu databases, but this run was handed one loaded database (Run::useDatabase, as an "
               "ensemble's or a calibration's runs share one): a run on several reads and drops them as it "
               "switches, so it cannot share one; give it its own -db set and no loaded database",
               splitList(r.dbPath).size());
    r.switching = std::make_unique<DatabaseSwitcher>();
    PetscCall(r.switching->setFromOptions(r.comm, *r.rules));
  }
  PetscCall(FractionSet::fromOptions(r.comm, &r.set));

  const std::vector<std::string> names = splitList(r.pipelineSpec);
  PetscCheck(!names.empty() || help, r.comm, PETSC_ERR_USER_INPUT,
             "-pipeline is empty; name the operators to apply, e.g. shift,drift,carry");
  for (std::size_t i = 0; i < names.size(); ++i)
    for (std::size_t j = i + 1; j < names.size(); ++j)
      PetscCheck(names[i] != names[j], r.comm, PETSC_ERR_USER_INPUT,
                 "-pipeline names '%s' twice; an operator reads its options once, so apply it once",
                 names[i].c_str());
  for (const auto &name : names) {
    std::unique_ptr<Operator> op;
    PetscCall(agreeOnStatus(r.comm, r.registry.create(name, &op)));
    PetscCall(r.ops.add(std::move(op)));
  }
  PetscCall(r.ops.setFromOptions(r.comm));
  PetscCall(r.paths.createFromOptions(r.comm, &r.path));
  PetscCall(r.ledger.setFromOptions(r.comm));
  PetscCall(r.scalars.setFromOptions(r.comm));
  PetscCall(r.live.setFromOptions(r.comm));
  r.forecast = std::make_unique<ForecastMonitor>(r.registry, r.paths, r.ops, names, r.answers.fluidization(),
                                                 r.switching.get(), r.scalars);
  PetscCall(r.forecast->setFromOptions(r.comm));
  r.status = std::make_unique<StatusMonitor>(r.live.enabled()); // on by default beside a process
  PetscCall(r.status->setFromOptions(r.comm));
  // An operator's options per scalar, -<prefix>scalar_NAME (the feed's values), are read at its set-up,
  // where it learns the names; looked up now, so that the program's check of unused options knows them.
  for (const auto &op : r.ops.operators())
    for (const std::string &name : r.scalars.names()) {
      PetscBool given = PETSC_FALSE;
      PetscCall(PetscOptionsHasName(nullptr, op->optionsPrefix().c_str(), ("-scalar_" + name).c_str(), &given));
    }
  PetscCall(r.cog->setFromOptions(r.comm));
  r.monitors.front().every = r.cog->every();
  PetscCall(r.answers.setFromOptions(r.comm));
  PetscCall(r.registeredMonitorsFromOptions());
  // -path_view, -db_switch_view and -NAME_view are printed once set up; they are read now
  // (looked up, which marks them used), so that the program's check of unused options knows them.
  std::vector<std::string> viewed{r.path->optionsPrefix()};
  if (r.switching) viewed.push_back(r.switching->rule().optionsPrefix());
  for (const auto &m : r.registered) viewed.push_back(m.monitor->optionsPrefix());
  for (const auto &prefix : viewed) {
    PetscBool given = PETSC_FALSE;
    PetscCall(PetscOptionsHasName(nullptr, prefix.c_str(), "-view", &given));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

// -monitors NAME,...: each made by the registry with the prefix "NAME_",
// sampled every -NAME_every steps.
PetscErrorCode Run::Impl::registeredMonitorsFromOptions() {
  char text[PETSC_MAX_PATH_LEN] = "";
  PetscBool given = PETSC_FALSE;
  PetscFunctionBeginUser;
  const std::string help = "Registered monitors to add, comma-separated: " + monitorKinds->listing();
  PetscOptionsBegin(comm, nullptr, "Registered monitors", "rcfd");
  PetscCall(PetscOptionsString("-monitors", help.c_str(), "", text, text, sizeof text, &given));
  PetscOptionsEnd();
  registered.clear();
  if (!given) PetscFunctionReturn(PETSC_SUCCESS);
  for (const auto &name : splitList(text)) {
    for (const auto &e : registered)
      PetscCheck(e.name != name, comm, PETSC_ERR_USER_INPUT, "-monitors names '%s' twice", name.c_str());
    std::unique_ptr<Monitor> monitor;
    PetscCall(agreeOnStatus(comm, monitorKinds->create(name, &monitor)));
    monitor->setOptionsPrefix(name + "_");
    PetscInt every = 1;
    PetscOptionsBegin(comm, monitor->optionsPrefix().c_str(), "Registered monitor", "rcfd");
    PetscCall(checkedInt(PetscOptionsObject, "-every", "Steps between samples of this monitor (0: first and last only)",
                         &every, 0, 1000000000));
    PetscOptionsEnd();
    PetscCall(monitor->setFromOptions(comm));
    registered.push_back({std::move(monitor), static_cast<long>(every), name});
  }
  // The built-in mixing_index is also asked for by -mixing_index: one writer of mixing.csv.
  PetscBool mixing = PETSC_FALSE;
  PetscCall(PetscOptionsGetBool(nullptr, nullptr, "-mixing_index", &mixing, nullptr));
  for (const auto &e : registered)
    PetscCheck(!(mixing && e.name == "mixing_index"), comm, PETSC_ERR_USER_INPUT,
               "-monitors mixing_index and -mixing_index both ask for mixing.csv; give one of them");
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Run::setUp() {
  Impl &r = *impl;
  PetscFunctionBeginUser;
  PetscCheck(r.path, r.comm, PETSC_ERR_ORDER, "Run::setUp() needs Run::setFromOptions() first");
  if (r.live.enabled()) PetscCall(r.liveStart()); // a switching rule's u_sup comes from the file
  if (r.switching) { // one partition for all; the first database the rule chooses
    PetscCall(r.switching->open(r.comm, splitList(r.dbPath), r.loadOptions));
    PetscCall(r.switching->activate(r.switching->initial(), 0.0, &r.db));
    r.switching->set().dropUnused(); // a blend's two databases
  }
  if (!r.db) {
    std::unique_ptr<Database> loaded;
    PetscCall(Database::load(r.comm, r.dbPath, r.loadOptions, &loaded));
    r.db = std::move(loaded);
  }
  const double dt = r.dtRec = r.db->metadata().dtRec;
  if (r.solidDensity <= 0) r.solidDensity = r.db->metadata().solidDensity;
  if (r.live.enabled()) { // -live_end, else the case's -t_end, else no end: the stop file or a signal
    if (r.live.endTime() > 0) r.tEnd = r.live.endTime();
    else if (r.tEnd < 0) r.tEnd = kLiveStepsWithoutEnd * dt;
    PetscCall(r.liveFollow(0.0)); // the database's conditions with the file's u_sup
  }
  if (r.tEnd < 0) r.tEnd = std::max(1, r.db->numFrames() - 1) * dt; // one pass inside the database
  if (r.checkpointFile.empty()) r.checkpointFile = r.outputDir + "/checkpoint.h5";
  PetscCheck(r.tEnd / dt >= 0.5 && r.tEnd / dt <= 1e12, r.comm, PETSC_ERR_USER_INPUT,
             "-t_end %g s is %.3g steps of dt_rec = %g s; expected at least one step and at most 1e12",
             r.tEnd, r.tEnd / dt, dt);
  r.steps = std::lround(r.tEnd / dt);
  PetscCall(r.fstate.create(r.db->layout(), r.set.size()));
  if (r.scalars.size() > 0) {
    PetscCall(r.fstate.createScalars(r.scalars.names()));
    PetscCall(r.scalars.setUp(*r.db, r.set, r.solidDensity));
  }
  const RunContext ctx = r.context();
  PetscCall(r.ops.setUp(ctx));
  for (const auto &op : r.ops.operators())
    PetscCheck(r.scalars.size() == 0 || op->carriesScalars(), r.comm, PETSC_ERR_USER_INPUT,
               "-scalars: the operator '%s' of -pipeline does not carry scalars yet (shift, drift, dispersion, the "
               "carry, growth, feed and discharge do); run without -scalars or without '%s'", op->type().c_str(), op->type().c_str());
  PetscCall(r.path->setUp(PathContext{*r.db, r.quiet == PETSC_TRUE}));
  r.pathFrames = r.db->numFrames();
  PetscCall(collectively(r.comm, [&] { // before anything is written: one sentence, nothing made
    namespace fs = std::filesystem;
    if (fs::exists(r.outputDir) && !fs::is_directory(r.outputDir))
      throw std::invalid_argument("-output_dir '" + r.outputDir + "' is a file; expected a directory");
    if (fs::is_directory(r.checkpointFile))
      throw std::invalid_argument("-checkpoint_file '" + r.checkpointFile + "' is a directory; expected a file name");
  }, PETSC_ERR_USER_INPUT));
  PetscCall(makeDirectories(r.comm, r.outputDir));
  if (r.writeFields) { // right after the centres of gravity
    const long fieldSteps = r.fieldsEvery > 0 ? std::max(1L, std::lround(r.fieldsEvery / dt)) : 0L;
    r.monitors.insert(r.monitors.begin() + 1, {std::make_unique<FieldMonitor>(), fieldSteps, "fields"});
  }
  std::vector<Answers::Named> asked; // none unless the case asks
  PetscCall(r.answers.createMonitors(ctx, r.steps * dt, r.quiet == PETSC_TRUE, &asked));
  for (auto &a : asked) r.monitors.push_back({std::move(a.monitor), a.every, a.name});
  if (r.forecast && r.forecast->enabled()) { // forecasts from the state, after the answers of the same step
    const long every = r.forecast->everySteps(dt);
    r.forecast->setMoistureWarning(r.answers.moistureWarningThreshold(), r.answers.moistureWarningUmfShare());
    r.monitors.push_back({std::move(r.forecast), every, "forecast.csv"});
  }
  for (auto &m : r.registered) r.monitors.push_back(std::move(m)); // -monitors
  r.registered.clear();
  if (r.scalars.size() > 0) // scalars.csv, with the centres of gravity
    r.monitors.push_back({std::make_unique<ScalarMonitor>(r.scalars.names()), r.cog->every(), "scalars"});
  if (r.scalars.size() > 0 && r.scalars.mixingAsked()) // with them: scalar_mixing.csv
    r.monitors.push_back({std::make_unique<ScalarMixingMonitor>(r.scalars.names(), r.scalars.mixingTolerance()),
                          r.cog->every(), "scalar_mixing"});
  if (r.scalars.size() > 0 && r.scalars.profilesAsked()) { // scalar_profiles.csv, sampled as the answers are
    TimeWindow window;
    if (!r.scalars.profilesWindow().empty())
      window = TimeWindow{r.scalars.profilesWindow()[0], r.scalars.profilesWindow()[1]};
    window.resolve(r.steps * dt);
    r.monitors.push_back({std::make_unique<ScalarProfilesMonitor>(r.scalars.names(), window), r.cog->every(),
                          "scalar_profiles"});
  }
  if (!r.ops.conservesMass() && r.ops.accountsMass()) // the balance per fraction of what operators add
    r.monitors.push_back({std::make_unique<MassAccountMonitor>(r.ops), r.cog->every(), "mass_account.csv"});
  std::vector<OperatorMonitor> brought; // e.g. the discharge's product size distribution
  for (const auto &op : r.ops.operators()) PetscCall(op->monitors(ctx, &brought));
  for (auto &b : brought) r.monitors.push_back({std::move(b.monitor), b.every, b.name});
  if (r.status && r.status->enabled()) { // last: it shows the latest values of the monitors before it
    std::vector<const Monitor *> watched;
    for (const auto &m : r.monitors) watched.push_back(m.monitor.get());
    r.status->watch(std::move(watched));
    r.status->nameDatabase([&r] { return r.databaseInUse(); }); // after a switch, the new one
    r.monitors.push_back({std::move(r.status), r.cog->every(), "status.json"});
  }
  for (auto &m : r.monitors) PetscCall(m.monitor->setUp(ctx, r.fstate, r.outputDir));
  for (auto &m : r.monitors)
    if (!m.monitor->optionsPrefix().empty()) PetscCall(viewFromOptions(r.comm, m.monitor->optionsPrefix(), *m.monitor));
  PetscCall(viewFromOptions(r.comm, r.path->optionsPrefix(), *r.path));
  PetscCheck(!r.stopAtSteady || std::any_of(r.monitors.begin(), r.monitors.end(),
                                            [](const Impl::Entry &e) { return e.monitor->detectsSteadyState(); }),
             r.comm, PETSC_ERR_USER_INPUT,
             "-stop_at_steady needs a steady-state criterion, and -pipeline %s has none (the discharge operator's "
             "product.csv is one)", r.pipelineSpec.c_str());
  r.cog->keepSamples(r.keepHistory);
  if (r.switching) {
    std::vector<const Monitor *> monitors;
    for (const auto &m : r.monitors) monitors.push_back(m.monitor.get());
    PetscCall(r.switching->setUp(*r.db, r.set, r.solidDensity, r.answers.fluidization(), r.outputDir,
                                 r.quiet == PETSC_TRUE, monitors));
    PetscCall(viewFromOptions(r.comm, r.switching->rule().optionsPrefix(), r.switching->rule()));
    r.switchCarry = std::make_unique<CarryOperator>();
    PetscCall(r.switchCarry->setKind(r.comm, "remap"));
  }
  r.pathFile = std::make_unique<CsvSeries>(
      r.comm, r.outputDir + "/path.txt",
      "# frame of each step of this run; replay it with -path_type recorded -path_file FILE; " +
          r.path->describe()); // the layout of writePathFile
  std::vector<std::string> labels;
  for (int i = 0; i < r.set.size(); ++i) labels.push_back(r.set.label(i));
  r.jumps = std::make_unique<JumpsFile>(r.comm, r.outputDir, r.switching != nullptr, std::move(labels));
  PetscCall(r.jumpCog.setUp(*r.db, r.set)); // the databases of a set share the mesh and layout
  r.isSetUp = true;
  if (r.restartFile.empty()) {
    PetscCall(setInitialState(InitialState{r.initKind, r.initFile}, *r.db, r.set, r.solidDensity, r.fstate));
    if (r.scalars.size() > 0) PetscCall(r.scalars.setInitial(*r.db, r.fstate));
  } else PetscCall(r.readCheckpoint());
  if (r.viewer) {
    PetscCall(PetscViewerPushFormat(r.viewer, r.viewFormat));
    PetscCall(view(r.viewer));
    PetscCall(PetscViewerPopFormat(r.viewer));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

// A monitor is called at the initial state, after every `every`-th step and
// after the last one.
PetscErrorCode Run::Impl::callMonitors(long step, double time, int frame, bool last) {
  PetscFunctionBeginUser;
  const RunContext ctx = context();
  const MonitorContext m{step, time, frame, last, fstate, ctx, outputDir};
  for (auto &e : monitors)
    if (step == 0 || last || (e.every > 0 && step % e.every == 0)) {
      const double start = MPI_Wtime();
      // Sampling is collective: a monitor that writes on rank 0 alone in sample()
      // agrees on the status itself (fields, snapshots), so the steps of a run
      // pay no reduction for it.  Flushing writes on rank 0 and is agreed here.
      PetscCall(e.monitor->sample(m));
      e.seconds += MPI_Wtime() - start;
    }
  PetscFunctionReturn(PETSC_SUCCESS);
}

// Under -stop_at_steady: whether a detector due at this step (any detector:
// `anyDue`) finds its criterion met; one reduction where one was asked, so
// every rank agrees.
PetscErrorCode Run::Impl::steadyAt(long step, double time, int frame, bool anyDue, bool *steady) {
  PetscFunctionBeginUser;
  const RunContext ctx = context();
  const MonitorContext m{step, time, frame, false, fstate, ctx, outputDir};
  int met = 0;
  bool asked = false; // the same on every rank: no reduction at the steps no detector is due
  for (auto &e : monitors)
    if (e.monitor->detectsSteadyState() && (anyDue || (e.every > 0 && step % e.every == 0))) {
      bool found = false;
      PetscCall(e.monitor->steadyAt(m, &found));
      met |= found;
      asked = true;
    }
  if (asked) PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &met, 1, MPI_INT, MPI_LOR, comm));
  *steady = met;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Run::Impl::flushMonitors() {
  PetscFunctionBeginUser;
  PetscCall(pathFile->flush());
  PetscCall(jumps->flush());
  if (switching) PetscCall(switching->flush());
  for (auto &e : monitors) {
    const double start = MPI_Wtime();
    PetscCall(agreeOnStatus(comm, e.monitor->flush()));
    e.seconds += MPI_Wtime() - start;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Run::Impl::progress(long step, double time, bool last) {
  PetscFunctionBeginUser;
  if (quiet) PetscFunctionReturn(PETSC_SUCCESS);
  const double now = MPI_Wtime();
  if (!last && now - lastProgress < progressInterval) PetscFunctionReturn(PETSC_SUCCESS);
  lastProgress = now;
  const double elapsed = now - wallStart;
  const double rate = elapsed > 0 ? step / elapsed : 0.0;
  if (live.enabled()) { // no end to count down to; how far the file goes instead
    const double liveRate = elapsed > 0 ? (step - startStep) / elapsed : 0.0;
    PetscCall(PetscPrintf(comm, "  t = %8.3f s  step %ld  live file to %.6g s  %8.0f steps/s  %6.1f s simulated per wall s\n",
                          time, step, live.knownUntil(), liveRate, liveRate * db->metadata().dtRec));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  const double eta = rate > 0 ? (steps - step) / rate : 0.0;
  PetscCall(PetscPrintf(comm, "  t = %8.3f / %.3f s  step %ld/%ld  %8.0f steps/s  %6.1f s simulated per wall s  ETA %.1f s\n",
                        time, tEnd, step, steps, rate, rate * db->metadata().dtRec, eta));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// A step taken as a jump: the operators one by one (as Pipeline::apply), with
// the bed measured just before and just after the carry, against the frame
// the state is carried onto (at the step's end when no operator carries).
PetscErrorCode Run::Impl::applyAcrossJump(const StepInfo &info, BedSample *before, BedSample *after) {
  bool measured = false;
  PetscFunctionBeginUser;
  const Vec alpha = db->alphaS(info.nextFrame);
  const double t = info.time + info.dt;
  for (const auto &op : ops.operators()) {
    const bool carry = !measured && op->type() == "carry";
    if (carry) PetscCall(jumpCog.measure(t, fstate.masses(), alpha, solidDensity, before));
    PetscCall(op->apply(info, fstate));
    if (carry) PetscCall(jumpCog.measure(t, fstate.masses(), alpha, solidDensity, after));
    measured = measured || carry;
  }
  if (!measured) {
    PetscCall(jumpCog.measure(t, fstate.masses(), alpha, solidDensity, before));
    *after = *before;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The time loop of solve(), up to the path file; an error returns to solve(),
// which reports it in the output directory.
PetscErrorCode Run::Impl::march() {
  Impl &r = *this;
  PetscFunctionBeginUser;
  const double dt = r.db->metadata().dtRec;
  const bool conservative = r.ops.conservesMass();
  const bool ledgerOn = conservative || r.ops.accountsMass(); // mass changed on purpose is accounted
  if (ledgerOn && r.startStep == 0) PetscCall(r.ledger.start(r.fstate));
  std::vector<double> addedAmounts; // [scalar][fraction], by the operators that change mass on purpose
  if (r.scalars.size() > 0 && r.startStep == 0) PetscCall(r.scalars.startLedger(r.fstate));
  if (r.scalars.size() > 0 && r.startStep > 0) { // their restored ledgers: what the checkpoint's expected holds
    r.ops.addedAmounts(&addedAmounts);
    r.scalars.operatorsAddedSoFar(addedAmounts);
  }
  std::vector<double> added; // by the operators that change mass on purpose, since the start
  std::vector<double> expected; // what the ledger expects each fraction to hold at a step's start
  // The frame of the next step; after a restart the path stands on it.
  int frame = r.startStep == 0 ? r.path->next() : r.path->frame();
  r.lastStep = r.startStep;
  bool liveEnded = false;
  PetscCall(r.liveAdvance(r.startStep, &liveEnded)); // the rows of the first step, or the input's end
  PetscCall(r.liveFollow(r.startStep * dt));
  // A live run stopped by its stop file or a signal is interrupted, not finished: its monitors get
  // no final call (no row off their schedule), so its files are the start of the uninterrupted run's.
  if (r.startStep == 0) PetscCall(r.callMonitors(0, 0.0, r.dbFrame(frame), r.steps == 0 && !liveEnded));
  const long checkpointSteps =
      r.checkpointEvery > 0 ? std::max(1L, std::lround(r.checkpointEvery / dt)) : 0L;
  r.wallStart = r.lastProgress = MPI_Wtime();
  double lastFlush = r.wallStart;
  StepInfo info;
  info.dt = dt;
  bool wrapNoted = false, stop = false;
  if (r.stopAtSteady && r.startStep > 0) { // the checkpoint's run may have stopped there
    PetscCall(r.steadyAt(r.startStep, r.startStep * dt, r.dbFrame(frame), true, &stop));
    if (stop) {
      if (!r.quiet)
        PetscCall(PetscPrintf(r.comm, "Steady already at the checkpoint's t = %g s (-stop_at_steady): no steps to "
                                      "make; the output files are the checkpoint's\n", r.startStep * dt));
      r.steps = r.startStep;
    }
  }
  for (long s = r.startStep; s < r.steps; ++s) {
    info.step = s;
    info.time = s * dt;
    int next; // in the path's frame index
    bool pathJump;
    try {
      next = r.path->next();
      pathJump = r.path->lastWasJump();
    } catch (const std::out_of_range &) { // a recorded path ends with the run it came from
      next = (frame + 1) % r.pathFrames;
      pathJump = next != frame + 1;
    }
    info.frame = r.dbFrame(frame); // the active database's; the same with one database
    info.nextFrame = r.dbFrame(next);
    // A jump of the path, or the path steps on where the frames of the database in
    // use do not follow: it wraps (a database shorter than the path's), or a blend's
    // database wraps inside it (docs/databases.md, "Databases of different lengths").
    info.jump = pathJump || (next == frame + 1 && !r.db->nextFollows(info.frame));
    r.lastStep = s + 1;
    PetscCall(r.pathFile->add(std::to_string(frame)));
    if (r.keepHistory) r.frames.push_back(frame);
    const bool wraps = info.jump && info.nextFrame == 0; // not a blend's jump inside it
    if (wraps && !wrapNoted && r.path->type() == "replay") {
      wrapNoted = true;
      if (!r.quiet)
        PetscCall(PetscPrintf(r.comm,
                              "Note: the replay passed the database's last frame and wraps to frame "
                              "%d at t = %g s (a jump; -t_end is longer than the database; rows "
                              "after jumps are listed in %s/jumps.csv)\n",
                              info.nextFrame, (s + 1) * dt, r.outputDir.c_str()));
    }
    if (ledgerOn && !conservative && !r.ledger.reference().empty()) { // the bed's totals for the operators
      r.ops.addedMass(&added);
      expected = r.ledger.reference();
      for (size_t i = 0; i < expected.size() && i < added.size(); ++i) expected[i] += added[i];
      info.expectedTotals = &expected;
    }
    info.conditions = &r.context().operatingConditions(); // a schedule's or a live file's u_sup now
    if (info.jump) {
      BedSample before, after;
      PetscCall(r.applyAcrossJump(info, &before, &after));
      PetscCall(r.jumps->add(s + 1, (s + 1) * dt, info.frame, info.nextFrame,
                             r.switching ? r.switching->activeName() : std::string(), &before, &after));
    } else PetscCall(r.ops.apply(info, r.fstate));
    if (r.scalars.size() > 0) {
      // The exchange's gas (Gunn's Re, the plug-flow gas's flow) at the u_sup the run follows now, a live
      // file's or a schedule's; otherwise the case's or the database's, resolved at set-up.
      if (r.switching || r.liveVelocity) r.scalars.sources().setSuperficialVelocity(info.conditions->superficialVelocity);
      PetscCall(r.scalars.applySources(dt, r.dbFrame(next), r.fstate));
      r.ops.addedAmounts(&addedAmounts);
      r.scalars.advanceLedger(addedAmounts);
    }
    frame = next;
    const double t = (s + 1) * dt;
    if (r.live.enabled()) { // the conditions from t on; whether the input goes on past the next step
      PetscCall(r.liveFollow(t));
      PetscCall(r.liveAdvance(s + 1, &liveEnded));
    }
    if (r.stopAtSteady) PetscCall(r.steadyAt(s + 1, t, r.dbFrame(frame), false, &stop));
    if (ledgerOn && !conservative) r.ops.addedMass(&added);
    if (ledgerOn) {
      const double start = MPI_Wtime();
      PetscCall(r.ledger.check(s + 1, r.fstate, s + 1 == r.steps || stop, conservative ? nullptr : &added));
      if (r.scalars.size() > 0)
        PetscCall(r.scalars.checkLedger(s + 1, r.ledger.interval(), r.fstate, s + 1 == r.steps || stop));
      r.ledgerSeconds += MPI_Wtime() - start;
    }
    if (r.switching) PetscCall(r.followSwitches(s + 1, t, frame));
    PetscCall(r.callMonitors(s + 1, t, r.dbFrame(frame), (s + 1 == r.steps && !liveEnded) || stop));
    const bool liveLast = r.live.enabled() && s + 1 == r.steps; // restartable where it stopped
    if ((checkpointSteps && ((s + 1) % checkpointSteps == 0 || stop)) || liveLast) { // the files first: the checkpoint records their lengths
      PetscCall(r.flushMonitors());
      PetscCall(r.writeCheckpoint(s + 1));
      lastFlush = MPI_Wtime();
    }
    // Results so far survive an interruption: flushed every 10 s of wall time.
    // Flushing is collective, and the ranks' clocks differ, so they agree on it
    // (the slowest rank's clock) every kFlushCheckSteps steps instead of each reading
    // its own (which hung two ranks on a loaded machine).
    if ((s + 1) % kFlushCheckSteps == 0) {
      double waited = MPI_Wtime() - lastFlush;
      PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &waited, 1, MPI_DOUBLE, MPI_MAX, r.comm));
      if (waited > 10.0) {
        PetscCall(r.flushMonitors());
        lastFlush = MPI_Wtime();
      }
    }
    if (stop) { // the detector's step is the run's last
      if (!r.quiet)
        PetscCall(PetscPrintf(r.comm, "Stopped at t = %g s (step %ld): the steady-state criterion is met "
                                      "(-stop_at_steady)\n", t, s + 1));
      r.steps = s + 1;
      break;
    }
    PetscCall(r.progress(s + 1, t, false));
  }
  PetscCall(r.flushMonitors());
  PetscCall(r.jumps->finish());
  // figures: drawn by the CLI (rcfd run), not by the library
  PetscCall(r.progress(r.steps, r.steps * dt, true));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// A run that fails after it started says so in its output directory (the
// file FAILED: the sentence, the step and the time) and keeps what it had
// reported: the monitors' files are flushed.  A run that starts removes the
// FAILED of an earlier one.
PetscErrorCode Run::Impl::reportFailure(PetscErrorCode status) {
  PetscMPIInt rank;
  const char *generic = nullptr;
  char *specific = nullptr;
  PetscErrorMessage(status, &generic, &specific);
  const std::string why = specific && *specific ? specific : (generic ? generic : "unknown error");
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  const double t = lastStep * dtRec; // db may be gone: a switch that failed to load the next one
  (void)flushMonitors(); // best effort: the disk may be what failed
  if (rank == 0) {
    char where[160];
    std::snprintf(where, sizeof where, "rcfd run failed at step %ld of %ld (t = %.9g s): ", lastStep, steps, t);
    try {
      writeTextAtomically(outputDir + "/FAILED", where + why + "\n");
    } catch (const std::exception &) { // nowhere to say it but the error itself
    }
  }
  SETERRQ(comm, status, "%s", why.c_str()); // the first failure, not a later one while flushing
}

PetscErrorCode Run::solve() {
  Impl &r = *impl;
  PetscFunctionBeginUser;
  PetscCheck(r.isSetUp && !r.solved, r.comm, PETSC_ERR_ORDER,
             "Run::solve() needs Run::setUp() first and runs once");
  r.solved = true;
  PetscMPIInt rank;
  PetscCallMPI(MPI_Comm_rank(r.comm, &rank));
  if (rank == 0) std::remove((r.outputDir + "/FAILED").c_str()); // from an earlier run, if any
  std::vector<double> initialMass;
  PetscCall(r.fstate.totals(&initialMass));
  const PetscErrorCode marched = r.march();
  if (marched) PetscCall(r.reportFailure(marched));
  const double dt = r.db->metadata().dtRec;

  PetscCall(r.ops.viewRequested());
  std::vector<double> finalMass;
  PetscCall(r.fstate.totals(&finalMass));
  double worst = 0.0;
  for (size_t i = 0; i < finalMass.size(); ++i)
    if (initialMass[i] > 0) worst = std::max(worst, std::fabs(finalMass[i] / initialMass[i] - 1.0));
  double low;
  PetscCall(r.fstate.minimum(&low));
  struct rusage usage;
  getrusage(RUSAGE_SELF, &usage);
  double peakMb = usage.ru_maxrss / 1024.0; // Linux reports kB
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &peakMb, 1, MPI_DOUBLE, MPI_MAX, r.comm));
  if (!r.quiet) {
    const double wall = MPI_Wtime() - r.wallStart;
    const long taken = r.steps - r.startStep;
    PetscCall(PetscPrintf(r.comm,
                          "Done: %ld steps, %.4g s simulated in %.3g s wall (%.3g wall s per simulated s), peak memory %.0f MB per rank\n"
                          "  largest relative change of a fraction's mass: %.2e (round-off removed by the ledger: %.2e);"
                          " smallest cell mass: %.3g kg\n"
                          "  results: %s/cog.csv%s\n",
                          taken, taken * dt, wall, taken > 0 ? wall / (taken * dt) : 0.0, peakMb, worst,
                          r.ledger.largestCorrection(), low, r.outputDir.c_str(),
                          r.writeFields ? (", " + r.outputDir + "/fields.xmf").c_str() : ""));
    // What each monitor cost (rank 0's wall time, sampling and writing).
    std::string costs;
    double total = 0.0;
    char item[160];
    for (const auto &e : r.monitors) {
      std::snprintf(item, sizeof item, "%s%s %.3g s", costs.empty() ? "" : ", ", e.name.c_str(), e.seconds);
      costs += item;
      total += e.seconds;
    }
    PetscCall(PetscPrintf(r.comm, "  monitors: %.3g s of the wall (%s)\n", total, costs.c_str()));
    // And each operator (rank 0's wall time in apply(), waiting at its meetings included).
    costs.clear();
    total = 0.0;
    const auto &ops = r.ops.operators();
    const auto &opSeconds = r.ops.applySeconds();
    for (size_t k = 0; k < ops.size() && k < opSeconds.size(); ++k) {
      std::snprintf(item, sizeof item, "%s%s %.3g s", costs.empty() ? "" : ", ", ops[k]->type().c_str(), opSeconds[k]);
      costs += item;
      total += opSeconds[k];
    }
    PetscCall(PetscPrintf(r.comm, "  operators: %.3g s of the wall (%s); mass ledger %.3g s\n", total, costs.c_str(),
                          r.ledgerSeconds));
    if (r.scalars.size() > 0) PetscCall(r.scalars.report(r.fstate, r.steps * dt)); // its account is since the start
    if (r.switching)
      PetscCall(PetscPrintf(r.comm, "  databases: %ld switches, %d loads in %.3g s (%.3g s per load), at most %d held at once%s\n",
                            r.switching->numSwitches(), r.switching->set().numLoads(), r.switching->set().loadSeconds(),
                            r.switching->set().loadSeconds() / std::max(1, r.switching->set().numLoads()),
                            r.switching->set().maxHeld(),
                            std::isfinite(r.switching->extrapolatingSince()) ? "; rcfd extrapolated (switches.csv)" : ""));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Run::view(PetscViewer viewer) const {
  const Impl &r = *impl;
  PetscFunctionBeginUser;
  PetscCall(r.db->view(viewer));
  if (r.switching) PetscCall(r.switching->view(viewer));
  PetscCall(r.set.view(viewer));
  PetscCall(r.ops.view(viewer));
  PetscCall(PetscViewerASCIIPrintf(viewer, "Run: %.4g s simulated in %ld steps, initial state %s, output in %s\n",
                                   r.tEnd, r.steps, r.restartFile.empty() ? r.initKind.c_str() : r.restartFile.c_str(),
                                   r.outputDir.c_str()));
  PetscCall(r.path->view(viewer));
  PetscCall(r.answers.view(viewer));
  std::string list;
  for (const auto &e : r.monitors)
    list += (list.empty() ? "" : ", ") + e.name + " (every " + std::to_string(e.every) + " steps)";
  PetscCall(PetscViewerASCIIPrintf(viewer, "Monitors: %s\n", list.c_str()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
