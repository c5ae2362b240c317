// The contract of every extension point (docs/extending.md), checked on every
// registered built-in of every point -- operators, size laws, carry kinds,
// path rules, switching rules, monitors -- the same way:
//  1. registered by name: the registry knows it and makes an object whose
//     type() is that name; an unknown name is refused with one sentence
//     listing the known names, a taken or malformed name cannot be added;
//  2. options read with its prefix: given another prefix, -help lists none of
//     its options under the default prefix (it does not hard-code it);
//  3. view printed: -<prefix>view ascii:FILE writes a non-empty FILE;
//  4. setUp is re-entrant: set up twice, it gives the same numbers (state
//     after steps, frames, decisions, file bytes) as set up once.
// Runs at 1 and 2 ranks.  usage: test_extension_contract DATA_DIR (with small.h5)
#include "check.hpp"
#include "fraction_sets.hpp"
#include "registry_helpers.hpp"
#include "scoped_options.hpp"
#include "base/petsc_compat.hpp"

#include "rcfd/plugin.hpp"
#include "state/initial_state.hpp"

#include <cstdarg>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

using namespace rcfd;

namespace {

std::string dir;
int counter = 0;
std::map<std::string, int> checked; // point -> built-ins checked

bool contains(const std::string &text, const std::string &part) { return text.find(part) != std::string::npos; }

// -help text of PETSc's options, captured instead of printed.
std::string helpText;
PetscErrorCode captureHelp(MPI_Comm, const char format[], ...) {
  char line[4096];
  va_list args;
  va_start(args, format);
  std::vsnprintf(line, sizeof line, format, args);
  va_end(args);
  helpText += line;
  return PETSC_SUCCESS;
}

// Option names printed by -help: the first word of lines "  -name <...>: help".
std::vector<std::string> helpOptions(const std::string &text) {
  std::vector<std::string> out;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    const auto start = line.find_first_not_of(' ');
    if (start == std::string::npos || line[start] != '-') continue;
    out.push_back(line.substr(start + 1, line.find_first_of(" <:", start) - start - 1));
  }
  return out;
}

// 2: with prefix `other`, setFromOptions lists no option under `usual`.
template <typename Object> void readsWithItsPrefix(Object &object, const std::string &usual, const std::string &other) {
  object.setOptionsPrefix(other);
  helpText.clear();
  {
    ScopedOptions help("-help");
    auto saved = PetscHelpPrintf;
    PetscHelpPrintf = captureHelp;
    const PetscErrorCode code = object.setFromOptions(PETSC_COMM_WORLD);
    PetscHelpPrintf = saved;
    RCFD_CHECK(code == PETSC_SUCCESS);
  }
  int own = 0, hardcoded = 0;
  for (const auto &name : helpOptions(helpText)) {
    if (name.rfind(other, 0) == 0) ++own;
    if (!usual.empty() && name.rfind(usual, 0) == 0) {
      ++hardcoded;
      std::fprintf(stderr, "%s: option -%s read without its prefix %s\n", object.type().c_str(), name.c_str(),
                   other.c_str());
    }
  }
  RCFD_CHECK(hardcoded == 0);
  PetscPrintf(PETSC_COMM_WORLD, "  %-14s %d options under its prefix\n", object.type().c_str(), own);
}

// 3: -<prefix>view ascii:FILE writes the object's view.
template <typename Object> void viewPrinted(const Object &object) {
  const std::string file = dir + "/view_" + std::to_string(counter++) + ".txt";
  {
    ScopedOptions view("-" + object.optionsPrefix() + "view ascii:" + file);
    PetscCallAbort(PETSC_COMM_WORLD, viewFromOptions(PETSC_COMM_WORLD, object.optionsPrefix(), object));
  }
  MPI_Barrier(PETSC_COMM_WORLD);
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  RCFD_CHECK(!text.str().empty());
}

struct Bed {
  std::unique_ptr<Database> db;
  FractionSet set = rcfd::test::fractionSet({1.0e-3, 1.8e-3, 3.0e-3}, {0.3, 0.3, 0.4});
  double rho = 2500.0;
  RunContext ctx() const { return RunContext{*db, set, rho}; }
};

// Options a built-in needs to do something on the small bed.
const std::string kZones = "-zones spray,feed,discharge -zone_spray_box 0.06,0.14,0,0.05,0.15,0.25 "
                           "-zone_feed_box 0,0.04,0,0.05,0,0.07 -zone_discharge_box 0.16,0.2,0,0.05,0,0.07 ";
