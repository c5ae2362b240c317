#include "analysis/span_statistics.hpp"

#include "observable/bed_dynamics.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace rcfd {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double meanOf(const std::vector<double> &x, size_t first, size_t last) {
  double sum = 0.0;
  for (size_t k = first; k < last; ++k) sum += x[k];
  return sum / static_cast<double>(last - first);
}

void requireTwo(const std::vector<double> &x) {
  if (x.size() < 2) throw std::invalid_argument("halves of a span: the series needs at least 2 frames.");
}

/// Both halves of a quantity and the standard error of their relative
/// difference from the batch means of y, the per-frame values whose mean the
/// quantity is.
HalvesDifference compare(double first, double second, const std::vector<double> &y, int batches) {
  HalvesDifference d;
  d.first = first;
  d.second = second;
  d.relative = second / first - 1.0;
  d.standardError = 2.0 * std::sqrt(varianceOfMeanByBatches(y, batches)) / meanOf(y, 0, y.size());
  return d;
}

} // namespace

double varianceOfMeanByBatches(const std::vector<double> &x, int batches) {
  const size_t m = batches > 0 ? x.size() / static_cast<size_t>(batches) : 0;
  if (batches < 2 || m < 2) return kNaN;
  std::vector<double> means(static_cast<size_t>(batches));
  for (size_t b = 0; b < means.size(); ++b) means[b] = meanOf(x, b * m, (b + 1) * m);
  const double grand = meanOf(means, 0, means.size());
  double sum = 0.0;
  for (double v : means) sum += (v - grand) * (v - grand);
  return sum / static_cast<double>(batches - 1) / static_cast<double>(batches);
}

double integratedTimeByBatches(const std::vector<double> &x, int batches) {
  const size_t m = batches > 0 ? x.size() / static_cast<size_t>(batches) : 0;
  if (batches < 2 || m < 2) return kNaN;
  const size_t n = m * static_cast<size_t>(batches); // the frames the batches use
  const std::vector<double> used(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(n));
  const double mean = meanOf(used, 0, n);
  double sum = 0.0;
  for (double v : used) sum += (v - mean) * (v - mean);
  const double variance = sum / static_cast<double>(n - 1);
  if (!(variance > 0.0)) return kNaN;
  return static_cast<double>(n) * varianceOfMeanByBatches(used, batches) / variance;
}

HalvesDifference halvesOfMean(const std::vector<double> &x, int batches) {
  requireTwo(x);
  const size_t half = x.size() / 2;
  return compare(meanOf(x, 0, half), meanOf(x, half, x.size()), x, batches);
}

HalvesDifference halvesOfMeanDeviation(const std::vector<double> &z, int batches) {
  requireTwo(z);
  const auto mid = z.begin() + static_cast<std::ptrdiff_t>(z.size() / 2);
  const double mean = meanOf(z, 0, z.size());
  std::vector<double> deviation(z.size());
  for (size_t k = 0; k < z.size(); ++k) deviation[k] = std::fabs(z[k] - mean);
  return compare(bedDynamics({z.begin(), mid}), bedDynamics({mid, z.end()}), deviation, batches);
}

} // namespace rcfd
