// Studies as short programs: a drift law's k_d calibrated against a
// reference, an ensemble of stitched paths, and runs compared with a
// reference -- the library behind `rcfd calibrate`, `rcfd run -ensemble N`
// and the Delta z scores of `rcfd compare` (docs/extending.md, "Studies";
// docs/examples/study is such a program, built against the installed package
// by the test suite).
//
// Each has PETSc's life cycle (collective on its communicator): construct
// with the program's registries (rcfd/plugin.hpp: built-ins, your own
// additions, plugins) -> setFromOptions() -> setters -> setUp() -> solve()
// -> view().  Every function returns a PetscErrorCode; nothing throws.
#pragma once

#include "rcfd/database.hpp"
#include "rcfd/plugin.hpp"

#include <memory>
#include <string>
#include <vector>

namespace rcfd {

/// How a curve Delta z(t) of a run agrees with the reference's: the paper's
/// Eq. 7 over a window and the RMS of the difference where both have samples.
struct CurveAgreement {
  double windowBegin = 0.0, windowEnd = 0.0; ///< s, the Eq. 7 window
  double meanReference = 0.0, meanRun = 0.0; ///< m, means over the window
  double segregationError = 0.0;             ///< Eq. 7: (meanRun - meanReference) / meanReference [%]
  double rms = 0.0;                          ///< m, RMS of run - reference over the overlap
  double rmsRelative = 0.0;                  ///< rms / the reference's peak
};

/// The drift coefficient k_d of one or more size laws that best reproduces a
/// reference's segregation curve (rcfd calibrate): replays on the loaded
/// database, a coarse scan and a golden section, batched where they share
/// the path.  Writes calibrate_scan.csv, calibrate_best.csv and
/// best-MODEL/cog.csv into the runs' -output_dir (default rcfd-calibrate).
class Calibration {
public:
  struct Result {
    std::string model;          ///< the size law (-calibrate_models)
    double kd = 0.0;            ///< best k_d, in `unit`
    std::string unit;           ///< the size law's unit of k_d
    double kdStandardError = 0; ///< from the measured drift's spread (-calibrate_from measured)
    bool scored = false;        ///< a reference was given and a run made at kd
    CurveAgreement agreement;   ///< of that run, when scored
  };

  /// The registries must outlive the calibration.
  Calibration(MPI_Comm comm, const Registries &registries);
  ~Calibration();
  Calibration(const Calibration &) = delete;
  Calibration &operator=(const Calibration &) = delete;

  /// The calibration's own options are read as -<prefix>calibrate_..., -<prefix>reference,
  /// -<prefix>score_window, ... (default: no prefix, as rcfd calibrate reads them); the
  /// runs read the run options (rcfd run -help).  Before setFromOptions().
  void setOptionsPrefix(const std::string &prefix);
  /// Reads -reference, -calibrate_from, -calibrate_models, -calibrate_objective,
  /// -calibrate_kd_range, -calibrate_tolerance, -calibrate_scan, -rcfd_time_offset,
  /// -score_window, -calibrate_batch, -calibrate_candidates (rcfd calibrate -help),
  /// and -calibrate_view [viewer]: view() at the end of solve().
  PetscErrorCode setFromOptions();
  /// Reads the reference and loads the database through a first run.
  PetscErrorCode setUp();
  /// Searches every size law, printing the evaluations, and writes the files.
  PetscErrorCode solve();
  /// One line per size law: its best k_d and, when scored, its agreement.
  PetscErrorCode view(PetscViewer viewer) const;

  const std::vector<Result> &results() const { return best; }
  /// Replays run by solve().
  int evaluations() const;

private:
  struct Impl; // src/analysis/study.cpp
  std::unique_ptr<Impl> impl;
  std::vector<Result> best;
};

/// The same case run along several stitched paths with seeds s, s+1, ...
/// (s: -path_seed), sharing one loaded database (rcfd run -ensemble N).  Each
/// member writes OUTPUT/member_k/ (fields off); OUTPUT/ensemble.csv holds the
/// mean and the sample standard deviation of every cog.csv column.
class Ensemble {
public:
  /// The registries must outlive the ensemble.
  Ensemble(MPI_Comm comm, const Registries &registries);
  ~Ensemble();
  Ensemble(const Ensemble &) = delete;
  Ensemble &operator=(const Ensemble &) = delete;

  /// Number of members (at least 1; default 2).
  PetscErrorCode setMembers(int members);
  /// Lets the first member read the run options (rcfd run -help): every
  /// member reads the same ones and then gets its own seed and directory.
  /// -ensemble_view [viewer]: view() at the end of solve().
  PetscErrorCode setFromOptions();
  /// Use an already loaded database instead of -db (e.g. the calibration's).
  void useDatabase(std::shared_ptr<Database> database);
  /// Refuses a path without a seed and a run on several databases, each in
  /// one sentence.
  PetscErrorCode setUp();
  /// Runs the members and writes ensemble.csv (on rank 0).
  PetscErrorCode solve();
  /// The members, the seeds and the file of the summary.
  PetscErrorCode view(PetscViewer viewer) const;

  int members() const { return count; }
  const std::string &outputDirectory() const { return directory; }
  /// OUTPUT/ensemble.csv, once solved.
  std::string summaryFile() const { return directory + "/ensemble.csv"; }
  /// Each member's total mass [kg] (all fractions) at its start and at its end, once solved.
  const std::vector<double> &initialMasses() const { return massBefore; }
  const std::vector<double> &finalMasses() const { return massAfter; }

private:
  struct Impl; // src/analysis/study.cpp
  std::unique_ptr<Impl> impl;
  int count = 2;
  std::string directory;
  std::vector<double> massBefore, massAfter;
};

/// Curves over time of runs against a reference (the Delta z part of rcfd
/// compare): every curve of the reference's centre-of-gravity file (cog.csv,
/// or an ensemble's ensemble.csv, mean columns) or bottom-layer file that a
/// run's file has too, over every window.  Reads files only: collective, but
/// every rank reads them.
class Comparison {
public:
  struct Score {
    std::string run;   ///< the run's label
    std::string curve; ///< delta_z, d32_bottom, ...
    CurveAgreement agreement;
  };

  explicit Comparison(MPI_Comm comm);
  ~Comparison();
  Comparison(const Comparison &) = delete;
  Comparison &operator=(const Comparison &) = delete;

  PetscErrorCode setReference(const std::string &file);
  /// A run's file of the reference's kind and its label (default: the file).
  PetscErrorCode addRun(const std::string &file, const std::string &label = "");
  /// Eq. 7 windows [s] in the reference's time (default: 0.5 to 1.5 s).
  PetscErrorCode setWindows(const std::vector<double> &beginEndPairs);
  /// Physical time of the runs' frame 0 [s], added to their times.
  void setTimeOffset(double seconds) { offset = seconds; }
  /// Reads and scores; a run without a curve of the reference, or a window
  /// a curve misses, is refused with a sentence naming the file.
  PetscErrorCode solve();
  /// One line per run, curve and window.
  PetscErrorCode view(PetscViewer viewer) const;

  const std::vector<Score> &scores() const { return scored; }

private:
  MPI_Comm comm;
  std::string reference;
  std::vector<std::string> files, labels;
  std::vector<double> windows{0.5, 1.5};
  double offset = 0.0;
  std::vector<Score> scored;
};

} // namespace rcfd