const std::map<std::string, std::string> kNeeds = {
    {"growth", kZones + "-growth_rate 2"},
    {"feed", kZones + "-feed_rate 4 -feed_mass_shares 0.2,0.3,0.5"},
    {"discharge", kZones + "-discharge_rate 20"},
    {"dispersion", "-dispersion_coefficient 1e-4"},
};

// Masses after `steps` steps of `op` (jumps every 4th step) from the mixed state.
std::vector<double> stepped(const Bed &bed, Operator &op, int steps) {
  FractionState st;
  PetscCallAbort(PETSC_COMM_WORLD, st.create(bed.db->layout(), bed.set.size()));
  PetscCallAbort(PETSC_COMM_WORLD, setInitialState(InitialState{}, *bed.db, bed.set, bed.rho, st));
  const int K = bed.db->numFrames();
  for (int s = 0; s < steps; ++s) {
    StepInfo step;
    step.step = s;
    step.time = s * bed.db->metadata().dtRec;
    step.dt = bed.db->metadata().dtRec;
    step.frame = (7 * s) % K;
    step.jump = s % 4 == 3;
    step.nextFrame = step.jump ? (7 * s + 11) % K : (step.frame + 1) % K;
    PetscCallAbort(PETSC_COMM_WORLD, op.apply(step, st));
  }
  const PetscScalar *m;
  PetscInt n;
  PetscCallAbort(PETSC_COMM_WORLD, VecGetLocalSize(st.masses(), &n));
  PetscCallAbort(PETSC_COMM_WORLD, VecGetArrayRead(st.masses(), &m));
  std::vector<double> out(m, m + n);
  PetscCallAbort(PETSC_COMM_WORLD, VecRestoreArrayRead(st.masses(), &m));
  return out;
}

// 4 for an operator (a size law through drift, a carry kind through carry):
// set up twice and once, the same masses after 12 steps, bit for bit.
void operatorTwice(const Bed &bed, const OperatorRegistry &registry, const std::string &name,
                   const std::string &options, bool *printedView) {
  ScopedOptions given(options);
  std::vector<double> result[2];
  for (int times : {1, 2}) {
    auto op = created(registry, name);
    PetscCallAbort(PETSC_COMM_WORLD, op->setFromOptions(PETSC_COMM_WORLD));
    if (!op->needed(bed.ctx())) {
      PetscPrintf(PETSC_COMM_WORLD, "  %-14s not needed by the small bed with '%s'\n", name.c_str(), options.c_str());
      RCFD_CHECK(false); // every built-in is given options that make it act
      return;
    }
    for (int k = 0; k < times; ++k) PetscCallAbort(PETSC_COMM_WORLD, op->setUp(bed.ctx()));
    if (times == 2 && !*printedView) {
      viewPrinted(*op);
      *printedView = true;
    }
    result[times - 1] = stepped(bed, *op, 12);
  }
  RCFD_CHECK(result[0] == result[1]);
}

void operators(const Bed &bed, const OperatorRegistry &registry) {
  for (const auto &name : registry.names()) {
    auto op = created(registry, name);
    RCFD_CHECK(op->type() == name && op->optionsPrefix() == name + "_");
    readsWithItsPrefix(*op, name + "_", "c" + std::to_string(counter++) + "_");
    const auto need = kNeeds.find(name);
    bool viewed = false;
    operatorTwice(bed, registry, name, need == kNeeds.end() ? "" : need->second, &viewed);
    ++checked["operator"];
  }
}

void sizeLaws(const Bed &bed, const OperatorRegistry &registry) {
  for (const auto &name : registry.sizeLaws().names()) {
    auto law = created(registry.sizeLaws(), name);
    RCFD_CHECK(law->type() == name);
    readsWithItsPrefix(*law, "drift_size_law_", "c" + std::to_string(counter++) + "_size_law_");
    law->setOptionsPrefix("drift_size_law_");
    PetscCallAbort(PETSC_COMM_WORLD, law->setFromOptions(PETSC_COMM_WORLD));
    viewPrinted(*law);
    bool viewed = true;
    operatorTwice(bed, registry, "drift", "-drift_size_law " + name + " -drift_kd 0.01", &viewed);
    ++checked["size law"];
  }
}

