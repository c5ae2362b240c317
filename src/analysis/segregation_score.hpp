// Scoring a segregation curve Delta z(t) = z_CoG(smallest) - z_CoG(largest)
// against a reference: the paper's Eq. 7 error of the window means and the
// RMS difference of the whole curve.  Serial and PETSc-free.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace rcfd {

struct DeltaZSeries {
  std::vector<double> time;   // s, increasing
  std::vector<double> deltaZ; // m
};

/// Reads a cog.csv of rcfd run or rcfd reference (columns time_s and
/// delta_z_m; also accepted: time and delta_z).  A file without a delta_z
/// column but with z_cog_d<D>mm[_m] columns gives the smallest class's
/// minus the largest's.  Lines starting with '#' are skipped.  `timeOffset`
/// is added to every time.  Throws std::runtime_error naming the file.
DeltaZSeries readDeltaZCsv(const std::string &path, double timeOffset = 0.0);

struct DeltaZScore {
  double windowBegin = 0.0, windowEnd = 0.0;    // s, scoring window of Eq. 7
  std::size_t windowSamplesRef = 0, windowSamplesModel = 0;
  double meanRef = 0.0, meanModel = 0.0;        // m, sample means over the window
  double segregationError = 0.0;                // Eq. 7, percent
  double overlapBegin = 0.0, overlapEnd = 0.0;  // s, times both series cover
  std::size_t curveSamples = 0;                 // model samples inside the overlap
  double rms = 0.0;                             // m, RMS of model - reference there
  double peakRef = 0.0;                         // m, largest |Delta z_ref| in the overlap
  double rmsRelative = 0.0;                     // rms / peakRef
  double meanAbsRef = 0.0;                      // m, mean |Delta z_ref| at the same samples
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
