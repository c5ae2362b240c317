#include "analysis/ensemble.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <stdexcept>

namespace rcfd {
namespace {

/// A numeric CSV file: its column names and values by column.
struct CsvTable {
  std::string path; // where it was read from, for messages
  std::vector<std::string> header;
  std::vector<std::vector<double>> columns;
};

std::string trim(const std::string &s) {
  const std::size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

std::vector<std::string> splitFields(const std::string &line) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(trim(line.substr(start, comma - start)));
    if (comma == std::string::npos) return fields;
    start = comma + 1;
  }
}

double parseNumber(const std::string &field, const std::string &where) {
  if (field.empty()) return std::nan(""); // a gap
  char *end = nullptr;
  const double v = std::strtod(field.c_str(), &end);
  if (end != field.c_str() + field.size()) throw std::runtime_error(where + "'" + field + "' is not a number.");
  return v;
}

/// The first line that is neither blank nor a '#' comment names the columns;
/// the others hold numbers.
CsvTable readCsv(const std::string &path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open the CSV file '" + path + "' (" + std::strerror(errno) + ").");
  CsvTable table{path, {}, {}};
  std::string line;
  for (int lineNo = 1; std::getline(in, line); ++lineNo) {
    const std::string text = trim(line);
    if (text.empty() || text[0] == '#') continue;
    std::vector<std::string> fields = splitFields(text);
    if (table.header.empty()) {
      table.header = std::move(fields);
      table.columns.assign(table.header.size(), {});
      continue;
    }
    const std::string where = path + ":" + std::to_string(lineNo) + ": ";
    if (fields.size() != table.header.size())
      throw std::runtime_error(where + "expected " + std::to_string(table.header.size()) +
                               " comma-separated fields but found " + std::to_string(fields.size()) + ".");
    for (std::size_t c = 0; c < fields.size(); ++c) table.columns[c].push_back(parseNumber(fields[c], where));
  }
  if (in.bad()) throw std::runtime_error("reading the CSV file '" + path + "' failed.");
  if (table.header.empty()) throw std::runtime_error("the CSV file '" + path + "' has no header line.");
  return table;
}

} // namespace

void writeEnsembleSummary(const std::vector<std::string> &memberCsvs, const std::string &csvOut) {
  if (memberCsvs.empty()) throw std::runtime_error("an ensemble needs at least one member");
  std::vector<CsvTable> members;
  for (const auto &p : memberCsvs) members.push_back(readCsv(p));
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
  const std::string tmp = csvOut + ".tmp";
  std::ofstream out(tmp);
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
  out.close();
  if (!out || std::rename(tmp.c_str(), csvOut.c_str()) != 0)
    throw std::runtime_error("cannot write '" + csvOut + "'");
}

} // namespace rcfd
