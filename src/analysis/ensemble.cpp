#include "analysis/ensemble.hpp"

#include "base/atomic_file.hpp"
#include "base/csv.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace rcfd {

void writeEnsembleSummary(const std::vector<std::string> &memberCsvs, const std::string &csvOut) {
  if (memberCsvs.empty()) throw std::runtime_error("an ensemble needs at least one member");
  std::vector<csv::Table> members;
  for (const auto &p : memberCsvs) members.push_back(csv::Table::read(p, "ensemble member"));
  const auto &header = members[0].columns();
  const size_t rows = members[0].numRows(), cols = header.size();
  for (const auto &m : members)
    if (m.columns() != header || m.numRows() != rows)
      throw std::runtime_error("ensemble member '" + m.path() + "' does not have the rows and columns of '" +
                               members[0].path() + "'");
  std::vector<std::vector<double>> mean(cols, std::vector<double>(rows, 0.0)), sd = mean;
  const double n = static_cast<double>(members.size());
  for (size_t c = 0; c < cols; ++c)
    for (size_t r = 0; r < rows; ++r) {
      double s = 0.0, s2 = 0.0;
      for (const auto &m : members) s += m.numberOrNan(r, static_cast<int>(c));
      const double mu = s / n;
      for (const auto &m : members) {
        const double d = m.numberOrNan(r, static_cast<int>(c)) - mu;
        s2 += d * d;
      }
      mean[c][r] = mu;
      sd[c][r] = members.size() > 1 ? std::sqrt(s2 / (n - 1)) : 0.0;
    }
  std::ostringstream out;
  out << std::setprecision(10) << "# mean and sample standard deviation over " << members.size()
      << " ensemble members\n"
      << header[0];
  for (size_t c = 1; c < cols; ++c) out << ',' << header[c] << "_mean," << header[c] << "_std";
  out << '\n';
  for (size_t r = 0; r < rows; ++r) {
    out << mean[0][r];
    for (size_t c = 1; c < cols; ++c) out << ',' << mean[c][r] << ',' << sd[c][r];
    out << '\n';
  }
  writeTextAtomically(csvOut, out.str());
}

} // namespace rcfd
