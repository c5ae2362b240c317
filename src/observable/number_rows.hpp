// Rows of numbers kept in memory and written whole: for the granulator's
// monitors, whose steady-state test reads back over their own history.  (The
// time series of the run's other monitors append to their files instead,
// CsvSeries, so that memory does not grow with the run's length.)
#pragma once

#include <string>
#include <vector>

namespace rcfd {

class NumberRows {
public:
  explicit NumberRows(int width = 0) : width(width) {}
  void add(const std::vector<double> &row) { values.insert(values.end(), row.begin(), row.end()); }
  std::size_t size() const { return width ? values.size() / width : 0; }
  /// Header line, then one line per row with 10 significant digits.
  std::string csv(const std::string &header) const;
  const std::vector<double> &flat() const { return values; }
  /// Refuses a state whose length is not a multiple of the width.
  bool restore(const double *begin, std::size_t n);

private:
  int width;
  std::vector<double> values;
};

} // namespace rcfd
