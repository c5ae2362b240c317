#include "analysis/batched_replay.hpp"
#include "base/petsc_compat.hpp"

#include "rcfd/drift.hpp"

#include <algorithm>
#include <cctype>
#include <sstream>
#include <stdexcept>

namespace rcfd {

struct BatchedReplay::Group {
  std::unique_ptr<Run> run;
  std::vector<Operator *> after; // the pipeline's operators after the shift
  MassLedger ledger;
  CogMonitor cog;                // with a directory: cog.csv and the samples
  CentreOfGravity measure;       // without one: the samples only
  std::vector<BedSample> samples;
  std::string directory;
};

BatchedReplay::BatchedReplay(MPI_Comm comm, const OperatorRegistry &registry) : comm(comm), registry(registry) {}
BatchedReplay::~BatchedReplay() = default;

bool BatchedReplay::batchable(Run &run, std::string *why) {
  const auto &ops = run.pipeline().operators();
  PetscBool restart = PETSC_FALSE, steady = PETSC_FALSE;
  (void)PetscOptionsHasName(nullptr, nullptr, "-restart", &restart);
  (void)PetscOptionsHasName(nullptr, nullptr, "-stop_at_steady", &steady);
  if (run.switchesDatabases()) *why = "the runs switch between several databases";
  else if (ops.empty() || ops.front()->type() != "shift") *why = "the shift is not the pipeline's first operator";
  else if (!run.pipeline().conservesMass()) *why = "an operator of the pipeline adds or removes mass";
  else if (run.state().numScalars() > 0) *why = "the runs carry scalars (-scalars)";
  else if (restart) *why = "the runs restart from a checkpoint";
  else if (steady) *why = "the runs stop at a steady state of their own";
  else return true;
  return false;
}

// A candidate's objects read the command line's options with the
// candidate's own over them: a copy of the options database, pushed while
// they read, so that the command line's are never changed.  Each option the
// candidate gives must be read.
PetscErrorCode BatchedReplay::withOptions(MPI_Comm comm, const std::string &options,
                                          const std::function<PetscErrorCode()> &read) {
  PetscOptions own = nullptr;
  PetscFunctionBeginUser;
  if (options.empty()) {
    PetscCall(read());
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  char *all = nullptr; // the command line's options, as "-name value ..." (values without blanks)
  PetscCall(PetscOptionsGetAll(nullptr, &all));
  PetscCall(PetscOptionsCreate(&own));
  PetscCall(PetscOptionsInsertString(own, all));
  PetscCall(PetscFree(all));
  PetscCall(PetscOptionsInsertString(own, options.c_str()));
  PetscCall(PetscOptionsPush(own));
  const PetscErrorCode status = read();
  PetscCall(PetscOptionsPop());
  if (status) {
    PetscCall(PetscOptionsDestroy(&own));
    PetscCall(status);
  }
  std::istringstream words(options);
  for (std::string w; words >> w;) {
    if (w.size() < 2 || w[0] != '-' || !std::isalpha(static_cast<unsigned char>(w[1]))) continue; // a value
    if (w == "-db") PetscCall(PetscOptionsDestroy(&own));
    PetscCheck(w != "-db", comm, PETSC_ERR_USER_INPUT,
               "The candidate options '%s' name -db, but the candidates share one loaded database: give -db on "
               "the command line and run a calibration per database", options.c_str());
    PetscBool used = PETSC_FALSE;
    PetscCall(PetscOptionsUsed(own, w.c_str() + 1, &used)); // stored without the dash
    if (!used) PetscCall(PetscOptionsDestroy(&own));
    PetscCheck(used, comm, PETSC_ERR_USER_INPUT,
               "The candidate option %s (of '%s') is read by none of the run's objects; check its spelling",
               w.c_str(), options.c_str());
  }
  PetscCall(PetscOptionsDestroy(&own));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BatchedReplay::solveAlone(const Candidate &candidate, Run &run) const {
  PetscFunctionBeginUser;
  if (database) run.useDatabase(database);
  PetscCall(withOptions(comm, candidate.options, [&]() -> PetscErrorCode {
    PetscFunctionBeginUser;
    PetscCall(run.setFromOptions());
    run.setOutputDirectory(candidate.outputDirectory);
    run.setQuiet(true);
    run.keepHistory(true);
    run.setWriteFields(false);
    if (candidate.configure) PetscCall(candidate.configure(run));
    PetscCall(run.setUp());
    PetscFunctionReturn(PETSC_SUCCESS);
  }));
  PetscCall(run.solve());
  PetscFunctionReturn(PETSC_SUCCESS);
}

// A drift scaled by agitation is given the batch's field of its measure
// instead of making its own (a drift given one already keeps it).
PetscErrorCode BatchedReplay::shareAgitation(Run &run) {
  PetscFunctionBeginUser;
  if (!database) PetscFunctionReturn(PETSC_SUCCESS); // loaded by the first candidate's run
  for (const auto &op : run.pipeline().operators()) {
    auto *drift = dynamic_cast<DriftOperator *>(op.get());
    if (!drift || drift->agitationField() || drift->agitationOption() == "none") continue;
    std::shared_ptr<const AgitationField> &field = fields[drift->agitationOption()];
    if (!field) {
      auto made = std::make_shared<AgitationField>();
      AgitationMeasure measure;
      PetscCall(parseAgitationMeasure(drift->agitationOption(), &measure));
      PetscCall(made->setUp(*database, measure));
      field = made;
    }
    drift->useAgitation(field);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BatchedReplay::setUpGroup(const Candidate &candidate, Group *g) {
  PetscFunctionBeginUser;
  g->run = registries ? std::make_unique<Run>(comm, *registries) : std::make_unique<Run>(comm, registry);
  g->run->setDefaultOutputDirectory("rcfd-calibrate");
  if (database) g->run->useDatabase(database);
  g->directory = candidate.outputDirectory;
  PetscCall(withOptions(comm, candidate.options, [&]() -> PetscErrorCode {
    PetscFunctionBeginUser;
    PetscCall(g->run->setFromOptions());
    if (!g->directory.empty()) g->run->setOutputDirectory(g->directory);
    g->run->setQuiet(true);
    g->run->setWriteFields(false);
    if (candidate.configure) PetscCall(candidate.configure(*g->run));
    PetscCall(shareAgitation(*g->run));
    PetscCall(g->run->setUp());
    PetscCall(g->ledger.setFromOptions(comm));
    PetscCall(g->cog.setFromOptions(comm));
    PetscFunctionReturn(PETSC_SUCCESS);
  }));
  std::string why;
  PetscCheck(batchable(*g->run, &why), comm, PETSC_ERR_USER_INPUT,
             "These replays cannot run as one batched state: %s; run them one by one (rcfd calibrate "
             "-calibrate_batch false)", why.c_str());
  const auto &ops = g->run->pipeline().operators();
  for (std::size_t k = 1; k < ops.size(); ++k) g->after.push_back(ops[k].get());
  if (g->directory.empty()) PetscCall(g->measure.setUp(g->run->database(), g->run->fractions()));
  else PetscCall(g->cog.setUp(g->run->context(), g->run->state(), g->directory));
  g->cog.keepSamples(true);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BatchedReplay::solve(const std::vector<Candidate> &candidates) {
  FractionSet set;
  PetscFunctionBeginUser;
  PetscCall(FractionSet::fromOptions(comm, &set));
  histories.assign(candidates.size(), {});
  finals.assign(candidates.size(), {});
  batchCount = 0;
  const int most = std::min(columnsPerBatch, kMaxFractions);
  const std::size_t perBatch = static_cast<std::size_t>(std::max(1, most / std::max(1, set.size())));
  for (std::size_t first = 0; first < candidates.size(); first += perBatch, ++batchCount)
    PetscCall(solveBatch(candidates, first, std::min(perBatch, candidates.size() - first)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The time loop of Run::solve (src/run/run.cpp, march) for `count`
// candidates at once: the path's frames, the shift on the batch, then each
// candidate's operators, ledger and centre of gravity on its own columns.
// A jump's step applies the same operators (Run measures the bed around the
// carry for jumps.csv, which a batch does not write).
PetscErrorCode BatchedReplay::solveBatch(const std::vector<Candidate> &candidates, std::size_t first,
                                         std::size_t count) {
  std::vector<Group> groups(count);
  PetscFunctionBeginUser;
  for (std::size_t g = 0; g < count; ++g) {
    PetscCall(setUpGroup(candidates[first + g], &groups[g]));
    if (!database) database = groups[g].run->sharedDatabase(); // loaded once for all
  }
  Run &lead = *groups.front().run;
  const Database &db = *database;
  const int nf = lead.fractions().size(), columns = nf * static_cast<int>(count);
  for (const Group &g : groups) {
    PetscCheck(g.run->fractions().size() == nf && g.run->numSteps() == lead.numSteps(), comm, PETSC_ERR_USER_INPUT,
               "The candidates of a batched replay differ in their number of fractions or of steps; give those "
               "options on the command line, not per candidate");
  }
  // The shift of all columns, with the command line's -shift_ options.
  std::unique_ptr<Operator> made;
  PetscCall(registry.create("shift", &made));
  auto *shift = dynamic_cast<ShiftOperator *>(made.get());
  PetscCheck(shift, comm, PETSC_ERR_PLIB, "The registry's shift is not rcfd's ShiftOperator; it cannot be batched");
  PetscCall(shift->setFromOptions(comm));
  shift->setColumns(columns);
  PetscCall(shift->setUp(lead.context()));
  FractionState batch;
  PetscCall(batch.create(db.layout(), columns));
  const PathRegistry builtinPaths = registries ? PathRegistry() : PathRegistry::withBuiltins();
  const PathRegistry &paths = registries ? registries->paths : builtinPaths;
  std::unique_ptr<FramePath> path;
  PetscCall(paths.createFromOptions(comm, &path));
  PetscCall(path->setUp(PathContext{db, true}));

  const PetscInt nlocal = db.layout().numLocal();
  // Each candidate's masses into its columns of the batch, and back, below
  // the bound on where mass can be: above it every candidate's cells are
  // empty, and so are the batch's (a cell empties only in a shift, which
  // writes the batch's zeros; a swap moves mass only between cells that
  // hold some), so the copies leave out the freeboard.  Cell by cell, all
  // candidates at once: each row of the batch is read or written once.
  std::vector<const PetscScalar *> from(count);
  std::vector<PetscScalar *> to(count);
  auto pack = [&]() -> PetscErrorCode {
    PetscScalar *b;
    PetscInt bound = 0;
    PetscFunctionBeginUser;
    for (std::size_t g = 0; g < count; ++g) {
      PetscInt end;
      PetscCall(groups[g].run->state().occupiedEnd(&end));
      bound = std::max(bound, end);
      PetscCall(VecGetArrayRead(groups[g].run->state().masses(), &from[g]));
    }
    PetscCall(VecGetArray(batch.masses(), &b));
    for (PetscInt c = 0; c < bound; ++c)
      for (std::size_t g = 0; g < count; ++g)
        for (int i = 0; i < nf; ++i) b[c * columns + static_cast<PetscInt>(g) * nf + i] = from[g][c * nf + i];
    PetscCall(VecRestoreArray(batch.masses(), &b));
    for (std::size_t g = 0; g < count; ++g) PetscCall(VecRestoreArrayRead(groups[g].run->state().masses(), &from[g]));
    PetscCall(batch.setOccupiedEnd(bound));
    PetscFunctionReturn(PETSC_SUCCESS);
  };
  auto unpack = [&]() -> PetscErrorCode {
    const PetscScalar *b;
    PetscInt bound;
    PetscFunctionBeginUser;
    PetscCall(batch.occupiedEnd(&bound));
    PetscCall(VecGetArrayRead(batch.masses(), &b));
    for (std::size_t g = 0; g < count; ++g) PetscCall(VecGetArray(groups[g].run->state().masses(), &to[g]));
    for (PetscInt c = 0; c < bound; ++c)
      for (std::size_t g = 0; g < count; ++g)
        for (int i = 0; i < nf; ++i) to[g][c * nf + i] = b[c * columns + static_cast<PetscInt>(g) * nf + i];
    for (std::size_t g = 0; g < count; ++g) {
      PetscCall(VecRestoreArray(groups[g].run->state().masses(), &to[g]));
      PetscCall(groups[g].run->state().setOccupiedEnd(bound));
    }
    PetscCall(VecRestoreArrayRead(batch.masses(), &b));
    PetscFunctionReturn(PETSC_SUCCESS);
  };
  const long steps = lead.numSteps();
  const int frames = db.numFrames();
  auto sample = [&](Group &g, long step, double time, int frame, bool last) -> PetscErrorCode {
    PetscFunctionBeginUser;
    if (step == 0 || last || step % g.cog.every() == 0) {
      const RunContext ctx = g.run->context();
      if (g.directory.empty()) { // what CogMonitor::sample measures, without the row of cog.csv
        BedSample s;
        PetscCall(g.measure.measure(time, g.run->state().masses(), db.alphaS(frame), ctx.solidDensity, &s));
        g.samples.push_back(std::move(s));
      } else PetscCall(g.cog.sample(MonitorContext{step, time, frame, last, g.run->state(), ctx, g.directory}));
    }
    PetscFunctionReturn(PETSC_SUCCESS);
  };
  int frame = path->next();
  for (Group &g : groups) {
    PetscCall(g.ledger.start(g.run->state()));
    PetscCall(sample(g, 0, 0.0, frame % frames, steps == 0));
  }
  StepInfo info;
  info.dt = db.metadata().dtRec;
  for (long s = 0; s < steps; ++s) {
    info.step = s;
    info.time = s * info.dt;
    int next;
    bool pathJump;
    try {
      next = path->next();
      pathJump = path->lastWasJump();
    } catch (const std::out_of_range &) { // a recorded path ends with the run it came from
      next = (frame + 1) % frames;
      pathJump = next != frame + 1;
    }
    info.frame = frame % frames;
    info.nextFrame = next % frames;
    info.jump = pathJump || (next == frame + 1 && !db.nextFollows(info.frame));
    PetscCall(pack());
    PetscCall(shift->apply(info, batch));
    PetscCall(unpack());
    const double t = (s + 1) * info.dt;
    for (std::size_t g = 0; g < count; ++g) {
      Group &group = groups[g];
      for (Operator *op : group.after) PetscCall(op->apply(info, group.run->state()));
      PetscCall(group.ledger.check(s + 1, group.run->state(), s + 1 == steps));
      PetscCall(sample(group, s + 1, t, next % frames, s + 1 == steps));
    }
    frame = next;
  }
  for (std::size_t g = 0; g < count; ++g) {
    if (groups[g].directory.empty()) histories[first + g] = std::move(groups[g].samples);
    else {
      PetscCall(groups[g].cog.flush());
      histories[first + g] = groups[g].cog.samples();
    }
    const PetscScalar *m;
    PetscCall(VecGetArrayRead(groups[g].run->state().masses(), &m));
    finals[first + g].assign(m, m + nlocal * nf);
    PetscCall(VecRestoreArrayRead(groups[g].run->state().masses(), &m));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
