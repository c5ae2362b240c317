#include "analysis/segregation_score.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rcfd {
namespace {

/// Diameter [mm] of a column named z_cog_d<D>mm, z_cog_d<D>mm_m or either
/// with _mean (an ensemble summary); negative otherwise.
double classDiameter(std::string name) {
  const std::string prefix = "z_cog_d", mean = "_mean";
  if (name.size() > mean.size() && name.compare(name.size() - mean.size(), mean.size(), mean) == 0)
    name.resize(name.size() - mean.size());
  if (name.rfind(prefix, 0) != 0) return -1.0;
  const std::string rest = name.substr(prefix.size());
  const auto mm = rest.find("mm");
  if (mm == std::string::npos || (rest.substr(mm) != "mm" && rest.substr(mm) != "mm_m")) return -1.0;
  char *end = nullptr;
  const std::string number = rest.substr(0, mm);
  const double d = std::strtod(number.c_str(), &end);
  return end && *end == '\0' && d > 0 ? d : -1.0;
}

int timeColumn(const CsvTable &t) { return t.find({"time_s", "time"}); }

} // namespace

DeltaZSeries readSeries(const CsvTable &table, const std::string &column, double timeOffset) {
  const int tCol = timeColumn(table);
  const int col = table.find({column, column + "_mean"});
  if (tCol < 0 || col < 0)
    throw std::runtime_error("'" + table.path() + "' has no " + (tCol < 0 ? "time_s" : column) + " column.");
  DeltaZSeries s;
  for (std::size_t r = 0; r < table.numRows(); ++r) {
    const double t = table.number(r, tCol) + timeOffset;
    if (!s.time.empty() && !(t > s.time.back()))
      throw std::runtime_error(table.where(r) + ": the times do not increase.");
    if (table.field(r, col) == "nan" || table.field(r, col) == "-nan") continue; // a gap
    s.time.push_back(t);
    s.deltaZ.push_back(table.number(r, col));
  }
  if (s.time.empty()) throw std::runtime_error("'" + table.path() + "' holds no values of " + column + ".");
  return s;
}

DeltaZSeries readDeltaZCsv(const std::string &path, double timeOffset) {
  return readDeltaZ(CsvTable::read(path, "centre-of-gravity file"), timeOffset);
}

DeltaZSeries readDeltaZ(const CsvTable &table, double timeOffset) {
  const std::string &path = table.path();
  const auto &names = table.columns();
  const int dzCol = table.find({"delta_z_m", "delta_z", "delta_z_m_mean"});
  int small = -1, large = -1;
  if (dzCol < 0) {
    double dMin = 0.0, dMax = 0.0;
    for (std::size_t i = 0; i < names.size(); ++i) {
      const double d = classDiameter(names[i]);
      if (d <= 0) continue;
      if (small < 0 || d < dMin) small = static_cast<int>(i), dMin = d;
      if (large < 0 || d > dMax) large = static_cast<int>(i), dMax = d;
    }
  }
  if (timeColumn(table) < 0 || (dzCol < 0 && (small < 0 || small == large)))
    throw std::runtime_error("'" + path +
                             "' is not a centre-of-gravity file: its header needs a time_s column "
                             "and delta_z_m (or two z_cog_d<D>mm columns).");
  if (dzCol >= 0) return readSeries(table, names[dzCol], timeOffset);
  DeltaZSeries s = readSeries(table, names[small], timeOffset);
  const DeltaZSeries l = readSeries(table, names[large], timeOffset);
  if (l.time != s.time) throw std::runtime_error("'" + path + "' has gaps in its class columns.");
  for (std::size_t k = 0; k < s.time.size(); ++k) s.deltaZ[k] -= l.deltaZ[k];
  return s;
}

std::string exactNumber(double x) {
  // Plain decimals where a person would write them (10, not 1e+01).
  const bool plain = std::fabs(x) >= 1e-4 && std::fabs(x) < 1e15;
  char text[40];
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, x);
    if (std::strtod(text, nullptr) == x && !(plain && std::strchr(text, 'e'))) break;
  }
  return text;
}

std::string csvNumber(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", x);
  return text;
}

double interpolate(const DeltaZSeries &s, double t) {
  if (s.time.empty()) return std::nan("");
  if (t <= s.time.front()) return s.deltaZ.front();
  if (t >= s.time.back()) return s.deltaZ.back();
  const std::size_t j = static_cast<std::size_t>(
      std::upper_bound(s.time.begin(), s.time.end(), t) - s.time.begin());
  const double w = (t - s.time[j - 1]) / (s.time[j] - s.time[j - 1]);
  return (1.0 - w) * s.deltaZ[j - 1] + w * s.deltaZ[j];
}

DeltaZScore scoreDeltaZ(const DeltaZSeries &ref, const DeltaZSeries &model, double w0, double w1) {
  DeltaZScore r;
  r.windowBegin = w0;
  r.windowEnd = w1;
  // A sample exactly on a window end counts, up to rounding of the times.
  const double slack = 1e-9 * std::max(1.0, std::fabs(w1));
  auto windowMean = [&](const DeltaZSeries &s, std::size_t *n) {
    double sum = 0.0;
    *n = 0;
    for (std::size_t k = 0; k < s.time.size(); ++k)
      if (s.time[k] >= w0 - slack && s.time[k] <= w1 + slack) sum += s.deltaZ[k], ++*n;
    return *n ? sum / double(*n) : 0.0;
  };
  r.meanRef = windowMean(ref, &r.windowSamplesRef);
  r.meanModel = windowMean(model, &r.windowSamplesModel);
  if (r.windowSamplesRef == 0 || r.windowSamplesModel == 0)
    throw std::invalid_argument("the scoring window [" + exactNumber(w0) + ", " + exactNumber(w1) +
                                "] s holds no sample of the " +
                                (r.windowSamplesRef == 0 ? "reference" : "rcfd run") + ".");
  r.segregationError = (r.meanModel - r.meanRef) / r.meanRef * 100.0;

  r.overlapBegin = std::max(ref.time.front(), model.time.front());
  r.overlapEnd = std::min(ref.time.back(), model.time.back());
  double sq = 0.0, absRef = 0.0;
  for (std::size_t k = 0; k < model.time.size(); ++k) {
    const double t = model.time[k];
    if (t < r.overlapBegin - slack || t > r.overlapEnd + slack) continue;
    const double d = model.deltaZ[k] - interpolate(ref, t);
    sq += d * d;
    absRef += std::fabs(interpolate(ref, t));
    ++r.curveSamples;
  }
  if (r.curveSamples == 0)
    throw std::invalid_argument("the rcfd run and the reference do not overlap in time.");
  r.rms = std::sqrt(sq / double(r.curveSamples));
  r.meanAbsRef = absRef / double(r.curveSamples);
  for (std::size_t k = 0; k < ref.time.size(); ++k)
    if (ref.time[k] >= r.overlapBegin - slack && ref.time[k] <= r.overlapEnd + slack)
      r.peakRef = std::max(r.peakRef, std::fabs(ref.deltaZ[k]));
  r.rmsRelative = r.peakRef > 0 ? r.rms / r.peakRef : std::nan("");
  return r;
}

} // namespace rcfd
