#include "analysis/class_scores.hpp"

#include <cmath>
#include <stdexcept>

namespace rcfd {
namespace {

/// The class label of a column named <prefix><label><unit>[_mean] (an
/// ensemble summary's mean), <unit> one of `units`, <label> a class d<D>mm;
/// empty for any other column.
std::string classLabel(std::string column, const std::string &prefix, const std::vector<std::string> &units) {
  const std::string mean = "_mean";
  if (column.size() > mean.size() && column.compare(column.size() - mean.size(), mean.size(), mean) == 0)
    column.resize(column.size() - mean.size());
  if (column.rfind(prefix, 0) != 0) return "";
  for (const std::string &unit : units) {
    if (column.size() < prefix.size() + unit.size() ||
        column.compare(column.size() - unit.size(), unit.size(), unit) != 0)
      continue;
    const std::string label = column.substr(prefix.size(), column.size() - prefix.size() - unit.size());
    if (labelDiameter(label) > 0) return label;
  }
  return "";
}

std::string joined(const std::vector<std::string> &names) {
  std::string text;
  for (const auto &n : names) text += (text.empty() ? "" : ", ") + n;
  return text;
}

} // namespace

ClassCurveSet readClassCurves(const CsvTable &table, double timeOffset) {
  ClassCurveSet s;
  s.curves.path = table.path();
  std::vector<std::string> labels, columns, massLabels;
  std::vector<int> massColumns;
  const auto &names = table.columns();
  for (std::size_t c = 0; c < names.size(); ++c) {
    const std::string z = classLabel(names[c], "z_cog_", {"_m", ""});
    if (!z.empty()) labels.push_back(z), columns.push_back(names[c]);
    const std::string m = classLabel(names[c], "mass_", {"_kg"});
    if (!m.empty()) massLabels.push_back(m), massColumns.push_back(static_cast<int>(c));
  }
  if (labels.empty()) return s;
  const int bed = table.find({"z_cog_bed_m", "z_cog_bed", "z_cog_bed_m_mean", "z_cog_bed_mean"});
  if (bed < 0)
    throw std::runtime_error("'" + table.path() + "' has class columns (" + joined(columns) +
                             ") but no z_cog_bed_m column: each class is scored as z_CoG,i - z_CoG,bed.");
  if (!massLabels.empty() && massLabels != labels)
    throw std::runtime_error("'" + table.path() + "' has mass columns of the classes " + joined(massLabels) +
                             " but centre-of-gravity columns of " + joined(labels) +
                             ": each class needs both, in the same order.");
  const DeltaZSeries zBed = readSeries(table, names[bed], timeOffset);
  double total = 0.0;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    const double d = labelDiameter(labels[i]);
    if (sameClass(d, s.diameters) >= 0)
      throw std::runtime_error("'" + table.path() + "' has two classes within 1 % of " + labels[i] +
                               ": classes are told apart by diameter.");
    DeltaZSeries curve = readSeries(table, columns[i], timeOffset);
    if (curve.time != zBed.time)
      throw std::runtime_error("'" + table.path() + "' has gaps in " + columns[i] + " where z_cog_bed has none.");
    for (std::size_t k = 0; k < curve.time.size(); ++k) curve.deltaZ[k] -= zBed.deltaZ[k];
    s.curves.names.push_back("class_" + labels[i]);
    s.curves.curves.push_back(std::move(curve));
    s.diameters.push_back(d);
    if (!massColumns.empty()) {
      s.massShares.push_back(table.number(0, massColumns[i]));
      total += s.massShares.back();
    }
  }
  if (!massColumns.empty() && !(total > 0))
    throw std::runtime_error("'" + table.path() + "' holds no mass in its first row's mass columns.");
  for (double &w : s.massShares) w /= total;
  return s;
}

ClassComparison compareClasses(const ClassCurveSet &ref, const ClassCurveSet &run, const std::string &label,
                               const std::vector<TimeSpan> &windows) {
  ClassComparison c;
  c.matched.path = run.curves.path;
  if (run.diameters.empty()) { // a file of Delta z only: nothing to match, one note
    if (!ref.diameters.empty())
      c.notes.push_back(label + ": '" + run.curves.path + "' has no class columns: its classes are not scored.");
    return c;
  }
  std::vector<int> runOf(ref.diameters.size(), -1); // the run's class of each reference class
  for (std::size_t i = 0; i < ref.diameters.size(); ++i) {
    runOf[i] = sameClass(ref.diameters[i], run.diameters);
    if (runOf[i] < 0) {
      c.notes.push_back(label + ": '" + run.curves.path + "' has no class " + ref.curves.names[i].substr(6) +
                        " (within 1 %): not scored.");
      continue;
    }
    c.matched.names.push_back(ref.curves.names[i]);
    c.matched.curves.push_back(run.curves.curves[runOf[i]]);
  }
  for (std::size_t j = 0; j < run.diameters.size(); ++j)
    if (sameClass(run.diameters[j], ref.diameters) < 0)
      c.notes.push_back(label + ": the reference '" + ref.curves.path + "' has no class " +
                        run.curves.names[j].substr(6) + " (within 1 %): not scored.");
  if (c.matched.names.empty() || windows.empty()) return c;
  c.scores = scoreCurves(ref.curves, c.matched, label, windows);

  // The poly-disperse number, from the first window's rows (one per class).
  const bool runWeights = !run.massShares.empty();
  if (!runWeights && ref.massShares.empty()) {
    c.notes.push_back(label + ": neither '" + run.curves.path + "' nor the reference has mass_<class>_kg columns: "
                      "no poly-disperse number.");
    return c;
  }
  PolydisperseScore &p = c.polydisperse;
  p.run = label;
  p.weightsFrom = runWeights ? run.curves.path : ref.curves.path;
  double weightSum = 0.0, sum = 0.0, largest = 0.0;
  const CurveScore *largestScore = nullptr;
  std::size_t row = 0;
  for (std::size_t i = 0; i < ref.diameters.size(); ++i) {
    if (runOf[i] < 0) continue;
    const CurveScore &s = c.scores[row];
    row += windows.size();
    const double w = runWeights ? run.massShares[runOf[i]] : ref.massShares[i];
    p.weights.push_back(w);
    weightSum += w;
    sum += w * s.score.rms * s.score.rms;
    if (ref.diameters[i] > largest) largest = ref.diameters[i], largestScore = &s;
  }
  if (!(weightSum > 0)) {
    c.notes.push_back(label + ": the matched classes hold no mass in '" + p.weightsFrom +
                      "': no poly-disperse number.");
    return c;
  }
  for (double &w : p.weights) w /= weightSum;
  p.rms = std::sqrt(sum / weightSum);
  p.largestClass = largestScore->curve;
  p.peakLargest = largestScore->score.peakRef;
  p.rmsRelative = p.peakLargest > 0 ? p.rms / p.peakLargest : std::nan("");
  p.curveBegin = largestScore->score.overlapBegin;
  p.curveEnd = largestScore->score.overlapEnd;
  p.curveSamples = largestScore->score.curveSamples;
  c.hasPolydisperse = true;
  return c;
}

std::string polydisperseRows(const std::vector<PolydisperseScore> &scores) {
  std::string text;
  for (const PolydisperseScore &p : scores)
    text += p.run + ",polydisperse,m,,,,,,,,," + exactNumber(p.curveBegin) + "," + exactNumber(p.curveEnd) + "," +
            std::to_string(p.curveSamples) + "," + csvNumber(p.rms) + "," + csvNumber(p.peakLargest) + "," +
            csvNumber(p.rmsRelative) + "\n";
  return text;
}

} // namespace rcfd
