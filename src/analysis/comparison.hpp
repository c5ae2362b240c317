// rcfd compare's side of the answers a run and a reference write: which
// file is which, curves over time (Delta z of cog.csv and ensemble.csv, the
// bottom layer's Sauter diameter of bottom.csv) scored over one or more
// windows, and the bed dynamics of a file for the database distance.
// Profiles and halves: profile_comparison.hpp.  Serial and PETSc-free; every
// error is a std::runtime_error whose message names the file at fault.
#pragma once

#include "analysis/segregation_score.hpp"

#include <string>
#include <vector>

namespace rcfd {

/// The files rcfd run and rcfd reference write that compare reads.
enum class AnswerFile {
  centresOfGravity, // cog.csv, or an ensemble's ensemble.csv (mean columns)
  bottomLayer,      // bottom.csv: time_s,d32_bottom_m,... (+ d32_<zone>_m)
  profiles,         // profiles.csv: z,alpha_d<D>mm,...,alpha_total
  halves,           // halves.csv: class,diameter,bottom_mass_fraction,top_mass_fraction
  bedDynamics,      // bed_dynamics.csv: samples,mean_z_cog_m,delta_z_cog_m
};

/// The kind of a file from its header; throws naming the file when it is
/// none of them.
AnswerFile answerFileKind(const CsvTable &table);
/// "centre-of-gravity file", "bottom-layer file", ... for messages.
std::string describe(AnswerFile kind);

/// The index of the diameter in `diameters` within 1 % of d, or -1: size
/// classes match by diameter, so that 1.95 mm and 1.950 mm are one class.
int sameClass(double d, const std::vector<double> &diameters);

/// Diameter [m] of a class label d<D>mm (e.g. d1.950mm), or -1.
double labelDiameter(const std::string &label);

struct TimeSpan {
  double begin = 0.0, end = 0.0; // s
};

/// The curves over time of one file: delta_z of a centre-of-gravity file,
/// every d32_*_m column of a bottom-layer file; names without the unit
/// (delta_z, d32_bottom), every curve in metres.
struct CurveSet {
  std::string path;
  std::vector<std::string> names;
  std::vector<DeltaZSeries> curves;
};
CurveSet readCurves(const CsvTable &table, double timeOffset);

/// One compared curve over one window.
struct CurveScore {
  std::string run, curve;
  DeltaZScore score;
};

/// Every curve of the reference that the run has too, over every window
/// (windows in the reference's time).  Throws naming the run's file when it
/// shares no curve with the reference, and the file whose curve a window
/// misses.
std::vector<CurveScore> scoreCurves(const CurveSet &reference, const CurveSet &run, const std::string &label,
                                    const std::vector<TimeSpan> &windows);

/// One row per compared curve and window, units in the header; `moreRows`
/// (rows of the same columns, e.g. polydisperseRows) after them.
void writeCurveScores(const std::string &path, const std::string &referencePath,
                      const std::vector<CurveScore> &scores, const std::string &moreRows = "");

/// The curves at the reference's times: time_s, <curve>_reference_m, then
/// <curve>_<label>_m for each run (empty outside a run's times).
void writeCurvesSideBySide(const std::string &path, const CurveSet &reference, const std::vector<CurveSet> &runs,
                           const std::vector<std::string> &labels);

/// Delta z_CoG [m] of a file: mean |z_CoG - mean z_CoG| of the z_cog_bed_m
/// column of a cog.csv, or the delta_z_cog_m of a bed_dynamics.csv.  An
/// ensemble summary is refused: its mean curve damps the bed's motion.
double bedDynamicsOfFile(const CsvTable &table);

/// Writes path atomically enough for a report (a temporary, then rename);
/// throws naming the file.
void writeTextFile(const std::string &path, const std::string &text);

} // namespace rcfd
