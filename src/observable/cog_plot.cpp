#include "observable/cog_plot.hpp"

#include "plot/png_plot.hpp"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <stdexcept>

namespace rcfd {
namespace {

bool startsWith(const std::string &s, const std::string &p) { return s.rfind(p, 0) == 0; }

// "z_cog_d1.950mm_m" -> "d = 1.950 mm"; "z_cog_bed_m" -> "bed".
std::string legendOf(const std::string &column) {
  std::string core = column.substr(6, column.size() - 8); // strip "z_cog_" and "_m"
  if (core == "bed") return "bed";
  if (core.size() > 3 && core[0] == 'd' && core.substr(core.size() - 2) == "mm")
    return "d = " + core.substr(1, core.size() - 3) + " mm";
  return core;
}

std::vector<double> scaled(const std::vector<double> &v, double factor) {
  std::vector<double> out(v);
  for (double &x : out) x *= factor;
  return out;
}

std::string deltaPath(const std::string &png) {
  const auto dot = png.rfind('.');
  return (dot == std::string::npos ? png : png.substr(0, dot)) + "-delta.png";
}

} // namespace

void plotCogCsv(const std::string &csvPath, const std::string &pngPath, const std::string &title) {
  const plot::CsvTable t = plot::readCsv(csvPath);
  const auto &time = t.column("time_s");
  plot::Figure cog{title, "time [s]", "centre of gravity [mm]", {}};
  for (const auto &name : t.header)
    if (startsWith(name, "z_cog_")) cog.series.push_back({legendOf(name), time, scaled(t.column(name), 1e3), {}, {}});
  plot::writePng(pngPath, cog);
  plot::Figure delta{title, "time [s]", "delta z = z_cog(smallest) - z_cog(largest) [mm]", {}};
  delta.series.push_back({"delta z", time, scaled(t.column("delta_z_m"), 1e3), {}, {}});
  plot::writePng(deltaPath(pngPath), delta);
}

void summariseEnsemble(const std::vector<std::string> &memberCsvs, const std::string &csvOut,
                       const std::string &pngOut, const std::string &title) {
  if (memberCsvs.empty()) throw std::runtime_error("an ensemble needs at least one member");
  std::vector<plot::CsvTable> members;
  for (const auto &p : memberCsvs) members.push_back(plot::readCsv(p));
  const auto &header = members[0].header;
  const size_t rows = members[0].columns[0].size(), cols = header.size();
  for (const auto &m : members)
    if (m.header != header || m.columns[0].size() != rows)
      throw std::runtime_error("ensemble member '" + m.path + "' does not have the rows and columns of '" +
                               members[0].path + "'");
  std::vector<std::vector<double>> mean(cols, std::vector<double>(rows, 0.0)), sd = mean;
  const double n = static_cast<double>(members.size());
  for (size_t c = 0; c < cols; ++c)
    for (size_t r = 0; r < rows; ++r) {
      double s = 0.0, s2 = 0.0;
      for (const auto &m : members) s += m.columns[c][r];
      const double mu = s / n;
      for (const auto &m : members) s2 += (m.columns[c][r] - mu) * (m.columns[c][r] - mu);
      mean[c][r] = mu;
      sd[c][r] = members.size() > 1 ? std::sqrt(s2 / (n - 1)) : 0.0;
    }
  {
    const std::string tmp = csvOut + ".tmp";
    std::ofstream out(tmp);
    out << std::setprecision(10) << "# mean and sample standard deviation over " << members.size()
        << " ensemble members\n" << header[0];
    for (size_t c = 1; c < cols; ++c) out << ',' << header[c] << "_mean," << header[c] << "_std";
    out << '\n';
    for (size_t r = 0; r < rows; ++r) {
      out << mean[0][r];
      for (size_t c = 1; c < cols; ++c) out << ',' << mean[c][r] << ',' << sd[c][r];
      out << '\n';
    }
    out.close();
    if (!out || std::rename(tmp.c_str(), csvOut.c_str()) != 0)
      throw std::runtime_error("cannot write '" + csvOut + "'");
  }
  auto band = [&](size_t c, const std::string &label) {
    plot::Series s{label, mean[0], scaled(mean[c], 1e3), {}, {}};
    for (size_t r = 0; r < rows; ++r) {
      s.yLow.push_back(1e3 * (mean[c][r] - sd[c][r]));
      s.yHigh.push_back(1e3 * (mean[c][r] + sd[c][r]));
    }
    return s;
  };
  plot::Figure cog{title + " (mean +- 1 sd of " + std::to_string(members.size()) + " paths)", "time [s]",
                   "centre of gravity [mm]", {}};
  plot::Figure delta{cog.title, "time [s]", "delta z [mm]", {}};
  for (size_t c = 0; c < cols; ++c) {
    if (startsWith(header[c], "z_cog_")) cog.series.push_back(band(c, legendOf(header[c])));
    if (header[c] == "delta_z_m") delta.series.push_back(band(c, "delta z"));
  }
  plot::writePng(pngOut, cog);
  plot::writePng(deltaPath(pngOut), delta);
}

} // namespace rcfd
