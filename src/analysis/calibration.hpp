// Calibration of the drift coefficient: the k_d that best reproduces a
// reference's segregation curve Delta z(t).  For each drift model, replay
// runs on the database (in-process, one Run per evaluation, sharing the
// loaded database; the drift operator of the run's -pipeline set through its
// typed setters) are scored against the reference with scoreDeltaZ(); a
// coarse scan of log10 k_d brackets the minimum and a golden-section search
// refines it.  With -calibrate_from measured, k_d is instead fitted in
// seconds to the drift rcfd build measured from the particles (the
// database's /extra/measured_drift, analysis/measured_drift.hpp), and one
// replay per model scores the fit when a reference is given.  The scan, the
// best parameters and scores of every model (calibrate_scan.csv,
// calibrate_best.csv), each model's best run (best-<model>/cog.csv) and, on
// the measured path, the measured drift (measured_drift.csv; figure:
// src/cli/figures/drift_law_form.py) are written to the output directory.
// Replays that share the database and the path (the coarse scan of every
// model, the golden section's first pair, the laws of
// -calibrate_candidates) run as one batched state (analysis/batched_replay.hpp):
// the same numbers bit for bit, each frame's shift read once for all;
// -calibrate_batch false runs them one by one (the default above 20,000 cells
// per rank, where a batch leaves the cache and runs slower).
#pragma once

#include "analysis/measured_drift.hpp"
#include "analysis/segregation_score.hpp"
#include "rcfd/observables.hpp"
#include "rcfd/operator.hpp"
#include "rcfd/plugin.hpp"

#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace rcfd {

class AgitationField;
class Database;
class Run;

class DriftCalibration {
public:
  struct Result {
    std::string model;
    double kd;                  ///< best k_d [the size law's unit]
    double kdStandardError = 0; ///< from the measured drift's spread (measured path)
    double exponent = 0;        ///< of the agitation scaling (a/a_bar)^n, with -calibrate_exponent
    double shape = std::numeric_limits<double>::quiet_NaN(); ///< the law's fitted shape parameter (power: m), measured path
    double chiSquarePerDof = std::numeric_limits<double>::quiet_NaN(); ///< of the measured fit
    std::string unit = "1/(m s)"; ///< of kd (the size law's)
    bool scored = false;        ///< a reference was given and a run made
    DeltaZScore score;          ///< of the run at that k_d
  };

  /// The registry supplies the run's operators; it must outlive the calibration.
  DriftCalibration(MPI_Comm comm, const OperatorRegistry &registry);
  /// All the program's registries (operators, paths, switching rules,
  /// monitors, with what plugins added); they must outlive the calibration.
  DriftCalibration(MPI_Comm comm, const Registries &registries);
  ~DriftCalibration();

  /// Its own options are read as -<prefix>calibrate_... (default: no prefix).
  void setOptionsPrefix(const std::string &p) { prefix = p; }
  /// Reads -reference, -calibrate_from, -calibrate_models (any registered
  /// size laws, rcfd/size_law.hpp), -calibrate_objective,
  /// -calibrate_kd_range, -calibrate_tolerance, -calibrate_scan,
  /// -rcfd_time_offset, -score_window, -calibrate_batch and
  /// -calibrate_candidates FILE (lines "NAME OPTIONS...": replays of given
  /// drift options, scored; no search).  Collective.
  PetscErrorCode setFromOptions();
  /// Reads the reference and loads the database through a first run, which
  /// reads the run's options (so that unknown options can be refused after
  /// this).  The runs are silent, write no fields and put their cog.csv in
  /// -output_dir (default rcfd-calibrate), overwritten by each evaluation.
  PetscErrorCode setUp();
  /// Searches every model and prints a table of the evaluations.  Collective.
  PetscErrorCode solve();

  const std::vector<Result> &results() const { return best; }
  int evaluations() const { return count; }

