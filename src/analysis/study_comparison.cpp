// rcfd::Comparison (include/rcfd/study.hpp): everything rcfd compare scores,
// as an object with PETSc's life cycle over the serial scorers of
// analysis/comparison.hpp, class_scores.hpp, profile_comparison.hpp and
// halves_comparison.hpp.  Every rank reads and scores (the files are small);
// rank 0 writes.  The scorers report by exceptions naming the file, which
// collectively() turns into one PETSc error on every rank.
#include "analysis/study_agreement.hpp"
#include "base/petsc_compat.hpp"

#include "analysis/class_scores.hpp"
#include "analysis/comparison.hpp"
#include "analysis/halves_comparison.hpp"
#include "analysis/profile_comparison.hpp"
#include "base/collective.hpp"
#include "observable/bed_dynamics.hpp"
#include "rcfd/database.hpp"

#include <filesystem>
#include <stdexcept>

namespace rcfd {

CurveAgreement agreementOf(const DeltaZScore &s) {
  CurveAgreement a;
  a.windowBegin = s.windowBegin;
  a.windowEnd = s.windowEnd;
  a.meanReference = s.meanRef;
  a.meanRun = s.meanModel;
  a.segregationError = s.segregationError;
  a.rms = s.rms;
  a.rmsRelative = s.rmsRelative;
  a.samplesReference = s.windowSamplesRef;
  a.samplesRun = s.windowSamplesModel;
  a.overlapBegin = s.overlapBegin;
  a.overlapEnd = s.overlapEnd;
  a.overlapSamples = s.curveSamples;
  a.peakReference = s.peakRef;
  return a;
}

PetscErrorCode viewAgreement(PetscViewer viewer, const CurveAgreement &a) {
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer,
                                   "mean %.4g mm (reference %.4g mm) over [%g, %g] s: Delta_seg %.1f %%, RMS/peak %.3f\n",
                                   1e3 * a.meanRun, 1e3 * a.meanReference, a.windowBegin, a.windowEnd,
                                   a.segregationError, a.rmsRelative));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// What the files are written from: the scorers' own records.
struct Comparison::Impl {
  CurveSet reference;              // curves over time
  std::vector<CurveSet> runs;      // one per run
  CurveSet referenceClasses;       // z_CoG,i - z_CoG,bed of the reference's classes
  std::vector<CurveSet> runClasses; // each run's classes the reference has
  std::vector<CurveScore> curveScores, classScores;
  std::vector<PolydisperseScore> polydisperse;
  std::vector<ProfileDifference> profiles;
  std::vector<HalvesDifference> halves;
  bool solved = false;
};

Comparison::Comparison(MPI_Comm c) : impl(std::make_unique<Impl>()), comm(c) {}
Comparison::~Comparison() = default;

PetscErrorCode Comparison::setReference(const std::string &file) {
  reference = file;
  isSetUp = false;
  return PETSC_SUCCESS;
}

PetscErrorCode Comparison::addRun(const std::string &file, const std::string &label) {
  files.push_back(file);
  labels.push_back(label.empty() ? file : label);
  isSetUp = false;
  return PETSC_SUCCESS;
}

