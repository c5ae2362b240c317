// Scoring a curve over time against a reference: the segregation curve
// Delta z(t) = z_CoG(smallest) - z_CoG(largest) with the paper's Eq. 7 error
// of window means and the RMS difference of the whole curve; the same scores
// serve any other scalar curve (the bottom layer's Sauter diameter).  Also
// the CSV reader of the comparisons.  Serial and PETSc-free.
#pragma once

#include "base/csv.hpp"

#include <cstddef>
#include <initializer_list>
#include <string>
#include <vector>

namespace rcfd {

/// The project's one CSV reader, by the name the comparisons use.
using CsvTable = csv::Table;

/// A curve over time; named for its first use, it holds any scalar.
struct DeltaZSeries {
  std::vector<double> time;   // s, increasing
  std::vector<double> deltaZ; // the curve's values (m for Delta z)
};

/// Reads a cog.csv of rcfd run or rcfd reference (columns time_s and
/// delta_z_m; also accepted: time and delta_z), or an ensemble.csv of rcfd
/// run -ensemble (its delta_z_m_mean: the ensemble's mean curve).  A file
/// without a delta_z column but with z_cog_d<D>mm[_m][_mean] columns gives
/// the smallest class's minus the largest's.  Lines starting with '#' are
/// skipped.  `timeOffset` is added to every time.  Throws std::runtime_error
/// naming the file.
DeltaZSeries readDeltaZCsv(const std::string &path, double timeOffset = 0.0);
/// The same from a table already read.
DeltaZSeries readDeltaZ(const CsvTable &table, double timeOffset = 0.0);

/// The curve of column `column` (or, in an ensemble summary, `column`_mean)
/// of a table with a time_s (or time) column, `timeOffset` added to every
/// time.  A field "nan" is a gap (an empty bottom layer has no diameter):
/// that row is left out.  Throws std::runtime_error naming the file when a
/// column is missing, a field is not a number or the times do not increase.
DeltaZSeries readSeries(const CsvTable &table, const std::string &column, double timeOffset = 0.0);

/// The shortest decimal that reads back as exactly x (e.g. 0.5, 3.045 or
/// 3.0450000000000004): for labels a user may type back in.
std::string exactNumber(double x);
/// A value for rcfd's CSV files: 9 significant digits (%.9g).
std::string csvNumber(double x);

struct DeltaZScore {
  double windowBegin = 0.0, windowEnd = 0.0;    // s, scoring window of Eq. 7
  std::size_t windowSamplesRef = 0, windowSamplesModel = 0;
  double meanRef = 0.0, meanModel = 0.0;        // sample means over the window
  double segregationError = 0.0;                // Eq. 7: (meanModel - meanRef) / meanRef, percent
  double overlapBegin = 0.0, overlapEnd = 0.0;  // s, times both series cover
  std::size_t curveSamples = 0;                 // model samples inside the overlap
  double rms = 0.0;                             // RMS of model - reference there
  double peakRef = 0.0;                         // largest |reference| in the overlap
  double rmsRelative = 0.0;                     // rms / peakRef
  double meanAbsRef = 0.0;                      // mean |reference| at the same samples
};

/// Linear interpolation of a series at time t (clamped at its ends).
double interpolate(const DeltaZSeries &s, double t);

/// Eq. 7 over [windowBegin, windowEnd]:
///   (mean Delta z_model - mean Delta z_ref) / mean Delta z_ref * 100,
/// each mean over that series' own samples in the window; and the RMS of
/// Delta z_model - Delta z_ref at the model's samples within the overlap
/// of both series, the reference interpolated linearly, divided by the
/// reference's peak |Delta z| in the overlap.  Throws std::invalid_argument
/// when the window holds no samples of either series or the series do not
/// overlap.
DeltaZScore scoreDeltaZ(const DeltaZSeries &reference, const DeltaZSeries &model,
                        double windowBegin, double windowEnd);

} // namespace rcfd