  /// One replay of a search: model, log10 k_d, exponent of (a/a_bar)^n
  /// (< 0: unscaled), the law's shape parameter (NaN: its default).
  struct Point {
    std::string model;
    double log10kd;
    double exponent = -1.0;
    double shape = std::numeric_limits<double>::quiet_NaN();
  };

private:
  // exponent >= 0: scaled by (a/a_bar)^n, a = leaving share; shape: the
  // law's shape parameter (NaN: its default).
  PetscErrorCode evaluate(const std::string &model, double log10kd, DeltaZScore *score, double exponent = -1.0,
                          double shape = std::numeric_limits<double>::quiet_NaN());
  // The points' scores, batched where possible, in their order; not recorded.
  PetscErrorCode replayAll(const std::vector<Point> &points, std::vector<DeltaZScore> *scores);
  PetscErrorCode configureDrift(Run &run, const Point &p);
  PetscErrorCode replayOne(const Point &p, DeltaZScore *score);
  PetscErrorCode scoreSamples(const std::vector<BedSample> &samples, DeltaZScore *score) const;
  void record(const std::string &model, double log10kd, const DeltaZScore &score);
  PetscErrorCode runCandidates(); // -calibrate_candidates
  PetscErrorCode reportReplays() const;
  PetscErrorCode fitMeasured(const std::string &model, Result *result);
  PetscErrorCode keepBestRun(const std::string &model);
  PetscErrorCode writeFiles() const;
  double objective(const DeltaZScore &s) const;
  // Every model's search, in step (one batch per stage); results in the order of `models`.
  PetscErrorCode searchAll(std::vector<Result> *results);
  // Its drift law's log10 k_d range of the search.
  PetscErrorCode searchRange(const std::string &model, double *lo, double *hi) const;

  MPI_Comm comm;
  std::string prefix; // of the calibration's own options
  const OperatorRegistry &registry;
  const Registries *registries = nullptr; // all of them, when given
  // A run with the calibration's registries.
  std::unique_ptr<Run> newRun() const;
  std::string referenceFile, objectiveName = "rms"; // rms: RMS/peak of the curve; seg: |Delta_seg|
  std::string source = "cog";                       // cog: replays against -reference; measured: regression
  std::string outputDirectory;                      // the runs' -output_dir
  double sauter = 0.0;                              // the runs' inventory d32 [m]
  double meanFactor = 1.0;                          // of the runs' drift scaled by agitation
  std::vector<std::string> models{"B"};
  double offset = 0.0, windowBegin = 0.5, windowEnd = 1.5;
  double kdLo = 1e2, kdHi = 1e6, tolerance = 0.01; // tolerance in log10 k_d
  bool rangeGiven = false; // else laws with k in m/s search 1e-4 to 1 m/s
  PetscInt scanPoints = 9;
  DeltaZSeries reference;
  std::shared_ptr<Database> db;
  std::vector<Result> best;
  struct ScanRow {
    std::string model;
    double kd;
    DeltaZScore score;
  };
  std::vector<ScanRow> scan;
  std::vector<double> measuredTable; // the database's measured drift (measured path)
  // Every law's fit per class (measured path): measured_law_fits.csv.
  struct LawRow {
    std::string model;
    double kd;
    std::string unit;
    double shape, chiSquare, chiSquarePerDof;
    MeasuredDrift::ClassDrift measured;
    double predicted, residual;
  };
  std::vector<LawRow> lawRows;
  std::vector<double> byAgitationTable; // and by agitation (with -calibrate_exponent)
  PetscBool fitExponent = PETSC_FALSE;  // -calibrate_exponent
  double agitationMean = 0.0;           // a bar of the measured drift by agitation
  std::shared_ptr<const AgitationField> leaving; // shared by the scaled runs
  int count = 0;
  PetscBool batch = PETSC_TRUE;   // -calibrate_batch
  PetscBool batchSet = PETSC_FALSE;
  /// Without -calibrate_batch, batched up to this many cells per rank: on
  /// dpm-bi-narrow's 1,920 cells a batch of 13 laws takes 0.84 of the one-by-one
  /// time, on the 56,000-cell default bed 1.1-1.4 (docs/performance.md).
  static constexpr PetscInt kBatchCellsPerRank = 20000;
  bool canBatch = false;          // and the runs' options allow it
  int batchedRuns = 0, batches = 0;
  double replaySeconds = 0.0;     // wall time of all replays
  std::string candidatesFile;     // -calibrate_candidates
};

} // namespace rcfd