void carryKinds(const Bed &bed, const OperatorRegistry &registry) {
  for (const auto &name : registry.carryKinds().names()) {
    auto kind = created(registry.carryKinds(), name);
    RCFD_CHECK(kind->type() == name);
    readsWithItsPrefix(*kind, "carry_", "c" + std::to_string(counter++) + "_");
    bool viewed = false; // the kind's view is the carry's (-carry_view)
    operatorTwice(bed, registry, "carry", "-carry_type " + name, &viewed);
    ++checked["carry kind"];
  }
}

void paths(const Bed &bed, const PathRegistry &registry) {
  // recorded needs a file of frames: an earlier run's path.txt
  const std::string file = dir + "/frames.txt";
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0) std::ofstream(file) << "# frames\n3\n4\n5\n9\n10\n";
  MPI_Barrier(PETSC_COMM_WORLD);
  const std::map<std::string, std::string> needs = {{"recorded", "-path_file " + file}};
  for (const auto &name : registry.names()) {
    std::unique_ptr<FramePath> path = created(registry, name);
    RCFD_CHECK(path->type() == name && path->optionsPrefix() == "path_");
    readsWithItsPrefix(*path, "path_", "c" + std::to_string(counter++) + "_");
    const auto need = needs.find(name);
    ScopedOptions given(need == needs.end() ? "" : need->second);
    std::vector<int> frames[2];
    for (int times : {1, 2}) {
      auto p = created(registry, name);
      PetscCallAbort(PETSC_COMM_WORLD, p->setFromOptions(PETSC_COMM_WORLD));
      for (int k = 0; k < times; ++k) PetscCallAbort(PETSC_COMM_WORLD, p->setUp(PathContext{*bed.db, true}));
      if (times == 2) viewPrinted(*p);
      const int steps = name == "recorded" ? 5 : 200; // the file holds 5 frames
      for (int s = 0; s < steps; ++s) frames[times - 1].push_back(p->next());
    }
    RCFD_CHECK(frames[0] == frames[1]);
    ++checked["path rule"];
  }
}

void switchRules(const SwitchRuleRegistry &registry) {
  std::vector<OperatingConditions> dbs(3);
  for (int i = 0; i < 3; ++i) dbs[i].superficialVelocity = 0.8 + 0.2 * i;
  const std::map<std::string, std::string> needs = {
      {"schedule", "-db_switch_schedule 0:0.8,1:1.0,2:1.2"},
      {"blend", "-db_switch_schedule 0:0.8,1:1.1,2:1.2"},
      {"state", "-db_switch_quantity inventory_d32 -db_switch_thresholds 1.5e-3,2e-3"},
      {"markov", "-db_switch_interval 0.25 -db_switch_seed 3"}};
  for (const auto &name : registry.names()) {
    auto rule = created(registry, name);
    RCFD_CHECK(rule->type() == name && rule->optionsPrefix() == "db_switch_");
    const auto need = needs.find(name);
    ScopedOptions given(need == needs.end() ? "" : need->second);
    readsWithItsPrefix(*rule, "db_switch_", "c" + std::to_string(counter++) + "_");
    std::vector<double> decisions[2];
    for (int times : {1, 2}) {
      auto r = created(registry, name);
      PetscCallAbort(PETSC_COMM_WORLD, r->setFromOptions(PETSC_COMM_WORLD));
      for (int k = 0; k < times; ++k) PetscCallAbort(PETSC_COMM_WORLD, r->setUp(SwitchContext{PETSC_COMM_WORLD, dbs}));
      if (times == 2) viewPrinted(*r);
      SwitchDecision active = r->initial();
      for (long s = 1; s <= 120; ++s) {
        SwitchSignals signals;
        signals.step = s;
        signals.time = 0.025 * s;
        signals.inventoryD32 = 1e-3 + 1.5e-3 * (0.5 + 0.5 * std::sin(0.1 * s));
        active = r->decide(active, signals);
        decisions[times - 1].insert(decisions[times - 1].end(),
                                    {double(active.database), double(active.partner), active.weight});
      }
    }
    RCFD_CHECK(decisions[0] == decisions[1]);
    ++checked["switching rule"];
  }
}

