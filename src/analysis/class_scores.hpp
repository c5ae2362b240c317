// Every size class of a centre-of-gravity file scored, not only the smallest
// against the largest: each class's height above the bed's centre of
// gravity, z_CoG,i - z_CoG,bed (t), of a run against the reference's (RMS
// over the run / the reference's peak, window means), and one poly-disperse
// number, the mass-weighted RMS of those class errors.  Serial and
// PETSc-free; every error is a std::runtime_error naming the file at fault.
#pragma once

#include "analysis/comparison.hpp"

#include <string>
#include <vector>

namespace rcfd {

/// The class curves of a cog.csv (or of an ensemble.csv's mean columns).
struct ClassCurveSet {
  CurveSet curves;                  // names class_<label> (class_d1.400mm), z_CoG,i - z_CoG,bed [m]
  std::vector<double> diameters;    // m, one per curve
  std::vector<double> massShares;   // the mass_<label>_kg columns at the first sample over their sum;
                                    // empty when the file has none (rcfd reference writes none)
};

/// Every z_cog_<label>[_m] column with <label> a class d<D>mm, relative to
/// z_cog_bed[_m]; none in a file without class columns.  Throws naming the
/// file when class columns come without a bed column, when two classes are
/// within 1 % of each other, or when the mass_<label>_kg columns are not
/// those of the classes one by one.
ClassCurveSet readClassCurves(const CsvTable &table, double timeOffset);

/// The poly-disperse number of one run: E = sqrt(sum_i w_i RMS_i^2) over the
/// matched classes, RMS_i their rms_difference and w_i their mass shares
/// (renormalised over the matched classes), in m; and E over the
/// reference's peak |z_CoG,i - z_CoG,bed| of the class of largest diameter.
struct PolydisperseScore {
  std::string run;
  std::string weightsFrom;       // the file whose mass columns gave the w_i
  std::vector<double> weights;   // w_i, in the reference's class order (matched classes only)
  double rms = 0.0;              // E [m]
  std::string largestClass;      // its curve name
  double peakLargest = 0.0;      // [m]
  double rmsRelative = 0.0;      // E / peakLargest
  double curveBegin = 0.0, curveEnd = 0.0;
  std::size_t curveSamples = 0;  // those of the largest class
};

/// One run's classes against the reference's.
struct ClassComparison {
  CurveSet matched;                // the run's classes the reference has, under the reference's names
  std::vector<CurveScore> scores;  // per matched class and window (class order, then window)
  std::vector<std::string> notes;  // a class only one side has; no poly-disperse number and why
  bool hasPolydisperse = false;
  PolydisperseScore polydisperse;
};

/// Classes match by diameter within 1 % (sameClass); a class only one side
/// has is skipped with a note.  The weights are the run's mass shares, or
/// the reference's when the run's file has no mass columns; without either
/// there is no poly-disperse number (a note says so).  Throws naming a file
/// as scoreCurves does.
ClassComparison compareClasses(const ClassCurveSet &reference, const ClassCurveSet &run, const std::string &label,
                               const std::vector<TimeSpan> &windows);

/// One row per run: run,polydisperse,m, the window and mean columns empty,
/// then curve_begin_s..rms_over_peak as in writeCurveScores' rows.
std::string polydisperseRows(const std::vector<PolydisperseScore> &scores);

} // namespace rcfd
