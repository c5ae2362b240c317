#include "analysis/comparison.hpp"

#include "observable/bed_dynamics.hpp"
#include "base/atomic_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace rcfd {
namespace {

bool startsWith(const std::string &s, const std::string &prefix) { return s.rfind(prefix, 0) == 0; }
bool endsWith(const std::string &s, const std::string &suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

/// d32_<name>_m (or its ensemble mean) -> d32_<name>; empty for other columns.
std::string diameterCurve(std::string column) {
  if (endsWith(column, "_mean")) column.resize(column.size() - 5);
  if (!startsWith(column, "d32_") || !endsWith(column, "_m") || column.size() <= 6) return "";
  return column.substr(0, column.size() - 2);
}


} // namespace

AnswerFile answerFileKind(const CsvTable &t) {
  const auto &c = t.columns();
  // Halves: these four columns first; more (e.g. d_over_d32) are read past.
  if (c.size() >= 4 && std::equal(c.begin(), c.begin() + 4,
                                  std::vector<std::string>{"class", "diameter", "bottom_mass_fraction",
                                                           "top_mass_fraction"}.begin()))
    return AnswerFile::halves;
  // Profiles: z, the classes' alpha, alpha_total; the scalars' columns after it are read past.
  if (!c.empty() && c.front() == "z" && std::find(c.begin(), c.end(), "alpha_total") != c.end())
    return AnswerFile::profiles;
  if (t.find({"delta_z_cog_m"}) >= 0 && t.find({"mean_z_cog_m"}) >= 0) return AnswerFile::bedDynamics;
  if (t.find({"time_s", "time"}) >= 0) {
    if (t.find({"d32_bottom_m", "d32_bottom_m_mean"}) >= 0) return AnswerFile::bottomLayer;
    for (const auto &name : c)
      if (startsWith(name, "delta_z") || startsWith(name, "z_cog_")) return AnswerFile::centresOfGravity;
  }
  throw std::runtime_error("'" + t.path() +
                           "' is none of the files rcfd compare reads (its header should be that of a cog.csv, "
                           "ensemble.csv, bottom.csv, profiles.csv, halves.csv or bed_dynamics.csv).");
}

std::string describe(AnswerFile kind) {
  switch (kind) {
  case AnswerFile::centresOfGravity: return "centre-of-gravity file";
  case AnswerFile::bottomLayer: return "bottom-layer file";
  case AnswerFile::profiles: return "profiles file";
  case AnswerFile::halves: return "halves file";
  case AnswerFile::bedDynamics: return "bed-dynamics file";
  }
  return "file";
}

int sameClass(double d, const std::vector<double> &diameters) {
  for (std::size_t i = 0; i < diameters.size(); ++i)
    if (diameters[i] > 0 && std::fabs(d - diameters[i]) <= 0.01 * diameters[i]) return static_cast<int>(i);
  return -1;
}

double labelDiameter(const std::string &label) {
  if (!startsWith(label, "d") || !endsWith(label, "mm") || label.size() < 4) return -1.0;
  const std::string digits = label.substr(1, label.size() - 3);
  char *end = nullptr;
  const double mm = std::strtod(digits.c_str(), &end);
  return end && *end == '\0' && mm > 0 ? 1e-3 * mm : -1.0;
}

CurveSet readCurves(const CsvTable &table, double timeOffset) {
  CurveSet s{table.path(), {}, {}};
  const AnswerFile kind = answerFileKind(table);
  if (kind == AnswerFile::centresOfGravity) {
    s.names.push_back("delta_z");
    s.curves.push_back(readDeltaZ(table, timeOffset));
  } else if (kind == AnswerFile::bottomLayer) {
    for (const auto &column : table.columns()) {
      const std::string name = diameterCurve(column);
      if (name.empty()) continue;
      s.names.push_back(name);
      s.curves.push_back(readSeries(table, name + "_m", timeOffset));
    }
  } else {
    throw std::runtime_error("'" + table.path() + "' is a " + describe(kind) +
                             ", not a file of curves over time (cog.csv, ensemble.csv or bottom.csv).");
  }
  return s;
}

std::vector<CurveScore> scoreCurves(const CurveSet &ref, const CurveSet &run, const std::string &label,
                                    const std::vector<TimeSpan> &windows) {
  std::vector<CurveScore> out;
  for (std::size_t c = 0; c < ref.names.size(); ++c) {
    std::size_t r = 0;
    while (r < run.names.size() && run.names[r] != ref.names[c]) ++r;
    if (r == run.names.size()) continue;
    for (const TimeSpan &w : windows) {
      try {
        out.push_back({label, ref.names[c], scoreDeltaZ(ref.curves[c], run.curves[r], w.begin, w.end)});
      } catch (const std::invalid_argument &e) {
        const std::string what = e.what();
        const bool refAtFault = what.find("of the reference") != std::string::npos;
        throw std::runtime_error("'" + (refAtFault ? ref.path : run.path) + "', " + ref.names[c] + ": " + what);
      }
    }
  }
  if (out.empty() && !windows.empty())
    throw std::runtime_error("'" + run.path + "' shares no curve with the reference '" + ref.path + "'.");
  return out;
}

void writeCurveScores(const std::string &path, const std::string &referencePath,
                      const std::vector<CurveScore> &scores, const std::string &moreRows) {
  std::string text = "# rcfd compare against " + referencePath +
                     ": window means and their relative difference (for delta_z the paper's Eq. 7, "
                     "Delta_seg); rms_difference over the times both curves cover, the reference "
                     "interpolated at the run's samples; values in the unit of the unit column\n"
                     "run,curve,unit,window_begin_s,window_end_s,samples_reference,samples_run,mean_reference,"
                     "mean_run,mean_difference,relative_difference_percent,curve_begin_s,curve_end_s,"
                     "curve_samples,rms_difference,peak_reference,rms_over_peak\n";
  for (const CurveScore &c : scores) {
    const DeltaZScore &s = c.score;
    text += c.run + "," + c.curve + ",m," + exactNumber(s.windowBegin) + "," + exactNumber(s.windowEnd) + "," +
            std::to_string(s.windowSamplesRef) + "," + std::to_string(s.windowSamplesModel) + "," +
            csvNumber(s.meanRef) + "," + csvNumber(s.meanModel) + "," + csvNumber(s.meanModel - s.meanRef) + "," +
            csvNumber(s.segregationError) + "," + exactNumber(s.overlapBegin) + "," + exactNumber(s.overlapEnd) +
            "," + std::to_string(s.curveSamples) + "," + csvNumber(s.rms) + "," + csvNumber(s.peakRef) + "," +
            csvNumber(s.rmsRelative) + "\n";
  }
  writeTextFile(path, text + moreRows);
}

void writeCurvesSideBySide(const std::string &path, const CurveSet &ref, const std::vector<CurveSet> &runs,
                           const std::vector<std::string> &labels) {
  std::string text = "time_s";
  for (const auto &name : ref.names) {
    text += "," + name + "_reference_m";
    for (const auto &l : labels) text += "," + name + "_" + l + "_m";
  }
  text += "\n";
  const DeltaZSeries &clock = ref.curves.front();
  for (std::size_t k = 0; k < clock.time.size(); ++k) {
    const double t = clock.time[k];
    text += csvNumber(t);
    for (std::size_t c = 0; c < ref.names.size(); ++c) {
      text += "," + (c == 0 ? csvNumber(clock.deltaZ[k]) : csvNumber(interpolate(ref.curves[c], t)));
      for (const CurveSet &run : runs) {
        text += ",";
        for (std::size_t r = 0; r < run.names.size(); ++r)
          if (run.names[r] == ref.names[c] && t >= run.curves[r].time.front() && t <= run.curves[r].time.back())
            text += csvNumber(interpolate(run.curves[r], t));
      }
    }
    text += "\n";
  }
  writeTextFile(path, text);
}

double bedDynamicsOfFile(const CsvTable &table) {
  const AnswerFile kind = answerFileKind(table);
  if (kind == AnswerFile::bedDynamics) {
    if (table.numRows() != 1)
      throw std::runtime_error("'" + table.path() + "' should hold one row of bed dynamics.");
    return table.number(0, table.find({"delta_z_cog_m"}));
  }
  bool ensemble = false; // an ensemble.csv: <column>_mean and _std for every column
  for (const auto &name : table.columns()) ensemble = ensemble || endsWith(name, "_mean");
  if (ensemble)
    throw std::runtime_error("'" + table.path() + "' is an ensemble summary: the mean of its members damps the "
                             "bed's motion, so give one member's cog.csv for the bed dynamics.");
  if (kind != AnswerFile::centresOfGravity || table.find({"z_cog_bed_m", "z_cog_bed"}) < 0)
    throw std::runtime_error("'" + table.path() + "' has no z_cog_bed_m column (a cog.csv of rcfd run or rcfd "
                             "reference, or a bed_dynamics.csv, gives the bed dynamics).");
  const std::string column = table.columns()[table.find({"z_cog_bed_m", "z_cog_bed"})];
  return bedDynamics(readSeries(table, column).deltaZ);
}

void writeTextFile(const std::string &path, const std::string &text) {
  const std::filesystem::path p(path);
  if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path());
  writeTextAtomically(path, text);
}

} // namespace rcfd
