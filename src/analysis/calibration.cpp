#include "analysis/calibration.hpp"
#include "base/petsc_compat.hpp"

#include "base/checked_options.hpp"
#include "analysis/batched_replay.hpp"
#include "analysis/measured_drift.hpp"
#include "base/atomic_file.hpp"
#include "base/collective.hpp"
#include "base/input_file.hpp"
#include "rcfd/agitation.hpp"
#include "rcfd/run.hpp"
#include "rcfd/swaps.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace rcfd {

DriftCalibration::DriftCalibration(MPI_Comm comm, const OperatorRegistry &registry)
    : comm(comm), registry(registry) {}
DriftCalibration::DriftCalibration(MPI_Comm comm, const Registries &registries)
    : comm(comm), registry(registries.operators), registries(&registries) {}
DriftCalibration::~DriftCalibration() = default;

std::unique_ptr<Run> DriftCalibration::newRun() const {
  return registries ? std::make_unique<Run>(comm, *registries) : std::make_unique<Run>(comm, registry);
}

PetscErrorCode DriftCalibration::setFromOptions() {
  char ref[PETSC_MAX_PATH_LEN] = "", objective[16] = "rms", from[16] = "cog", laws[PETSC_MAX_PATH_LEN] = "";
  PetscInt nrange = 2, nwindow = 2;
  std::vector<std::string> given;
  PetscReal range[2] = {kdLo, kdHi}, window[2] = {windowBegin, windowEnd};
  PetscBool setRef = PETSC_FALSE, setModels = PETSC_FALSE, setRange = PETSC_FALSE,
            setWindow = PETSC_FALSE, help = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, prefix.empty() ? nullptr : prefix.c_str(), "rcfd calibrate: fit the drift coefficient to a reference",
                    "rcfd");
  PetscCall(PetscOptionsString("-reference", "Reference cog.csv (rcfd reference)", "", "", ref,
                               sizeof ref, &setRef));
  PetscCall(PetscOptionsString("-calibrate_from",
                               "cog: replays scored against -reference; measured: regression on the database's "
                               "measured drift (rcfd build), in seconds",
                               "", from, from, sizeof from, nullptr));
  PetscCall(PetscOptionsBool("-calibrate_exponent",
                             "With -calibrate_from measured: also fit n of a drift scaled by (a/a_bar)^n, a the "
                             "cell's leaving share, to the measured drift by agitation",
                             "", fitExponent, &fitExponent, nullptr));
  const std::string modelsHelp = "Size laws to fit, comma-separated: any of " + registry.sizeLaws().listing();
  PetscCall(checkedStringArray(PetscOptionsObject, "-calibrate_models", modelsHelp.c_str(), 16, &given, &setModels));
  PetscCall(PetscOptionsString("-calibrate_objective",
                               "rms: RMS of Delta z(t) - reference / reference peak; seg: |Eq. 7 error| in the window",
                               "", objective, objective, sizeof objective, nullptr));
  PetscCall(checkedRealArray(PetscOptionsObject, "-calibrate_kd_range", "Search interval of k_d [1/(m s)]",
                             range, &nrange, &setRange));
  PetscCall(checkedReal(PetscOptionsObject, "-calibrate_tolerance",
                        "Width of the final interval in log10 k_d", &tolerance, kPositive));
  PetscCall(checkedInt(PetscOptionsObject, "-calibrate_scan",
                       "Points of the coarse scan that brackets the minimum", &scanPoints, 2, 100000));
  PetscCall(checkedReal(PetscOptionsObject, "-rcfd_time_offset",
                        "Physical time of the database's frame 0 [s], added to the runs' times",
                        &offset, {-1e9, 1e9, true, true, "a finite time in s"}));
  PetscCall(checkedRealArray(PetscOptionsObject, "-score_window", "Window t0,t1 [s] of the Eq. 7 means", window,
                             &nwindow, &setWindow));
  PetscCall(PetscOptionsBool("-calibrate_batch",
                             "Run the replays that share the database and path as one state (the shift read once "
                             "per frame for all; the same bits); false: one by one (default: batched up to "
                             "20000 cells per rank)",
                             "", batch, &batch, &batchSet));
  PetscCall(PetscOptionsString("-calibrate_candidates",
                               "File of replays to run and score instead of a search, one per line: NAME then its "
                               "drift options (e.g. B-leaving2 -drift_model B -drift_kd 1.732e4 -drift_agitation "
                               "leaving -drift_agitation_exponent 2); each writes OUTPUT_DIR/NAME/cog.csv",
                               "", laws, laws, sizeof laws, nullptr));
  PetscOptionsEnd();
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-help", &help));
  if (help) PetscFunctionReturn(PETSC_SUCCESS);
  source = from;
  PetscCheck(source == "cog" || source == "measured", comm, PETSC_ERR_USER_INPUT,
             "-calibrate_from %s is not known; use cog or measured", from);
  candidatesFile = laws;
  PetscCheck(setRef || source == "measured" || !candidatesFile.empty(), comm, PETSC_ERR_USER_INPUT,
             "No reference given: pass -reference REF/cog.csv (made by rcfd reference)");
  for (std::size_t i = 0; i < given.size(); ++i) {
    const std::string &m = given[i];
    PetscCheck(registry.sizeLaws().has(m), comm, PETSC_ERR_USER_INPUT,
               "-calibrate_models: size law '%s' is not known; use any of %s", m.c_str(),
               registry.sizeLaws().listing().c_str());
    PetscCheck(std::find(given.begin(), given.begin() + i, m) == given.begin() + i, comm, PETSC_ERR_USER_INPUT,
               "-calibrate_models names the size law '%s' twice", m.c_str());
  }
  objectiveName = objective;
  PetscCheck(objectiveName == "rms" || objectiveName == "seg", comm, PETSC_ERR_USER_INPUT,
             "-calibrate_objective %s is not known; use rms or seg", objective);
  PetscCheck((!setRange || nrange == 2) && range[0] > 0 && range[0] < range[1], comm, PETSC_ERR_USER_INPUT,
             "-calibrate_kd_range takes two values lo,hi with 0 < lo < hi");
  PetscCheck(tolerance > 0, comm, PETSC_ERR_USER_INPUT, "-calibrate_tolerance must be positive");
  PetscCheck(scanPoints >= 3, comm, PETSC_ERR_USER_INPUT, "-calibrate_scan must be at least 3");
  PetscCheck((!setWindow || nwindow == 2) && window[0] < window[1], comm, PETSC_ERR_USER_INPUT,
             "-score_window takes two times t0,t1 [s] with t0 < t1");
  referenceFile = ref;
  if (!given.empty()) models = given;
  kdLo = range[0];
  kdHi = range[1];
  rangeGiven = setRange;
  windowBegin = window[0];
  windowEnd = window[1];
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode DriftCalibration::setUp() {
  PetscFunctionBeginUser;
  if (!referenceFile.empty())
    PetscCall(collectively(comm, [&] { reference = readDeltaZCsv(referenceFile); }, PETSC_ERR_USER_INPUT));
  const std::unique_ptr<Run> made = newRun();
  Run &first = *made;
  first.setDefaultOutputDirectory("rcfd-calibrate");
  PetscCall(first.setFromOptions());
  PetscCheck(!first.switchesDatabases(), comm, PETSC_ERR_USER_INPUT,
             "rcfd calibrate with several databases in -db: a calibration's runs share one loaded database and fit "
             "one bed's drift; calibrate on each database of the set alone (-db a.h5), then run the set");
  first.setQuiet(true);
  first.setWriteFields(false);
  PetscCall(first.setUp());
  db = first.sharedDatabase();
  outputDirectory = first.outputDirectory();
  for (const auto &op : first.pipeline().operators())
    if (auto *d = dynamic_cast<DriftOperator *>(op.get())) meanFactor = d->meanAgitationFactor();
  sauter = first.fractions().inventorySauterDiameter();
  if (!batchSet) { // measured: faster on the CFD-DEM meshes, slower once a batch leaves the cache
    PetscMPIInt size;
    PetscCallMPI(MPI_Comm_size(comm, &size));
    batch = first.database().layout().numCells() <= kBatchCellsPerRank * size ? PETSC_TRUE : PETSC_FALSE;
  }
  std::string why;
  canBatch = batch && BatchedReplay::batchable(first, &why);
  if (batch && !canBatch) PetscCall(PetscPrintf(comm, "Note: the replays run one by one: %s\n", why.c_str()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The drift operator of the run's pipeline set to the point's law, k_d,
// shape and agitation exponent (typed setters, between setFromOptions and setUp).
PetscErrorCode DriftCalibration::configureDrift(Run &run, const Point &p) {
  PetscFunctionBeginUser;
  run.keepHistory(true); // the samples it scores
  DriftOperator *drift = nullptr;
  for (const auto &op : run.pipeline().operators())
    if (auto *d = dynamic_cast<DriftOperator *>(op.get())) drift = d;
  PetscCheck(drift, comm, PETSC_ERR_USER_INPUT,
             "rcfd calibrate fits the drift operator, but -pipeline has none (add drift)");
  PetscCall(drift->setSizeLaw(p.model));
  if (std::isfinite(p.shape)) drift->sizeLaw()->setShapeParameter(p.shape);
  drift->setKd(std::pow(10.0, p.log10kd));
  if (p.exponent >= 0.0) {
    if (!leaving) {
      auto field = std::make_shared<AgitationField>();
      PetscCall(field->setUp(*db, AgitationMeasure::LeavingShare));
      leaving = field;
    }
    drift->useAgitation(leaving);
    drift->setAgitationExponent(p.exponent);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode DriftCalibration::scoreSamples(const std::vector<BedSample> &samples, DeltaZScore *score) const {
  DeltaZSeries s;
  PetscFunctionBeginUser;
  for (const BedSample &b : samples) {
    s.time.push_back(b.time + offset);
    s.deltaZ.push_back(b.deltaZ);
  }
  PetscCall(collectively(
      comm, [&] { *score = scoreDeltaZ(reference, s, windowBegin, windowEnd); }, PETSC_ERR_USER_INPUT));
  PetscFunctionReturn(PETSC_SUCCESS);
}

void DriftCalibration::record(const std::string &model, double log10kd, const DeltaZScore &score) {
  scan.push_back({model, std::pow(10.0, log10kd), score});
  ++count;
}

/// Runs the case with the given model and k_d and scores it.
PetscErrorCode DriftCalibration::evaluate(const std::string &model, double log10kd, DeltaZScore *score,
                                          double exponent, double shape) {
  PetscFunctionBeginUser;
  PetscCall(replayOne(Point{model, log10kd, exponent, shape}, score));
  record(model, log10kd, *score);
  PetscFunctionReturn(PETSC_SUCCESS);
}

// One run of its own (its cog.csv in OUTPUT_DIR), scored, not recorded.
PetscErrorCode DriftCalibration::replayOne(const Point &p, DeltaZScore *score) {
  PetscFunctionBeginUser;
  const double start = MPI_Wtime();
  const std::unique_ptr<Run> made = newRun();
  Run &run = *made;
  run.setDefaultOutputDirectory("rcfd-calibrate");
  run.useDatabase(db);
  PetscCall(run.setFromOptions());
  run.setQuiet(true);
  run.setWriteFields(false);
  PetscCall(configureDrift(run, p));
  PetscCall(run.setUp());
  PetscCall(run.solve());
  PetscCall(scoreSamples(run.history(), score));
  replaySeconds += MPI_Wtime() - start;
  PetscFunctionReturn(PETSC_SUCCESS);
}

// Several points: one batched state when the runs allow it (no cog.csv),
// else one by one (each overwriting OUTPUT_DIR/cog.csv).
PetscErrorCode DriftCalibration::replayAll(const std::vector<Point> &points, std::vector<DeltaZScore> *scores) {
  PetscFunctionBeginUser;
  scores->assign(points.size(), DeltaZScore{});
  if (!canBatch) {
    for (std::size_t k = 0; k < points.size(); ++k) PetscCall(replayOne(points[k], &(*scores)[k]));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  const double start = MPI_Wtime();
  std::vector<BatchedReplay::Candidate> candidates; // no cog.csv: the scores are all a search needs
  for (const Point &p : points) candidates.push_back({"", "", [this, p](Run &run) { return configureDrift(run, p); }});
  BatchedReplay batched(comm, registry);
  batched.useRegistries(registries);
  batched.useDatabase(db);
  PetscCall(batched.solve(candidates));
  for (std::size_t k = 0; k < points.size(); ++k) PetscCall(scoreSamples(batched.history(static_cast<int>(k)), &(*scores)[k]));
  replaySeconds += MPI_Wtime() - start;
  batchedRuns += static_cast<int>(points.size());
  batches += batched.batches();
  PetscFunctionReturn(PETSC_SUCCESS);
}

double DriftCalibration::objective(const DeltaZScore &s) const {
  return objectiveName == "rms" ? s.rmsRelative : std::fabs(s.segregationError);
}

// k of a dimensionless law is a velocity: without -calibrate_kd_range its
// search spans 0.1 mm/s to 1 m/s instead of the 1/(m s) range of A and B.
PetscErrorCode DriftCalibration::searchRange(const std::string &model, double *lo, double *hi) const {
  std::unique_ptr<SizeLaw> law;
  PetscFunctionBeginUser;
  PetscCall(registry.sizeLaws().create(model, &law));
  const bool velocityUnit = std::string(law->unitOfK()) == "m/s";
  *lo = std::log10(rangeGiven || !velocityUnit ? kdLo : 1e-4);
  *hi = std::log10(rangeGiven || !velocityUnit ? kdHi : 1.0);
  PetscFunctionReturn(PETSC_SUCCESS);
}

// Every model: a coarse scan, then a golden section in the bracket around
// its best point.  The models' searches go in step, so that the replays of
// one stage (all scans, the first pairs, each next point) are one batch;
// each model's rows are recorded and printed in its own order (the scan,
// the pair, the section), as one model after the other would make them.
PetscErrorCode DriftCalibration::searchAll(std::vector<Result> *results) {
  struct Search {
    std::string model;
    std::vector<double> xs, fs;
    double a = 0, b = 0, c = 0, d = 0, fc = 0, fd = 0;
    bool lower = false; // the pending point is c (else d)
    std::vector<std::pair<double, DeltaZScore>> rows;
  };
  const int n = static_cast<int>(scanPoints);
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  std::vector<Search> searches(models.size());
  std::vector<Point> points;
  std::vector<DeltaZScore> scores;
  PetscFunctionBeginUser;
  for (std::size_t m = 0; m < models.size(); ++m) {
    Search &s = searches[m];
    s.model = models[m];
    double lo, hi;
    PetscCall(searchRange(s.model, &lo, &hi));
    for (int i = 0; i < n; ++i) {
      s.xs.push_back(lo + (hi - lo) * i / (n - 1));
      points.push_back({s.model, s.xs.back()});
    }
  }
  PetscCall(replayAll(points, &scores));
  points.clear();
  for (std::size_t m = 0; m < models.size(); ++m) {
    Search &s = searches[m];
    for (int i = 0; i < n; ++i) {
      s.rows.push_back({s.xs[i], scores[m * n + i]});
      s.fs.push_back(objective(scores[m * n + i]));
    }
    const int best = static_cast<int>(std::min_element(s.fs.begin(), s.fs.end()) - s.fs.begin());
    s.a = s.xs[std::max(0, best - 1)], s.b = s.xs[std::min(n - 1, best + 1)];
    s.c = s.b - g * (s.b - s.a), s.d = s.a + g * (s.b - s.a);
    points.push_back({s.model, s.c});
    points.push_back({s.model, s.d});
  }
  PetscCall(replayAll(points, &scores));
  for (std::size_t m = 0; m < models.size(); ++m) {
    Search &s = searches[m];
    s.rows.push_back({s.c, scores[2 * m]});
    s.rows.push_back({s.d, scores[2 * m + 1]});
    s.fc = objective(scores[2 * m]), s.fd = objective(scores[2 * m + 1]);
  }
  for (;;) { // the next point of every model whose bracket is still wider than the tolerance
    std::vector<Search *> active;
    points.clear();
    for (Search &s : searches) {
      if (!(s.b - s.a > tolerance)) continue;
      s.lower = s.fc < s.fd;
      if (s.lower) {
        s.b = s.d, s.d = s.c, s.fd = s.fc;
        s.c = s.b - g * (s.b - s.a);
      } else {
        s.a = s.c, s.c = s.d, s.fc = s.fd;
        s.d = s.a + g * (s.b - s.a);
      }
      active.push_back(&s);
      points.push_back({s.model, s.lower ? s.c : s.d});
    }
    if (active.empty()) break;
    PetscCall(replayAll(points, &scores));
    for (std::size_t k = 0; k < active.size(); ++k) {
      Search &s = *active[k];
      s.rows.push_back({points[k].log10kd, scores[k]});
      (s.lower ? s.fc : s.fd) = objective(scores[k]);
    }
  }
  results->clear();
  for (Search &s : searches) {
    PetscCall(PetscPrintf(comm, "model %s:\n  %12s %14s %12s %10s\n", s.model.c_str(), "k_d", "mean dz [mm]",
                          "Delta_seg [%]", "RMS/peak"));
    for (const auto &[x, score] : s.rows) {
      record(s.model, x, score);
      PetscCall(PetscPrintf(comm, "  %12.5g %14.4f %12.1f %10.4f\n", std::pow(10.0, x), 1e3 * score.meanModel,
                            score.segregationError, score.rmsRelative));
    }
    const int best = static_cast<int>(std::min_element(s.fs.begin(), s.fs.end()) - s.fs.begin());
    double xBest = s.fc < s.fd ? s.c : s.d;
    if (s.fs[best] < std::min(s.fc, s.fd)) xBest = s.xs[best];
    Result r;
    r.model = s.model;
    r.kd = std::pow(10.0, xBest);
    PetscCall(evaluate(s.model, xBest, &r.score)); // its cog.csv, kept as best-MODEL/cog.csv
    r.scored = true;
    PetscCall(keepBestRun(s.model));
    results->push_back(r);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

// k_d by weighted least squares on the measured drift relative to the bulk
// (fitDriftCoefficient with relativeToBulk), then one scored replay.
PetscErrorCode DriftCalibration::fitMeasured(const std::string &model, Result *result) {
  std::vector<double> table;
  int cols = 0;
  PetscFunctionBeginUser;
  PetscCall(db->readMatrix("measured_drift", &table, &cols));
  PetscCheck(!table.empty(), comm, PETSC_ERR_USER_INPUT,
             "-calibrate_from measured: database '%s' holds no measured drift (rcfd build from particle "
             "snapshots stores it; databases from other builders or older versions do not)",
             db->path().c_str());
  std::vector<MeasuredDrift::ClassDrift> drift;
  std::unique_ptr<SizeLaw> law;
  DriftFit fit;
  PetscCall(registry.sizeLaws().create(model, &law));
  PetscCall(collectively(comm, [&] {
    drift = measuredDriftFromTable(table, cols);
    measuredTable = table;
    fit = fitDriftLaw(drift, sauter, *law);
    // A law scaled by (a/a_bar)^n drifts on average meanFactor times as fast.
    result->model = model;
    result->kd = fit.kd / meanFactor;
    result->kdStandardError = fit.standardError / meanFactor;
    result->shape = fit.shape;
    result->chiSquarePerDof = fit.chiSquarePerDof;
    result->unit = law->unitOfK();
    for (std::size_t c = 0; c < drift.size(); ++c)
      lawRows.push_back({model, result->kd, result->unit, fit.shape, fit.chiSquare, fit.chiSquarePerDof, drift[c],
                         fit.predicted[c], fit.residual[c]});
  }, PETSC_ERR_USER_INPUT));
  PetscCheck(result->kd > 0.0, comm, PETSC_ERR_USER_INPUT,
             "-calibrate_from measured: the measured drift of '%s' gives k_d = %g for size law %s: the "
             "large particles do not sink relative to the bulk, so no drift law of this form fits",
             db->path().c_str(), result->kd, model.c_str());
  if (model == models.front())
    for (const auto &c : drift)
      PetscCall(PetscPrintf(comm, "  measured: d = %.4g mm (mass share %.3f): u = %+.3f +- %.3f mm/s relative to the bulk\n",
                            c.diameter * 1e3, c.massShare, c.velocity * 1e3, c.standardError * 1e3));
  std::string shapeText;
  SizeLaw::ShapeParameter p;
  if (law->shapeParameter(&p)) {
    char text[96];
    std::snprintf(text, sizeof text, std::isfinite(fit.shape) ? ", %s %.2f" : ", %s %g (not fitted: it needs three classes)",
                  p.option.c_str(), p.value);
    shapeText = text;
  }
  std::string residuals;
  for (double r : fit.residual) {
    char text[32];
    std::snprintf(text, sizeof text, "%s%+.2f", residuals.empty() ? "" : " ", r * 1e3);
    residuals += text;
  }
  PetscCall(PetscPrintf(comm, "model %s: k_d = %.4g +- %.2g %s%s from the measured drift (d32 %.4g mm%s); chi^2/dof %.4g, "
                              "residual per class [mm/s] %s\n",
                        model.c_str(), result->kd, result->kdStandardError, result->unit.c_str(), shapeText.c_str(),
                        sauter * 1e3, meanFactor != 1.0 ? ", divided by the mean agitation factor of the runs' drift" : "",
                        fit.chiSquarePerDof, residuals.c_str()));
  if (fitExponent) {
    std::vector<double> mean;
    int c1 = 0, c2 = 0;
    PetscCall(db->readMatrix("measured_drift_by_agitation", &byAgitationTable, &c1));
    PetscCall(db->readMatrix("measured_agitation_mean", &mean, &c2));
    PetscCheck(!byAgitationTable.empty() && mean.size() == 1, comm, PETSC_ERR_USER_INPUT,
               "-calibrate_exponent: database '%s' holds no measured drift by agitation (rcfd build from "
               "particle snapshots stores it from this version on)",
               db->path().c_str());
    AgitationDriftFit scaled;
    PetscCall(collectively(comm, [&] {
      scaled = fitAgitationExponent(driftByAgitationFromTable(byAgitationTable, c1), drift, mean[0], sauter, *law);
    }, PETSC_ERR_USER_INPUT));
    result->kd = scaled.kd;
    result->kdStandardError = 0.0;
    result->exponent = scaled.exponent;
    agitationMean = mean[0];
    PetscCall(PetscPrintf(comm, "model %s scaled by (a/a_bar)^n, a = leaving share (a_bar %.4g from the particles): "
                                "n = %.2f, k_d = %.4g %s, chi^2/dof %.3g\n",
                          model.c_str(), mean[0], scaled.exponent, scaled.kd, result->unit.c_str(),
                          scaled.chiSquarePerDof));
  }
  if (!referenceFile.empty()) {
    PetscCall(evaluate(model, std::log10(result->kd), &result->score, fitExponent ? result->exponent : -1.0,
                       result->shape));
    result->scored = true;
    PetscCall(keepBestRun(model));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The last evaluation's cog.csv (the best k_d's run) kept as best-<model>/cog.csv.
PetscErrorCode DriftCalibration::keepBestRun(const std::string &model) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(collectively(comm, [&] {
    if (rank != 0) return;
    namespace fs = std::filesystem;
    const fs::path dir = fs::path(outputDirectory) / ("best-" + model);
    fs::create_directories(dir);
    fs::copy_file(fs::path(outputDirectory) / "cog.csv", dir / "cog.csv", fs::copy_options::overwrite_existing);
  }, PETSC_ERR_FILE_WRITE));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode DriftCalibration::writeFiles() const {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  auto number = [](double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", v);
    return std::string(text);
  };
  PetscCall(collectively(comm, [&] {
    if (rank != 0) return;
    std::ostringstream scanCsv, bestCsv;
    scanCsv << "# rcfd calibrate: every replay, in the order run; Delta_seg is Eq. 7 over [" << windowBegin
            << ", " << windowEnd << "] s, rms_over_peak the RMS of Delta z(t) - reference / reference peak\n"
            << "model,kd,mean_run_m,mean_reference_m,delta_seg_percent,rms_over_peak\n";
    for (const ScanRow &r : scan)
      scanCsv << r.model << ',' << number(r.kd) << ',' << number(r.score.meanModel) << ','
              << number(r.score.meanRef) << ',' << number(r.score.segregationError) << ','
              << number(r.score.rmsRelative) << '\n';
    bestCsv << "# rcfd calibrate: the best k_d of every model (from " << source << (source == "cog" ? ", objective " + objectiveName : std::string())
            << "); scores of its run (best-MODEL/cog.csv), empty without a reference\n"
            << "model,source,kd,kd_standard_error,agitation_exponent,d32_m,delta_seg_percent,rms_over_peak,mean_run_m,"
               "mean_reference_m,kd_unit,shape_parameter,chi2_per_dof\n";
    auto optional = [&](double v) { return std::isfinite(v) ? number(v) : std::string(); };
    for (const Result &r : best) {
      bestCsv << r.model << ',' << source << ',' << number(r.kd) << ',' << number(r.kdStandardError) << ','
              << number(r.exponent) << ',' << number(sauter);
      if (r.scored)
        bestCsv << ',' << number(r.score.segregationError) << ',' << number(r.score.rmsRelative) << ','
                << number(r.score.meanModel) << ',' << number(r.score.meanRef);
      else
        bestCsv << ",,,,";
      bestCsv << ',' << r.unit << ',' << optional(r.shape) << ',' << optional(r.chiSquarePerDof) << '\n';
    }
    std::filesystem::create_directories(outputDirectory);
    // A stored table as CSV: a comment, the header, the rows (each ending with `extra`).
    auto writeTable = [&](const std::string &name, const std::string &comment, const std::string &header,
                          const std::vector<double> &table, int cols, const std::string &extra) {
      if (table.empty()) return;
      std::ostringstream m;
      m << "# rcfd calibrate: " << comment << "\n" << header << "\n";
      for (std::size_t r = 0; r < table.size(); r += cols) {
        for (int c = 0; c < cols; ++c) m << (c ? "," : "") << number(table[r + c]);
        m << extra << '\n';
      }
      writeTextAtomically(outputDirectory + "/" + name, m.str());
    };
    writeTable("measured_drift.csv",
               "the drift rcfd build measured in " + db->path() +
                   ", relative to the bulk solid of each cell; d32_m is the runs' inventory d32",
               "diameter_m,velocity_m_s,standard_error_m_s,particles,frames,mass_share,d32_m", measuredTable,
               kMeasuredDriftColumns, "," + number(sauter));
    writeTable("measured_drift_by_agitation.csv",
               "the measured drift of " + db->path() +
                   " by the leaving share of the particle's cell (bins of 0.1); mass_share within the bin",
               "agitation,diameter_m,velocity_m_s,standard_error_m_s,particles,frames,mass_share,agitation_mean",
               byAgitationTable, kDriftByAgitationColumns, "," + number(agitationMean));
    if (!lawRows.empty()) {
      std::ostringstream fits;
      fits << "# rcfd calibrate: every size law fitted to the drift measured in " << db->path()
           << " relative to the bulk, u_i = k (g_i - sum_j s_j g_j), weights 1/se^2; one row per law and class; "
              "law_m_s is the fitted law's u, residual_m_s measured - law; shape_parameter: power's m (fitted)\n"
           << "model,kd,kd_unit,shape_parameter,chi2,chi2_per_dof,d32_m,diameter_m,mass_share,velocity_m_s,"
              "standard_error_m_s,law_m_s,residual_m_s\n";
      for (const LawRow &r : lawRows)
        fits << r.model << ',' << number(r.kd) << ',' << r.unit << ',' << optional(r.shape) << ','
             << number(r.chiSquare) << ',' << number(r.chiSquarePerDof) << ',' << number(sauter) << ','
             << number(r.measured.diameter) << ',' << number(r.measured.massShare) << ','
             << number(r.measured.velocity) << ',' << number(r.measured.standardError) << ','
             << number(r.predicted) << ',' << number(r.residual) << '\n';
      writeTextAtomically(outputDirectory + "/measured_law_fits.csv", fits.str());
    }
    writeTextAtomically(outputDirectory + "/calibrate_scan.csv", scanCsv.str());
    writeTextAtomically(outputDirectory + "/calibrate_best.csv", bestCsv.str());
  }, PETSC_ERR_FILE_WRITE));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// -calibrate_candidates FILE: lines NAME OPTIONS...; '#' starts a comment.
// Every replay writes OUTPUT_DIR/NAME/cog.csv; with -reference each is
// scored (calibrate_candidates.csv).
PetscErrorCode DriftCalibration::runCandidates() {
  std::vector<std::pair<std::string, std::string>> laws;
  PetscFunctionBeginUser;
  PetscCall(collectively(comm, [&] {
    requireRegularFile(candidatesFile);
    std::ifstream in(candidatesFile);
    if (!in) throw std::invalid_argument("-calibrate_candidates: cannot open '" + candidatesFile + "'");
    int number = 0;
    for (std::string line; std::getline(in, line);) {
      ++number;
      std::istringstream words(line.substr(0, line.find('#')));
      std::string name, options;
      if (!(words >> name)) continue;
      std::getline(words, options);
      options.erase(0, std::min(options.size(), options.find_first_not_of(" \t")));
      options.erase(options.find_last_not_of(" \t\r") + 1);
      const std::string where = "-calibrate_candidates '" + candidatesFile + "', line " + std::to_string(number);
      if (name.find('/') != std::string::npos || name == "." || name == "..")
        throw std::invalid_argument(where + ": the name '" + name + "' is not a directory name (its cog.csv goes in OUTPUT_DIR/NAME)");
      for (const auto &l : laws)
        if (l.first == name) throw std::invalid_argument(where + ": the name '" + name + "' is given twice");
      laws.push_back({name, options});
    }
    if (laws.empty())
      throw std::invalid_argument("-calibrate_candidates '" + candidatesFile +
                                  "' names no replay (one a line: NAME then its drift options)");
  }, PETSC_ERR_USER_INPUT));
  const double start = MPI_Wtime();
  std::vector<std::vector<BedSample>> samples(laws.size());
  std::vector<BatchedReplay::Candidate> candidates;
  for (const auto &l : laws) candidates.push_back({outputDirectory + "/" + l.first, l.second, nullptr});
  BatchedReplay batched(comm, registry);
  batched.useRegistries(registries);
  batched.useDatabase(db);
  if (canBatch && laws.size() > 1) {
    PetscCall(batched.solve(candidates));
    for (std::size_t k = 0; k < laws.size(); ++k) samples[k] = batched.history(static_cast<int>(k));
    batchedRuns += static_cast<int>(laws.size());
    batches += batched.batches();
  } else {
    for (std::size_t k = 0; k < laws.size(); ++k) {
      const std::unique_ptr<Run> run = newRun();
      PetscCall(batched.solveAlone(candidates[k], *run));
      samples[k] = run->history();
    }
  }
  replaySeconds += MPI_Wtime() - start;
  count = static_cast<int>(laws.size());
  std::ostringstream table;
  table << "# rcfd calibrate -calibrate_candidates " << candidatesFile << ": every replay (cog.csv in OUTPUT_DIR/NAME); "
        << "Delta_seg is Eq. 7 over [" << windowBegin << ", " << windowEnd << "] s, rms_over_peak the RMS of "
        << "Delta z(t) - reference / reference peak (empty without -reference)\n"
        << "name,options,mean_run_m,mean_reference_m,delta_seg_percent,rms_over_peak\n";
  PetscCall(PetscPrintf(comm, "  %-24s %14s %12s %10s\n", "replay", "mean dz [mm]", "Delta_seg [%]", "RMS/peak"));
  for (std::size_t k = 0; k < laws.size(); ++k) {
    char row[160];
    if (!referenceFile.empty()) {
      DeltaZScore score;
      PetscCall(scoreSamples(samples[k], &score));
      PetscCall(PetscPrintf(comm, "  %-24s %14.4f %12.1f %10.4f\n", laws[k].first.c_str(), 1e3 * score.meanModel,
                            score.segregationError, score.rmsRelative));
      std::snprintf(row, sizeof row, "%.9g,%.9g,%.9g,%.9g", score.meanModel, score.meanRef, score.segregationError,
                    score.rmsRelative);
    } else {
      PetscCall(PetscPrintf(comm, "  %-24s (no -reference: not scored)\n", laws[k].first.c_str()));
      std::snprintf(row, sizeof row, ",,,");
    }
    std::string options = laws[k].second;
    std::replace(options.begin(), options.end(), ',', ' '); // one CSV field
    table << laws[k].first << ',' << options << ',' << row << '\n';
  }
  PetscMPIInt rank;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(collectively(comm, [&] {
    if (rank == 0) writeTextAtomically(outputDirectory + "/calibrate_candidates.csv", table.str());
  }, PETSC_ERR_FILE_WRITE));
  PetscCall(PetscPrintf(comm, "%d replay runs; wrote %s/calibrate_candidates.csv and NAME/cog.csv\n", count,
                        outputDirectory.c_str()));
  PetscCall(reportReplays());
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode DriftCalibration::reportReplays() const {
  PetscFunctionBeginUser;
  PetscCall(PetscPrintf(comm, "replays: %.3g s wall; %d of %d in %d batched state(s)%s\n", replaySeconds, batchedRuns,
                        count, batches, batch ? "" : " (-calibrate_batch false)"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode DriftCalibration::solve() {
  PetscFunctionBeginUser;
  best.clear();
  scan.clear();
  lawRows.clear();
  if (!candidatesFile.empty()) {
    PetscCall(runCandidates());
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  if (source == "cog")
    PetscCall(PetscPrintf(comm,
                          "Calibrating k_d in [%g, %g] 1/(m s) against %s, objective %s (%s), "
                          "Eq. 7 window [%g, %g] s\n",
                          kdLo, kdHi, referenceFile.c_str(), objectiveName.c_str(),
                          objectiveName == "rms" ? "RMS of the Delta z(t) difference / reference peak"
                                                 : "|Delta_seg|",
                          windowBegin, windowEnd));
  else
    PetscCall(PetscPrintf(comm, "Fitting k_d to the measured drift of %s\n", db->path().c_str()));
  std::vector<Result> results;
  if (source == "cog") PetscCall(searchAll(&results));
  for (std::size_t m = 0; m < models.size(); ++m) {
    const std::string &model = models[m];
    Result r;
    if (source == "cog") r = results[m];
    else PetscCall(fitMeasured(model, &r));
    best.push_back(r);
    if (r.scored) PetscCall(PetscPrintf(comm,
                          "model %s: best k_d = %.4g 1/(m s): Delta_seg %.1f %%, RMS/peak %.3f, "
                          "mean dz %.4g mm (reference %.4g mm)\n",
                          model.c_str(), r.kd, r.score.segregationError, r.score.rmsRelative,
                          1e3 * r.score.meanModel, 1e3 * r.score.meanRef));
  }
  PetscCall(writeFiles());
  PetscCall(PetscPrintf(comm, "%d replay runs; wrote %s/calibrate_scan.csv, calibrate_best.csv and best-MODEL/cog.csv\n",
                        count, outputDirectory.c_str()));
  PetscCall(reportReplays());
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
