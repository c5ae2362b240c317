// Studies as short programs: a drift law's k_d calibrated against a
// reference, an ensemble of stitched paths, and runs compared with a
// reference -- the library behind `rcfd calibrate`, `rcfd run -ensemble N`
// and `rcfd compare` (docs/extending.md, "Studies";
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

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace rcfd {

/// How a curve over time of a run agrees with the reference's (Delta z(t),
/// a class's z_CoG,i - z_CoG,bed, the bottom layer's d32): the paper's Eq. 7
/// over a window, and the RMS of the difference over the times both cover.
struct CurveAgreement {
  double windowBegin = 0.0, windowEnd = 0.0; ///< s, the Eq. 7 window
  double meanReference = 0.0, meanRun = 0.0; ///< means over the window, each over its own samples [m]
  double segregationError = 0.0;             ///< Eq. 7: (meanRun - meanReference) / meanReference [%]
  double rms = 0.0;                          ///< m, RMS of run - reference over the overlap
  double rmsRelative = 0.0;                  ///< rms / peakReference
  std::size_t samplesReference = 0;          ///< the reference's samples in the window
  std::size_t samplesRun = 0;                ///< the run's samples in the window
  double overlapBegin = 0.0, overlapEnd = 0.0; ///< s, the times both curves cover
  std::size_t overlapSamples = 0;            ///< the run's samples there (the RMS is over them,
                                             ///< the reference interpolated linearly)
  double peakReference = 0.0;                ///< m, the reference's largest |value| in the overlap
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
  /// The members' drift: size law `sizeLaw` (a name of the registries' size
  /// laws, with its default parameters) and k_d = `kd` in the law's unit,
  /// over what -drift_size_law and -drift_kd say; the drift operator of
  /// -pipeline gets them as a calibration's replays do, so that the members
  /// run the law the calibration fitted.  An unknown law or a k_d that is not
  /// positive and finite is refused here, a -pipeline without drift in
  /// setUp(), each in one sentence.
  PetscErrorCode setDriftLaw(const std::string &sizeLaw, double kd);
  /// The same with a calibration's result: its model and kd (what Result
  /// holds; a run scaled by agitation, -calibrate_exponent, is not handed over).
  PetscErrorCode setDriftLaw(const Calibration::Result &fit);
  /// Refuses a path without a seed, a run on several databases and a drift
  /// law set without a drift operator in -pipeline, each in one sentence.
  PetscErrorCode setUp();
  /// Runs the members and writes ensemble.csv (on rank 0).
  PetscErrorCode solve();
  /// The members, the seeds, the drift law when set and the file of the summary.
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

/// Runs' answers against a reference's: everything rcfd compare scores (it
/// prints and draws what this computes).  The reference's header decides the
/// kind, and every run's file must be of it:
///  - centres of gravity (a cog.csv of rcfd run or rcfd reference, or an
///    ensemble's ensemble.csv, mean columns): Delta z(t) over every window
///    (scores()); every size class's z_CoG,i - z_CoG,bed against the
///    reference's, classes matched by diameter within 1 % (classScores());
///    and the poly-disperse number E = sqrt(sum_i w_i RMS_i^2) of each run,
///    w_i the run's mass shares (else the reference's) over the matched
///    classes (polydisperse());
///  - bottom layer (bottom.csv): every d32_*_m curve over every window (scores());
///  - vertical profiles (profiles.csv): every class's alpha and alpha_total
///    layer by layer (profileScores());
///  - the halves' size distributions (halves.csv): each class's mass fraction
///    in the bottom and top halves and the halves' Sauter diameters (halvesScores()).
/// Reads files only: collective, but every rank reads them; what is written
/// is written by rank 0.  Errors name the file at fault in one sentence.
class Comparison {
public:
  /// The kind of the files compared.
  enum class Kind { centresOfGravity, bottomLayer, profiles, halves };

  /// A curve over time over one window: curve delta_z or d32_<name> (scores()),
  /// class_<label> (classScores(): z_CoG,i - z_CoG,bed, label e.g. d1.950mm).
  struct Score {
    std::string run;   ///< the run's label
    std::string curve; ///< delta_z, d32_bottom, class_d1.950mm, ...
    CurveAgreement agreement;
  };
  /// One run's poly-disperse number.
  struct Polydisperse {
    std::string run;
    std::size_t runIndex = 0;     ///< the run's place in the order of addRun()
    double rms = 0.0;             ///< E [m]
    double rmsRelative = 0.0;     ///< E / peakLargest
    std::string largestClass;     ///< class_<label> of the largest diameter matched
    double peakLargest = 0.0;     ///< m, its reference's peak |z_CoG,i - z_CoG,bed|
    std::vector<double> weights;  ///< w_i, in the reference's class order (matched classes)
    std::string weightsFrom;      ///< the file whose mass columns gave them
    double overlapBegin = 0.0, overlapEnd = 0.0; ///< s, the largest class's overlap
    std::size_t overlapSamples = 0;
  };
  /// One vertical profile, over the layers where either bed holds solid.
  struct ProfileScore {
    std::string run, curve;            ///< curve alpha_d<D>mm or alpha_total
    std::size_t layers = 0;
    double zBegin = 0.0, zEnd = 0.0;   ///< m, the lowest and highest layer used
    double rms = 0.0, maxAbs = 0.0;    ///< of alpha_run - alpha_reference
    double peakReference = 0.0, rmsRelative = 0.0;
  };
  /// One class of the halves (a mass fraction), or their Sauter diameters
  /// (label d32, diameter 0, values in m).
  struct HalvesScore {
    std::string run, label;
    double diameter = 0.0; ///< m
    double bottomReference = 0.0, bottomRun = 0.0, topReference = 0.0, topRun = 0.0;
  };
  /// The bed dynamics Delta z_CoG = mean |z_CoG - mean z_CoG| of two beds and
  /// the database distance |a - b| / b.
  struct DatabaseDistance {
    double dynamicsA = 0.0, dynamicsB = 0.0; ///< m
    std::size_t framesA = 0, framesB = 0;    ///< frames of a database; 0 for a file
    double distance = 0.0;
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
  /// Reads the files' headers: the kind, and that every run's file is of it
  /// (a bed-dynamics file is refused: see databaseDistance()).  solve() calls
  /// it when it was not called.
  PetscErrorCode setUp();
  /// Reads and scores; a run without a curve of the reference, or a window a
  /// curve misses, is refused with a sentence naming the file.
  PetscErrorCode solve();
  /// One line per run, curve and window (or profile, or class of the halves),
  /// then each run's poly-disperse number.
  PetscErrorCode view(PetscViewer viewer) const;

  /// Once set up.
  Kind kind() const { return fileKind; }
  const std::vector<Score> &scores() const { return scored; }
  const std::vector<Score> &classScores() const { return classScored; }
  const std::vector<Polydisperse> &polydisperse() const { return polydisperseScored; }
  /// Why a class or a poly-disperse number was not scored (a class only one side has, ...).
  const std::vector<std::string> &notes() const { return why; }
  const std::vector<ProfileScore> &profileScores() const { return profiles; }
  const std::vector<HalvesScore> &halvesScores() const { return halves; }

  /// Once solved, curves over time only: the curves at the reference's times
  /// (time_s, <curve>_reference_m, <curve>_<label>_m per run; empty outside a
  /// run's times) and, when classes were scored, theirs in classCurvesFile(file).
  PetscErrorCode writeCurves(const std::string &file) const;
  /// delta_z.csv -> delta_z-classes.csv.
  static std::string classCurvesFile(const std::string &curvesFile);
  /// Once solved: one row per score (curves, then classes, then each run's
  /// poly-disperse number; or profiles; or halves), units in the header.
  PetscErrorCode writeScores(const std::string &file) const;

  /// Collective.  The database distance between two bed dynamics, each a
  /// database (.h5 or .hdf5, its frames' bed centres), a cog.csv (its
  /// z_cog_bed_m column; an ensemble summary is refused) or a bed_dynamics.csv;
  /// b with no bed dynamics is refused.
  static PetscErrorCode databaseDistance(MPI_Comm comm, const std::string &a, const std::string &b,
                                         DatabaseDistance *distance);

private:
  struct Impl; // src/analysis/study_comparison.cpp
  std::unique_ptr<Impl> impl;
  MPI_Comm comm;
  std::string reference;
  std::vector<std::string> files, labels;
  std::vector<double> windows{0.5, 1.5};
  double offset = 0.0;
  bool isSetUp = false;
  Kind fileKind = Kind::centresOfGravity;
  std::vector<Score> scored, classScored;
  std::vector<Polydisperse> polydisperseScored;
  std::vector<std::string> why;
  std::vector<ProfileScore> profiles;
  std::vector<HalvesScore> halves;
};

} // namespace rcfd
