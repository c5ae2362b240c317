#include "rcfd/run.hpp"
#include "base/petsc_compat.hpp"

#include "path/database_recurrence.hpp"
#include "observable/cog_plot.hpp"
#include "path/frame_path.hpp"

#include "base/collective.hpp"
#include "base/h5.hpp"

#include <petscviewerhdf5.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <sys/resource.h>
#include <stdexcept>

namespace rcfd {
namespace {

std::vector<std::string> splitList(const std::string &text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

} // namespace

std::string formatCsvRow(const BedSample &s, int digits) {
  std::ostringstream row;
  row.precision(digits);
  row << s.time << ',' << s.zCogBed;
  for (double z : s.zCog) row << ',' << z;
  row << ',' << s.deltaZ;
  for (double m : s.mass) row << ',' << m;
  row << ',' << s.minMass << ',' << s.bulkMismatch;
  return row.str();
}


Run::Run(MPI_Comm comm, const OperatorRegistry &registry) : comm(comm), registry(registry) {}
Run::~Run() = default;

PetscErrorCode Run::setFromOptions() {
  char text[PETSC_MAX_PATH_LEN];
  PetscBool set_;
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, nullptr, "rcfd run", "rcfd");
  text[0] = '\0';
  PetscCall(PetscOptionsString("-db", "Database file (HDF5), e.g. from rcfd synth", "", "", text,
                               sizeof text, &set_));
  if (set_) dbPath = text;
  PetscCall(PetscOptionsReal("-t_end", "Simulated time to run [s] (default: one pass over the frames)",
                             "", tEnd, &tEnd, nullptr));
  PetscCall(PetscOptionsString("-output_dir", "Directory for results", "", outputDir.c_str(), text,
                               sizeof text, &set_));
  if (set_) outputDir = text;
  PetscCall(PetscOptionsString("-pipeline", "Operators applied each step, in order", "",
                               pipelineSpec.c_str(), text, sizeof text, &set_));
  if (set_) pipelineSpec = text;
  PetscCall(PetscOptionsInt("-monitor_every", "Steps between rows of cog.csv", "", monitorEvery,
                            &monitorEvery, nullptr));
  PetscCall(PetscOptionsInt("-monitor_digits", "Significant digits in cog.csv", "", csvDigits,
                            &csvDigits, nullptr));
  PetscCall(PetscOptionsBool("-fields", "Write HDF5 + XDMF fields", "", writeFields, &writeFields,
                             nullptr));
  PetscCall(PetscOptionsReal("-fields_every", "Simulated time between field outputs [s] (0: start and end only)",
                             "", fieldsEvery, &fieldsEvery, nullptr));
  PetscCall(PetscOptionsString("-init", "Initial state: mixed, layered or file", "",
                               initKind.c_str(), text, sizeof text, &set_));
  if (set_) initKind = text;
  PetscCall(PetscOptionsString("-init_file", "HDF5 file with dataset /masses [cells x fractions] in kg",
                               "", "", text, sizeof text, &set_));
  if (set_) initFile = text;
  PetscCall(PetscOptionsString("-path_type", "Frame path: replay, random, markov, quarter or recorded",
                               "", pathType.c_str(), text, sizeof text, &set_));
  if (set_) pathType = text;
  PetscCall(PetscOptionsInt("-path_seed", "Seed of the stitching path", "", pathSeed, &pathSeed, nullptr));
  PetscCall(PetscOptionsInt("-path_start", "Frame of the first step", "", pathStart, &pathStart, nullptr));
  PetscCall(PetscOptionsInt("-path_min_length", "Shortest sequence [frames] (default: by kind)", "",
                            pathMinLength, &pathMinLength, nullptr));
  PetscCall(PetscOptionsInt("-path_max_length", "Longest sequence [frames] (default: by kind)", "",
                            pathMaxLength, &pathMaxLength, nullptr));
  PetscCall(PetscOptionsInt("-path_band", "Jumps only to frames at least this far away (default: K/10)",
                            "", pathBand, &pathBand, nullptr));
  PetscCall(PetscOptionsReal("-path_mean_interval", "markov: mean extra steps before a jump", "",
                             pathMeanInterval, &pathMeanInterval, nullptr));
  PetscCall(PetscOptionsInt("-path_candidates", "Jump to one of this many best matches, at random",
                            "", pathCandidates, &pathCandidates, nullptr));
  PetscCall(PetscOptionsString("-path_file", "Frames to replay, one per line (path_type recorded)",
                               "", "", text, sizeof text, &set_));
  if (set_) pathFile = text;
  PetscCall(PetscOptionsString("-recurrence_norm", "sqrDiff, euclidean, absDiff or max", "",
                               recurrenceNorm.c_str(), text, sizeof text, &set_));
  if (set_) recurrenceNorm = text;
  PetscCall(PetscOptionsReal("-checkpoint_every", "Simulated time between checkpoints [s] (0: none)",
                             "", checkpointEvery, &checkpointEvery, nullptr));
  PetscCall(PetscOptionsString("-checkpoint_file", "Checkpoint file (default: OUTPUT_DIR/checkpoint.h5)",
                               "", "", text, sizeof text, &set_));
  if (set_) checkpointFile = text;
  PetscCall(PetscOptionsString("-restart", "Continue from this checkpoint file", "", "", text,
                               sizeof text, &set_));
  if (set_) restartFile = text;
  PetscCall(PetscOptionsReal("-solid_density", "Particle density [kg/m^3] (default: the database's)",
                             "", solidDensity, &solidDensity, nullptr));
  PetscCall(PetscOptionsBool("-plot", "Draw cog.png and cog-delta.png at the end", "", plotResults,
                             &plotResults, nullptr));
  PetscCall(PetscOptionsBool("-quiet", "No progress or summary output", "", quiet, &quiet, nullptr));
  PetscCall(PetscOptionsReal("-progress_interval", "Wall seconds between progress lines", "",
                             progressInterval, &progressInterval, nullptr));
  PetscOptionsEnd();
  PetscBool help = PETSC_FALSE;
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-help", &help));
  PetscCheck(!dbPath.empty() || help, comm, PETSC_ERR_USER_INPUT,
             "No database given: pass -db FILE (make one with 'rcfd synth -o FILE')");
  PetscCheck(monitorEvery >= 1, comm, PETSC_ERR_USER_INPUT, "-monitor_every must be at least 1");
  PetscCheck(initKind == "mixed" || initKind == "layered" || initKind == "file", comm,
             PETSC_ERR_USER_INPUT, "-init %s is not known; use mixed, layered or file", initKind.c_str());
  PetscCheck(initKind != "file" || !initFile.empty(), comm, PETSC_ERR_USER_INPUT,
             "-init file needs -init_file FILE");
  PetscCheck(pathType != "recorded" || !pathFile.empty(), comm, PETSC_ERR_USER_INPUT,
             "-path_type recorded needs -path_file FILE");
  PetscCheck(checkpointEvery >= 0, comm, PETSC_ERR_USER_INPUT, "-checkpoint_every must be >= 0");
  if (checkpointFile.empty()) checkpointFile = outputDir + "/checkpoint.h5";
  PetscCall(Database::optionsFromCommandLine(&loadOptions));
  PetscCall(FractionSet::fromOptions(comm, &set));

