// Is a recorded span stationary?  The two halves of a per-frame series (mean bed
// height, Delta z_CoG) compared against the scatter that the series' own
// autocorrelation makes expected (docs/synthetic.md, "Stationarity over the
// recorded span").  A stationary bed whose quantity is correlated over tau
// frames holds only n / tau independent samples in n frames, so its halves
// differ by about 2 sqrt(tau var / n) / mean even though nothing drifts.
#pragma once

#include <vector>

namespace rcfd {

/// Batches the span is cut into for the standard errors of the halves: 6 batches of
/// 50 frames for the default 300.  Measured on the steady bed (tau about 50 frames,
/// docs/synthetic.md), 3 or 6 batches or overlapping batches give the same errors, a
/// little low for Delta z_CoG: 3 of them, not 2, hold 93-100 % of the spans' differences.
inline constexpr int kHalvesBatches = 6;

/// Variance of the mean of x[0, n) by batch means: x cut into `batches` batches of
/// m = floor(n / batches) frames (a remainder at the end is left out), the sample
/// variance of the batch means over the number of batches.  Batches much longer
/// than the correlation time are independent, so this is var(mean) without a model
/// of the autocorrelation; shorter batches underestimate it.  NaN with fewer than
/// 2 batches or frames per batch.
double varianceOfMeanByBatches(const std::vector<double> &x, int batches);

/// Integrated autocorrelation time of x in frames, tau = 1 + 2 sum_k rho_k (the
/// statistical inefficiency: var(mean of n) = tau var(x) / n for n >> tau), by batch
/// means: n varianceOfMeanByBatches / var(x).  NaN as above, or for a constant x.
double integratedTimeByBatches(const std::vector<double> &x, int batches);

/// One quantity over the two halves of a span [0, n/2) and [n/2, n).
struct HalvesDifference {
  double first = 0.0, second = 0.0; ///< the quantity over each half
  double relative = 0.0;            ///< second / first - 1
  /// Standard error of `relative` expected of a stationary series from its own
  /// batch means over the whole span (the halves as independent means of n/2
  /// frames): 2 sqrt(var(mean of n)) / mean.  NaN when the span is too short.
  double standardError = 0.0;
};

/// The halves' means of x (e.g. the bed height).  Throws std::invalid_argument
/// for fewer than 2 values.
HalvesDifference halvesOfMean(const std::vector<double> &x, int batches = kHalvesBatches);

/// The halves' Delta z_CoG (bedDynamics: mean |z - mean| of each half about the
/// half's own mean); the standard error is that of the mean of |z - mean of the
/// span|.  Throws std::invalid_argument for fewer than 2 values.
HalvesDifference halvesOfMeanDeviation(const std::vector<double> &z, int batches = kHalvesBatches);

} // namespace rcfd