void monitors(const Bed &bed, const MonitorRegistry &registry) {
  for (const auto &name : registry.names()) {
    auto monitor = created(registry, name);
    RCFD_CHECK(monitor->type() == name);
    readsWithItsPrefix(*monitor, name + "_", "c" + std::to_string(counter++) + "_");
    std::string bytes[2];
    for (int times : {1, 2}) {
      auto m = created(registry, name);
      m->setOptionsPrefix(name + "_");
      PetscCallAbort(PETSC_COMM_WORLD, m->setFromOptions(PETSC_COMM_WORLD));
      const std::string out = dir + "/monitor_" + name + "_" + std::to_string(times);
      PetscCallAbort(PETSC_COMM_WORLD, makeDirectories(PETSC_COMM_WORLD, out));
      FractionState st;
      PetscCallAbort(PETSC_COMM_WORLD, st.create(bed.db->layout(), bed.set.size()));
      PetscCallAbort(PETSC_COMM_WORLD, setInitialState(InitialState{"layered", ""}, *bed.db, bed.set, bed.rho, st));
      const RunContext ctx = bed.ctx();
      for (int k = 0; k < times; ++k) PetscCallAbort(PETSC_COMM_WORLD, m->setUp(ctx, st, out));
      if (times == 2) viewPrinted(*m);
      for (long s = 0; s < 3; ++s)
        PetscCallAbort(PETSC_COMM_WORLD, m->sample(MonitorContext{s, 0.01 * s, 0, s == 2, st, ctx, out}));
      PetscCallAbort(PETSC_COMM_WORLD, m->flush());
      MPI_Barrier(PETSC_COMM_WORLD);
      for (const auto &entry : std::filesystem::directory_iterator(out)) {
        std::ifstream in(entry.path());
        std::stringstream text;
        text << in.rdbuf();
        bytes[times - 1] += entry.path().filename().string() + ":" + text.str();
      }
    }
    RCFD_CHECK(!bytes[0].empty() && bytes[0] == bytes[1]);
    ++checked["monitor"];
  }
}

// 1 beyond the built-ins: names are checked, and an unknown one is one sentence.
void names(const Registries &builtins) {
  OperatorRegistry registry = OperatorRegistry::withBuiltins();
  const OperatorFactory none = [] { return std::unique_ptr<Operator>(); };
  {
    ErrorCapture error;
    RCFD_CHECK(registry.add("drift", none, "again") == PETSC_ERR_ARG_WRONG);
    RCFD_CHECK(contains(error.message(), "Cannot register the operator 'drift': the name is taken"));
  }
  for (const char *bad : {"", "two words", "a,b", "9lives", "-x"}) {
    ErrorCapture error;
    RCFD_CHECK(registry.add(bad, none, "bad") == PETSC_ERR_ARG_WRONG);
    RCFD_CHECK(contains(error.message(), "a name is a letter followed by letters, digits or '_'"));
  }
  {
    ErrorCapture error;
    std::unique_ptr<FramePath> path;
    RCFD_CHECK(builtins.paths.create("stich", &path) == PETSC_ERR_USER_INPUT && !path);
    RCFD_CHECK(error.message() == "-path_type: unknown path 'stich'; known paths: markov, quarter, random, recorded, "
                                  "replay");
  }
  {
    ErrorCapture error;
    std::unique_ptr<Monitor> monitor;
    RCFD_CHECK(builtins.monitors.create("mixing", &monitor) == PETSC_ERR_USER_INPUT);
    RCFD_CHECK(error.message() == "-monitors: unknown monitor 'mixing'; known monitors: mixing_index");
  }
}

} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  {
    RCFD_CHECK(argc >= 2);
    const std::string data = argv[1];
    PetscMPIInt size;
    PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
    dir = data + "/contract_np" + std::to_string(size);
    PetscCall(makeDirectories(PETSC_COMM_WORLD, dir));
    Bed bed;
    PetscCall(Database::load(PETSC_COMM_WORLD, data + "/small.h5", DatabaseLoadOptions{}, &bed.db));
    const Registries builtins = Registries::withBuiltins();
    operators(bed, builtins.operators);
    sizeLaws(bed, builtins.operators);
    carryKinds(bed, builtins.operators);
    paths(bed, builtins.paths);
    switchRules(builtins.switchRules);
    monitors(bed, builtins.monitors);
    names(builtins);
    PetscPrintf(PETSC_COMM_WORLD, "checked: %d operators, %d size laws, %d carry kinds, %d path rules, "
                                  "%d switching rules, %d monitors\n",
                checked["operator"], checked["size law"], checked["carry kind"], checked["path rule"],
                checked["switching rule"], checked["monitor"]);
    RCFD_CHECK(checked["operator"] == 7 && checked["size law"] == 5 && checked["carry kind"] == 3 &&
               checked["path rule"] == 5 && checked["switching rule"] == 4 && checked["monitor"] == 1);
  }
  const int result = RCFD_TEST_RESULT();
  PetscCall(PetscFinalize());
  return result;
}
