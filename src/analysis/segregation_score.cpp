#include "analysis/segregation_score.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rcfd {
namespace {

std::vector<std::string> splitComma(const std::string &line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const auto b = item.find_first_not_of(" \t\r");
    const auto e = item.find_last_not_of(" \t\r");
    out.push_back(b == std::string::npos ? std::string() : item.substr(b, e - b + 1));
  }
  return out;
}

int findColumn(const std::vector<std::string> &names, std::initializer_list<const char *> choices) {
  for (const char *c : choices)
    for (std::size_t i = 0; i < names.size(); ++i)
      if (names[i] == c) return static_cast<int>(i);
  return -1;
}

/// Diameter [mm] of a column named z_cog_d<D>mm or z_cog_d<D>mm_m; negative otherwise.
double classDiameter(const std::string &name) {
  const std::string prefix = "z_cog_d";
  if (name.rfind(prefix, 0) != 0) return -1.0;
  const std::string rest = name.substr(prefix.size());
  const auto mm = rest.find("mm");
  if (mm == std::string::npos || (rest.substr(mm) != "mm" && rest.substr(mm) != "mm_m")) return -1.0;
  char *end = nullptr;
  const std::string number = rest.substr(0, mm);
  const double d = std::strtod(number.c_str(), &end);
  return end && *end == '\0' && d > 0 ? d : -1.0;
}

} // namespace

DeltaZSeries readDeltaZCsv(const std::string &path, double timeOffset) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open the centre-of-gravity file '" + path + "'.");
  std::string line;
  long lineNo = 0;
  std::vector<std::string> names;
  while (std::getline(in, line)) {
    ++lineNo;
    if (line.empty() || line[0] == '#') continue;
    names = splitComma(line);
    break;
  }
  const int tCol = findColumn(names, {"time_s", "time"});
  int dzCol = findColumn(names, {"delta_z_m", "delta_z"});
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
  if (tCol < 0 || (dzCol < 0 && (small < 0 || small == large)))
    throw std::runtime_error("'" + path +
                             "' is not a centre-of-gravity file: its header needs a time_s column "
                             "and delta_z_m (or two z_cog_d<D>mm columns).");
  DeltaZSeries s;
  const std::size_t need = static_cast<std::size_t>(std::max({tCol, dzCol, small, large})) + 1;
  while (std::getline(in, line)) {
    ++lineNo;
    if (line.empty() || line[0] == '#' || line == "\r") continue;
    const auto v = splitComma(line);
    auto number = [&](int c) {
      if (v.size() < need)
        throw std::runtime_error("'" + path + "', line " + std::to_string(lineNo) + ": expected " +
                                 std::to_string(names.size()) + " values, found " +
                                 std::to_string(v.size()) + ".");
      char *end = nullptr;
      errno = 0;
      const double x = std::strtod(v[c].c_str(), &end);
      if (v[c].empty() || *end != '\0' || errno == ERANGE)
        throw std::runtime_error("'" + path + "', line " + std::to_string(lineNo) +
                                 ": expected a number in column '" + names[c] + "', found '" +
                                 v[c] + "'.");
      return x;
    };
    const double t = number(tCol) + timeOffset;
    const double dz = dzCol >= 0 ? number(dzCol) : number(small) - number(large);
    if (!s.time.empty() && !(t > s.time.back()))
      throw std::runtime_error("'" + path + "', line " + std::to_string(lineNo) +
                               ": the times do not increase.");
    s.time.push_back(t);
    s.deltaZ.push_back(dz);
  }
  if (s.time.empty()) throw std::runtime_error("'" + path + "' holds no rows.");
  return s;
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
    throw std::invalid_argument("the scoring window [" + std::to_string(w0) + ", " +
                                std::to_string(w1) + "] s holds no sample of the " +
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