  std::vector<std::unique_ptr<Operator>> created;
  PetscCall(collectively(
      comm,
      [&] {
        for (const auto &name : splitList(pipelineSpec)) created.push_back(registry.create(name));
      },
      PETSC_ERR_USER_INPUT));
  for (auto &op : created) PetscCall(ops.add(std::move(op)));
  PetscCall(ops.setFromOptions(comm));
  PetscCall(ledger.setFromOptions(comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Run::setUp() {
  PetscFunctionBeginUser;
  if (!db) {
    std::unique_ptr<Database> loaded;
    PetscCall(Database::load(comm, dbPath, loadOptions, &loaded));
    db = std::move(loaded);
  }
  if (solidDensity <= 0) solidDensity = db->metadata().solidDensity;
  if (tEnd < 0) tEnd = db->numFrames() * db->metadata().dtRec;
  steps = std::lround(tEnd / db->metadata().dtRec);
  PetscCall(fstate.create(db->layout(), set.size()));
  RunContext ctx{*db, set, solidDensity};
  PetscCall(ops.setUp(ctx));
  PetscCall(cog.setUp(*db, set));
  PetscCall(setUpPath());
  PetscCall(makeDirectories(comm, outputDir));
  csv = std::make_unique<CsvSeries>(comm, outputDir + "/cog.csv", csvHeader());
  if (writeFields) PetscCall(fields.setUp(*db, set, solidDensity, outputDir, fstate.masses()));
  if (restartFile.empty()) PetscCall(initialState());
  else PetscCall(readCheckpoint());
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::string Run::csvHeader() const {
  std::string header = "time_s,z_cog_bed_m";
  for (int i = 0; i < set.size(); ++i) header += ",z_cog_" + set.label(i) + "_m";
  header += ",delta_z_m";
  for (int i = 0; i < set.size(); ++i) header += ",mass_" + set.label(i) + "_kg";
  return header + ",min_cell_mass_kg,bulk_mismatch";
}

// The path is built identically on every rank: from the stored recurrence
// matrix (or one computed and broadcast from rank 0), its parameters and seed.
PetscErrorCode Run::setUpPath() {
  PetscFunctionBeginUser;
  const int K = db->numFrames();
  if (pathType == "recorded") {
    PetscCall(collectively(
        comm, [&] { path = makeRecordedPath(K, readPathFile(pathFile)); }, PETSC_ERR_USER_INPUT));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  std::vector<double> R;
  if (pathType != "replay") {
    RecurrenceNorm norm = RecurrenceNorm::SqrDiff;
    PetscCall(collectively(
        comm, [&] { norm = parseRecurrenceNorm(recurrenceNorm); }, PETSC_ERR_USER_INPUT));
    bool stored = false;
    PetscCall(loadOrComputeRecurrence(*db, norm, &R, &stored));
    if (!quiet && !stored)
      PetscCall(PetscPrintf(comm, "Computed the %s recurrence matrix of %d frames (store it with "
                                  "'rcfd recurrence %s' to reuse it)\n",
                            recurrenceNorm.c_str(), K, dbPath.c_str()));
  }
  PathParams p;
  p.seed = static_cast<std::uint64_t>(pathSeed);
  p.startFrame = static_cast<int>(pathStart);
  if (pathMinLength > 0) p.minLength = static_cast<int>(pathMinLength);
  if (pathMaxLength > 0) p.maxLength = static_cast<int>(pathMaxLength);
  if (pathBand > 0) p.band = static_cast<int>(pathBand);
  if (pathMeanInterval >= 0) p.meanIntervalSteps = pathMeanInterval;
  if (pathType != "replay") p.candidates = static_cast<int>(pathCandidates);
  PetscCall(collectively(comm, [&] { path = makeFramePath(pathType, K, R, p); }, PETSC_ERR_USER_INPUT));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Run::monitor(double time, int frameOfState) {
  PetscFunctionBeginUser;
  BedSample s;
  PetscCall(cog.measure(time, fstate.masses(), db->alphaS(frameOfState), solidDensity, &s));
  samples.push_back(s);
  csv->add(formatCsvRow(s, static_cast<int>(csvDigits)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Run::progress(long step, double time, bool last) {
  PetscFunctionBeginUser;
  if (quiet) PetscFunctionReturn(PETSC_SUCCESS);
  const double now = MPI_Wtime();
  if (!last && now - lastProgress < progressInterval) PetscFunctionReturn(PETSC_SUCCESS);
  lastProgress = now;
  const double elapsed = now - wallStart;
  const double rate = elapsed > 0 ? step / elapsed : 0.0;
  const double eta = rate > 0 ? (steps - step) / rate : 0.0;
  PetscCall(PetscPrintf(comm, "  t = %8.3f / %.3f s  step %ld/%ld  %8.0f steps/s  %6.1f s simulated per wall s  ETA %.1f s\n",
                        time, tEnd, step, steps, rate, rate * db->metadata().dtRec, eta));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Run::solve() {
  PetscFunctionBeginUser;
  const double dt = db->metadata().dtRec;
  std::vector<double> initialMass;
  PetscCall(fstate.totals(&initialMass));
  const bool ledgerOn = ops.conservesMass();
  if (ledgerOn && startStep == 0) PetscCall(ledger.start(fstate));
  // The frame of the next step; after a restart the path stands on it.
  int frame = startStep == 0 ? path->next() : path->frame();
  if (startStep == 0) {
    PetscCall(monitor(0.0, frame));
    if (writeFields) PetscCall(fields.write(0.0, frame, fstate.masses()));
  }
  auto every = [dt](double interval) { return interval > 0 ? std::max(1L, std::lround(interval / dt)) : 0L; };
  const long fieldSteps = every(fieldsEvery), checkpointSteps = every(checkpointEvery);
  wallStart = lastProgress = MPI_Wtime();
  double lastFlush = wallStart;
  StepInfo info;
  info.dt = dt;
  for (long s = startStep; s < steps; ++s) {
    info.step = s;
    info.time = s * dt;
    info.frame = frame;
    try {
      info.nextFrame = path->next();
      info.jump = path->lastWasJump();
    } catch (const std::out_of_range &) { // a recorded path ends with the run it came from
      info.nextFrame = (frame + 1) % db->numFrames();
      info.jump = info.nextFrame != frame + 1;
    }
    frames.push_back(frame);
    PetscCall(ops.apply(info, fstate));
    if (ledgerOn) PetscCall(ledger.check(s + 1, fstate));
    frame = info.nextFrame;
    const double t = (s + 1) * dt;
    if ((s + 1) % monitorEvery == 0 || s + 1 == steps) PetscCall(monitor(t, frame));
    if (writeFields && fieldSteps && (s + 1) % fieldSteps == 0 && s + 1 < steps)
      PetscCall(fields.write(t, frame, fstate.masses()));
    if (checkpointSteps && (s + 1) % checkpointSteps == 0) PetscCall(writeCheckpoint(s + 1));
    if (MPI_Wtime() - lastFlush > 10.0) { // results so far survive an interruption
      PetscCall(csv->flush());
      lastFlush = MPI_Wtime();
    }
    PetscCall(progress(s + 1, t, false));
  }
  if (writeFields) PetscCall(fields.write(steps * dt, frame, fstate.masses()));
  PetscCall(csv->flush());
  PetscCall(writePath());
  if (plotResults) {
    PetscMPIInt rank;
    PetscCallMPI(MPI_Comm_rank(comm, &rank));
    PetscCall(collectively(comm, [&] {
      if (rank == 0) plotCogCsv(outputDir + "/cog.csv", outputDir + "/cog.png", outputDir);
    }));
  }
  PetscCall(progress(steps, steps * dt, true));

  PetscCall(ops.viewRequested());
  std::vector<double> finalMass;
  PetscCall(fstate.totals(&finalMass));
  double worst = 0.0;
  for (size_t i = 0; i < finalMass.size(); ++i)
    if (initialMass[i] > 0) worst = std::max(worst, std::fabs(finalMass[i] / initialMass[i] - 1.0));
  double low;
  PetscCall(fstate.minimum(&low));
  struct rusage usage;
  getrusage(RUSAGE_SELF, &usage);
  double peakMb = usage.ru_maxrss / 1024.0; // Linux reports kB
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &peakMb, 1, MPI_DOUBLE, MPI_MAX, comm));
  if (!quiet) {
    const double wall = MPI_Wtime() - wallStart;
    PetscCall(PetscPrintf(comm,
                          "Done: %ld steps, %.4g s simulated in %.3g s wall (%.3g wall s per simulated s), peak memory %.0f MB per rank\n"
                          "  largest relative change of a fraction's mass: %.2e (round-off removed by the ledger: %.2e);"
                          " smallest cell mass: %.3g kg\n"
                          "  results: %s/cog.csv%s%s\n",
                          steps - startStep, (steps - startStep) * dt, wall,
                          steps > startStep ? wall / ((steps - startStep) * dt) : 0.0, peakMb, worst,
                          ledger.largestCorrection(), low,
                          outputDir.c_str(), plotResults ? ", cog.png" : "",
                          writeFields ? (", " + outputDir + "/fields.xmf").c_str() : ""));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Run::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(db->view(viewer));
  PetscCall(set.view(viewer));
  PetscCall(ops.view(viewer));
  PetscCall(PetscViewerASCIIPrintf(viewer, "Run: %.4g s simulated in %ld steps, initial state %s, output in %s\n",
                                   tEnd, steps, restartFile.empty() ? initKind.c_str() : restartFile.c_str(),
                                   outputDir.c_str()));
  PetscCall(PetscViewerASCIIPrintf(viewer, "Path: %s\n", path->describe().c_str()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