PetscErrorCode Comparison::setWindows(const std::vector<double> &pairs) {
  PetscFunctionBeginUser;
  PetscCheck(!pairs.empty() && pairs.size() % 2 == 0, comm, PETSC_ERR_ARG_WRONG,
             "Comparison: give the windows as pairs t0,t1 [s]");
  for (std::size_t i = 0; i < pairs.size(); i += 2)
    PetscCheck(pairs[i] < pairs[i + 1], comm, PETSC_ERR_ARG_OUTOFRANGE,
               "Comparison: window %d, [%g, %g] s, does not have t0 < t1", static_cast<int>(i / 2 + 1), pairs[i],
               pairs[i + 1]);
  windows = pairs;
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The reference's kind, and every run's file of it; a bed dynamics is a
// comparison of its own (databaseDistance).
PetscErrorCode Comparison::setUp() {
  int kind = 0;
  PetscFunctionBeginUser;
  PetscCheck(!reference.empty() && !files.empty(), comm, PETSC_ERR_ORDER,
             "Comparison: give a reference and at least one run before setUp()");
  PetscCall(collectively(comm, [&] {
    const AnswerFile k = answerFileKind(CsvTable::read(reference, "reference file"));
    for (const auto &run : files) {
      const AnswerFile r = answerFileKind(CsvTable::read(run, "run's file"));
      if (r != k)
        throw std::runtime_error("'" + run + "' is a " + describe(r) + " but the reference '" + reference +
                                 "' is a " + describe(k) + ": compare files of one kind.");
    }
    if (k == AnswerFile::bedDynamics)
      throw std::runtime_error("'" + reference + "' holds a bed dynamics: compare it with -db_distance A,B.");
    kind = static_cast<int>(k);
  }, PETSC_ERR_USER_INPUT));
  switch (static_cast<AnswerFile>(kind)) {
  case AnswerFile::bottomLayer: fileKind = Kind::bottomLayer; break;
  case AnswerFile::profiles: fileKind = Kind::profiles; break;
  case AnswerFile::halves: fileKind = Kind::halves; break;
  default: fileKind = Kind::centresOfGravity;
  }
  isSetUp = true;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Comparison::solve() {
  PetscFunctionBeginUser;
  if (!isSetUp) PetscCall(setUp());
  std::vector<TimeSpan> spans;
  for (std::size_t i = 0; i < windows.size(); i += 2) spans.push_back({windows[i], windows[i + 1]});
  auto next = std::make_unique<Impl>();
  std::vector<std::string> notes;
  std::vector<std::size_t> polydisperseRuns; // the run of each poly-disperse number
  PetscCall(collectively(comm, [&] {
    Impl &r = *next;
    const CsvTable refTable = CsvTable::read(reference, "reference file");
    // Profiles and halves: each run's file read and compared as a whole.
    const auto each = [&](auto read, auto compare, auto &rows) {
      const auto ref = read(refTable);
      for (std::size_t i = 0; i < files.size(); ++i) {
        const auto d = compare(ref, read(CsvTable::read(files[i], "run's file")), labels[i]);
        rows.insert(rows.end(), d.begin(), d.end());
      }
    };
    if (fileKind == Kind::profiles) return each(readProfiles, compareProfiles, r.profiles);
    if (fileKind == Kind::halves) return each(readHalves, compareHalves, r.halves);
    // Curves over time; of centres of gravity also every class.
    r.reference = readCurves(refTable, 0.0);
    const bool cog = fileKind == Kind::centresOfGravity;
    const ClassCurveSet refClasses = cog ? readClassCurves(refTable, 0.0) : ClassCurveSet{};
    r.referenceClasses = refClasses.curves;
    for (std::size_t i = 0; i < files.size(); ++i) {
      const CsvTable table = CsvTable::read(files[i], "run's file");
      r.runs.push_back(readCurves(table, offset));
      const auto s = scoreCurves(r.reference, r.runs.back(), labels[i], spans);
      r.curveScores.insert(r.curveScores.end(), s.begin(), s.end());
      if (!cog) continue;
      const ClassComparison c = compareClasses(refClasses, readClassCurves(table, offset), labels[i], spans);
      r.runClasses.push_back(c.matched);
      r.classScores.insert(r.classScores.end(), c.scores.begin(), c.scores.end());
      notes.insert(notes.end(), c.notes.begin(), c.notes.end());
      if (c.hasPolydisperse) {
        r.polydisperse.push_back(c.polydisperse);
        polydisperseRuns.push_back(i);
      }
    }
  }, PETSC_ERR_USER_INPUT));
  next->solved = true;
  impl = std::move(next);
  why = std::move(notes);
  scored.clear();
  classScored.clear();
  polydisperseScored.clear();
  profiles.clear();
  halves.clear();
  for (const CurveScore &c : impl->curveScores) scored.push_back({c.run, c.curve, agreementOf(c.score)});
  for (const CurveScore &c : impl->classScores) classScored.push_back({c.run, c.curve, agreementOf(c.score)});
  for (std::size_t k = 0; k < impl->polydisperse.size(); ++k) {
    const PolydisperseScore &p = impl->polydisperse[k];
    Polydisperse out;
    out.run = p.run;
    out.runIndex = polydisperseRuns[k];
    out.rms = p.rms;
    out.rmsRelative = p.rmsRelative;
    out.largestClass = p.largestClass;
    out.peakLargest = p.peakLargest;
    out.weights = p.weights;
    out.weightsFrom = p.weightsFrom;
    out.overlapBegin = p.curveBegin;
    out.overlapEnd = p.curveEnd;
    out.overlapSamples = p.curveSamples;
    polydisperseScored.push_back(out);
  }
  for (const ProfileDifference &d : impl->profiles)
    profiles.push_back({d.run, d.curve, d.layers, d.zBegin, d.zEnd, d.rms, d.maxAbs, d.peakRef, d.rmsRelative});
  for (const HalvesDifference &d : impl->halves)
    halves.push_back({d.run, d.label, d.diameter, d.bottomRef, d.bottomRun, d.topRef, d.topRun});
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::string Comparison::classCurvesFile(const std::string &curvesFile) {
  const std::filesystem::path p(curvesFile);
  return (p.parent_path() / (p.stem().string() + "-classes.csv")).string();
}

PetscErrorCode Comparison::writeCurves(const std::string &file) const {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCheck(fileKind == Kind::centresOfGravity || fileKind == Kind::bottomLayer, comm, PETSC_ERR_ARG_WRONG,
             "Comparison: '%s' holds no curves over time to write to '%s'", reference.c_str(), file.c_str());
  PetscCheck(impl->solved, comm, PETSC_ERR_ORDER, "Comparison: solve() before writeCurves()");
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(collectively(comm, [&] {
    if (rank != 0) return;
    writeCurvesSideBySide(file, impl->reference, impl->runs, labels);
    if (!impl->classScores.empty())
      writeCurvesSideBySide(classCurvesFile(file), impl->referenceClasses, impl->runClasses, labels);
  }, PETSC_ERR_USER_INPUT));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Comparison::writeScores(const std::string &file) const {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCheck(impl->solved, comm, PETSC_ERR_ORDER, "Comparison: solve() before writeScores()");
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(collectively(comm, [&] {
    if (rank != 0) return;
    if (fileKind == Kind::profiles) writeProfileScores(file, reference, impl->profiles);
    else if (fileKind == Kind::halves) writeHalvesScores(file, reference, impl->halves);
    else {
      std::vector<CurveScore> rows = impl->curveScores; // the curves' rows, then the classes'
      rows.insert(rows.end(), impl->classScores.begin(), impl->classScores.end());
      writeCurveScores(file, reference, rows, polydisperseRows(impl->polydisperse));
    }
  }, PETSC_ERR_USER_INPUT));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Comparison::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer, "Comparison against %s:\n", reference.c_str()));
  for (const std::vector<Score> *list : {&scored, &classScored})
    for (const Score &s : *list) {
      PetscCall(PetscViewerASCIIPrintf(viewer, "  %s, %s: ", s.run.c_str(), s.curve.c_str()));
      PetscCall(PetscViewerASCIIUseTabs(viewer, PETSC_FALSE));
      PetscCall(viewAgreement(viewer, s.agreement));
      PetscCall(PetscViewerASCIIUseTabs(viewer, PETSC_TRUE));
    }
  for (const Polydisperse &p : polydisperseScored)
    PetscCall(PetscViewerASCIIPrintf(viewer, "  %s, poly-disperse: E = %.4g mm, %.3f of the peak of %s\n",
                                     p.run.c_str(), 1e3 * p.rms, p.rmsRelative, p.largestClass.c_str()));
  for (const ProfileScore &p : profiles)
    PetscCall(PetscViewerASCIIPrintf(viewer, "  %s, %s: RMS %.4g over %zu layers, RMS/peak %.3f\n", p.run.c_str(),
                                     p.curve.c_str(), p.rms, p.layers, p.rmsRelative));
  for (const HalvesScore &h : halves)
    PetscCall(PetscViewerASCIIPrintf(viewer, "  %s, %s: bottom %.4g (reference %.4g), top %.4g (reference %.4g)\n",
                                     h.run.c_str(), h.label.c_str(), h.bottomRun, h.bottomReference, h.topRun,
                                     h.topReference));
  PetscFunctionReturn(PETSC_SUCCESS);
}

namespace {
bool isDatabase(const std::string &path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  return ext == ".h5" || ext == ".hdf5";
}
} // namespace

PetscErrorCode Comparison::databaseDistance(MPI_Comm comm, const std::string &a, const std::string &b,
                                            DatabaseDistance *distance) {
  PetscMPIInt rank;
  const std::string path[2] = {a, b};
  double dyn[2] = {0.0, 0.0};
  std::size_t frames[2] = {0, 0};
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  for (int i = 0; i < 2; ++i) {
    if (isDatabase(path[i])) {
      DatabaseLoadOptions load;
      load.loadShifts = false;
      std::unique_ptr<Database> db;
      PetscCall(Database::load(comm, path[i], load, &db));
      std::vector<double> zCog;
      PetscCall(databaseBedCentres(*db, &zCog));
      PetscCall(collectively(comm, [&] { dyn[i] = bedDynamics(zCog); }, PETSC_ERR_USER_INPUT));
      frames[i] = zCog.size();
    } else {
      PetscCall(collectively(comm, [&] {
        if (rank == 0) dyn[i] = bedDynamicsOfFile(CsvTable::read(path[i], "bed-dynamics file"));
      }, PETSC_ERR_USER_INPUT));
      PetscCallMPI(MPI_Bcast(&dyn[i], 1, MPI_DOUBLE, 0, comm));
    }
  }
  double d = 0.0;
  PetscCall(collectively(comm, [&] {
    try {
      d = rcfd::databaseDistance(dyn[0], dyn[1]);
    } catch (const std::invalid_argument &) {
      throw std::runtime_error("'" + b + "' has no bed dynamics (Delta z_CoG = 0), so it cannot be "
                               "the denominator of the database distance.");
    }
  }, PETSC_ERR_USER_INPUT));
  *distance = {dyn[0], dyn[1], frames[0], frames[1], d};
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
