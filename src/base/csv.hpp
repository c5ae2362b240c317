// The one CSV reader: comma-separated text with a header line naming the
// columns, as rcfd writes it (cog.csv) and as users give it (particle
// snapshots, references).  Errors name the file, the line and the column.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace rcfd::csv {

/// Split one line at commas into `fields`, each trimmed of blanks (and of a
/// trailing '\r').  An empty line gives one empty field.
void splitLine(std::string_view line, std::vector<std::string_view> &fields);

/// Whether the line holds nothing but blanks, or is a comment ('#' first).
bool isSkipped(std::string_view line);

/// Parse a whole field as a finite number (locale-independent); false if
/// the field is empty, not a number, has trailing characters or overflows.
bool parseNumber(std::string_view field, double &value);

/// A whole CSV file in memory: the header's column names and the rows'
/// fields as text.  Blank lines and '#' comments are skipped anywhere.
class Table {
public:
  /// Throws std::runtime_error naming the file when it cannot be read, has
  /// no header, or a row holds another number of fields than the header;
  /// `what` names the kind of file in those messages.
  static Table read(const std::string &path, const std::string &what = "CSV file");

  const std::string &path() const { return file; }
  const std::vector<std::string> &columns() const { return names; }
  /// Index of the first of `choices` present in the header; -1 if none is.
  int find(std::initializer_list<std::string_view> choices) const;
  size_t numRows() const { return rows.size(); }
  /// Line of the file that row `r` came from (1-based), for messages.
  long lineOf(size_t row) const { return lines[row]; }
  std::string_view field(size_t row, int column) const { return rows[row][column]; }
  /// The field as a number; throws "'<file>', line L, column '<name>':
  /// expected a number, found '<text>'".
  double number(size_t row, int column) const;
  /// The same, but an empty field or "nan" (how rcfd writes a value that does not
  /// exist, such as the centre of gravity of an empty fraction) gives NaN, a gap.
  double numberOrNan(size_t row, int column) const;
  /// "'<file>', line L" for the line of row `r`, to start a message.
  std::string where(size_t row) const;

private:
  std::string file;
  std::vector<std::string> names;
  std::vector<std::vector<std::string>> rows;
  std::vector<long> lines;
};

} // namespace rcfd::csv
