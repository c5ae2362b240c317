#include "analysis/halves_comparison.hpp"

#include "analysis/comparison.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace rcfd {
HalvesTable readHalves(const CsvTable &table) {
  if (answerFileKind(table) != AnswerFile::halves)
    throw std::runtime_error("'" + table.path() + "' is not a halves file: its header should be "
                             "class,diameter,bottom_mass_fraction,top_mass_fraction.");
  HalvesTable h{table.path(), {}, {}, {}, {}};
  for (std::size_t r = 0; r < table.numRows(); ++r) {
    h.label.emplace_back(table.field(r, 0));
    h.diameter.push_back(table.number(r, 1));
    h.bottom.push_back(table.number(r, 2));
    h.top.push_back(table.number(r, 3));
    if (!(h.diameter.back() > 0.0)) throw std::runtime_error(table.where(r) + ": the diameter is not positive.");
  }
  if (h.label.empty()) throw std::runtime_error("'" + table.path() + "' holds no classes.");
  return h;
}

double sauterDiameter(const std::vector<double> &m, const std::vector<double> &d) {
  double sum = 0.0, mass = 0.0;
  for (std::size_t i = 0; i < m.size(); ++i) sum += m[i] / d[i], mass += m[i];
  return sum > 0.0 ? mass / sum : std::nan("");
}

std::vector<HalvesDifference> compareHalves(const HalvesTable &ref, const HalvesTable &run,
                                            const std::string &label) {
  std::vector<HalvesDifference> out;
  for (std::size_t c = 0; c < ref.label.size(); ++c) {
    const int m = sameClass(ref.diameter[c], run.diameter);
    if (m < 0) continue;
    out.push_back({label, ref.label[c], ref.diameter[c], ref.bottom[c], run.bottom[m], ref.top[c], run.top[m]});
  }
  out.push_back({label, "d32", 0.0, sauterDiameter(ref.bottom, ref.diameter),
                 sauterDiameter(run.bottom, run.diameter), sauterDiameter(ref.top, ref.diameter),
                 sauterDiameter(run.top, run.diameter)});
  return out;
}

void writeHalvesScores(const std::string &path, const std::string &referencePath,
                       const std::vector<HalvesDifference> &rows) {
  std::string text = "# rcfd compare of the bottom and top halves' size distributions against " + referencePath +
                     ": mass fraction of each class (unit 1) in each half, and the halves' Sauter diameters "
                     "(row d32, unit m); difference = run - reference\n"
                     "run,class,diameter_m,unit,bottom_reference,bottom_run,bottom_difference,top_reference,"
                     "top_run,top_difference\n";
  for (const auto &d : rows) {
    const bool d32 = d.diameter == 0.0;
    text += d.run + "," + d.label + "," + (d32 ? "" : csvNumber(d.diameter)) + "," + (d32 ? "m" : "1") + "," +
            csvNumber(d.bottomRef) + "," + csvNumber(d.bottomRun) + "," + csvNumber(d.bottomRun - d.bottomRef) + "," +
            csvNumber(d.topRef) + "," + csvNumber(d.topRun) + "," + csvNumber(d.topRun - d.topRef) + "\n";
  }
  writeTextFile(path, text);
}

} // namespace rcfd
