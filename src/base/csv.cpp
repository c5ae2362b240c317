#include "base/csv.hpp"

#include "base/input_file.hpp"

#include <limits>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <stdexcept>

namespace rcfd::csv {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

} // namespace

void splitLine(std::string_view line, std::vector<std::string_view> &fields) {
  fields.clear();
  std::size_t b = 0;
  for (;;) {
    const std::size_t e = line.find(',', b);
    fields.push_back(trim(line.substr(b, e == std::string_view::npos ? std::string_view::npos : e - b)));
    if (e == std::string_view::npos) break;
    b = e + 1;
  }
}

bool isSkipped(std::string_view line) {
  line = trim(line);
  return line.empty() || line.front() == '#';
}

bool parseNumber(std::string_view t, double &v) {
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  return !t.empty() && r.ec == std::errc() && r.ptr == t.data() + t.size() && std::isfinite(v);
}

Table Table::read(const std::string &path, const std::string &what) {
  requireRegularFile(path);
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open the " + what + " '" + path + "'.");
  Table t;
  t.file = path;
  std::string line;
  std::vector<std::string_view> fields;
  long lineNo = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    if (isSkipped(line)) continue;
    splitLine(line, fields);
    if (t.names.empty()) {
      t.names.assign(fields.begin(), fields.end());
      continue;
    }
    if (fields.size() != t.names.size())
      throw std::runtime_error("'" + path + "', line " + std::to_string(lineNo) + ": expected " +
                               std::to_string(t.names.size()) + " values (as many as the header " +
                               "names), found " + std::to_string(fields.size()) + ".");
    t.rows.emplace_back(fields.begin(), fields.end());
    t.lines.push_back(lineNo);
  }
  if (in.bad()) throw std::runtime_error("reading the " + what + " '" + path + "' failed.");
  if (t.names.empty())
    throw std::runtime_error("'" + path + "' is empty: expected a header line naming the columns.");
  return t;
}

int Table::find(std::initializer_list<std::string_view> choices) const {
  for (std::string_view c : choices) {
    const auto it = std::find(names.begin(), names.end(), c);
    if (it != names.end()) return static_cast<int>(it - names.begin());
  }
  return -1;
}

std::string Table::where(size_t row) const {
  return "'" + file + "', line " + std::to_string(lines[row]);
}

double Table::number(size_t row, int column) const {
  double v = 0.0;
  if (!parseNumber(rows[row][column], v))
    throw std::runtime_error(where(row) + ", column '" + names[column] +
                             "': expected a number, found '" + rows[row][column] + "'.");
  return v;
}

double Table::numberOrNan(size_t row, int column) const {
  const std::string_view f = field(row, column);
  if (f.empty() || f == "nan" || f == "-nan") return std::numeric_limits<double>::quiet_NaN();
  return number(row, column);
}

} // namespace rcfd::csv
