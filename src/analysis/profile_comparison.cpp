#include "analysis/profile_comparison.hpp"

#include "analysis/comparison.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace rcfd {
ProfileTable readProfiles(const CsvTable &table) {
  // The columns up to alpha_total; a run's scalars follow it (docs/scalars.md) and are not compared.
  const auto &all = table.columns();
  const auto total = std::find(all.begin(), all.end(), "alpha_total");
  const std::vector<std::string> c(all.begin(), total == all.end() ? all.end() : total + 1);
  ProfileTable p{table.path(), {}, {}, {}, {}};
  bool ok = c.size() >= 2 && c.front() == "z" && c.back() == "alpha_total";
  for (std::size_t i = 1; ok && i + 1 < c.size(); ++i)
    ok = c[i].rfind("alpha_", 0) == 0 && labelDiameter(c[i].substr(6)) > 0;
  if (!ok)
    throw std::runtime_error("'" + table.path() +
                             "' is not a profiles file: its header should be z,alpha_d<D>mm,...,alpha_total.");
  for (std::size_t i = 1; i < c.size(); ++i) {
    p.curves.push_back(c[i]);
    p.diameter.push_back(i + 1 < c.size() ? labelDiameter(c[i].substr(6)) : 0.0);
  }
  p.alpha.assign(p.curves.size(), {});
  for (std::size_t r = 0; r < table.numRows(); ++r) {
    p.z.push_back(table.number(r, 0));
    if (r > 0 && !(p.z[r] > p.z[r - 1])) throw std::runtime_error(table.where(r) + ": the heights z do not increase.");
    for (std::size_t k = 0; k < p.curves.size(); ++k) p.alpha[k].push_back(table.number(r, static_cast<int>(k + 1)));
  }
  if (p.z.empty()) throw std::runtime_error("'" + table.path() + "' holds no layers.");
  return p;
}

int matchingProfile(const ProfileTable &ref, std::size_t c, const ProfileTable &run) {
  if (ref.diameter[c] == 0.0) return static_cast<int>(run.curves.size()) - 1; // alpha_total
  const std::vector<double> classes(run.diameter.begin(), run.diameter.end() - 1);
  return sameClass(ref.diameter[c], classes);
}

std::vector<ProfileDifference> compareProfiles(const ProfileTable &ref, const ProfileTable &run,
                                               const std::string &label) {
  const double span = ref.z.back() - ref.z.front() + 1.0;
  bool sameLayers = run.z.size() == ref.z.size();
  for (std::size_t k = 0; sameLayers && k < ref.z.size(); ++k)
    sameLayers = std::fabs(run.z[k] - ref.z[k]) <= 1e-6 * span;
  if (!sameLayers)
    throw std::runtime_error("'" + run.path + "' has other layers than the reference '" + ref.path + "' (" +
                             std::to_string(run.z.size()) + " against " + std::to_string(ref.z.size()) +
                             "): profiles compare on one mesh.");
  std::vector<std::size_t> layers; // where either bed holds solid
  for (std::size_t k = 0; k < ref.z.size(); ++k)
    if (ref.alpha.back()[k] > 0.0 || run.alpha.back()[k] > 0.0) layers.push_back(k);
  std::vector<ProfileDifference> out;
  for (std::size_t c = 0; c < ref.curves.size(); ++c) {
    const int m = matchingProfile(ref, c, run);
    if (m < 0) continue;
    ProfileDifference d{label, ref.curves[c]};
    double sq = 0.0;
    for (std::size_t k : layers) {
      const double diff = run.alpha[m][k] - ref.alpha[c][k];
      sq += diff * diff;
      d.maxAbs = std::max(d.maxAbs, std::fabs(diff));
      d.peakRef = std::max(d.peakRef, std::fabs(ref.alpha[c][k]));
    }
    d.layers = layers.size();
    if (!layers.empty()) {
      d.zBegin = ref.z[layers.front()];
      d.zEnd = ref.z[layers.back()];
      d.rms = std::sqrt(sq / static_cast<double>(layers.size()));
    }
    d.rmsRelative = d.peakRef > 0.0 ? d.rms / d.peakRef : std::nan("");
    out.push_back(d);
  }
  return out;
}

void writeProfileScores(const std::string &path, const std::string &referencePath,
                        const std::vector<ProfileDifference> &rows) {
  std::string text = "# rcfd compare of vertical profiles against " + referencePath +
                     ": over the layers where either bed holds solid, RMS and largest |alpha_run - "
                     "alpha_reference|; alpha in the unit of the unit column (1: a volume fraction)\n"
                     "run,curve,unit,layers,z_begin_m,z_end_m,rms_difference,max_abs_difference,peak_reference,"
                     "rms_over_peak\n";
  for (const auto &d : rows)
    text += d.run + "," + d.curve + ",1," + std::to_string(d.layers) + "," + csvNumber(d.zBegin) + "," +
            csvNumber(d.zEnd) + "," + csvNumber(d.rms) + "," + csvNumber(d.maxAbs) + "," + csvNumber(d.peakRef) + "," +
            csvNumber(d.rmsRelative) + "\n";
  writeTextFile(path, text);
}

} // namespace rcfd
