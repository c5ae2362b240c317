// One CSV line of numbers, as the granulator's monitors write them
// (product.csv, mass_account.csv, steady_state.csv): 10 significant digits,
// comma-separated.  Their rows are appended as they are made (CsvSeries), so
// that memory does not grow with the run's length.
#pragma once

#include <string>
#include <vector>

namespace rcfd {

/// "%.10g" (or `digits` significant digits) of each number, separated by commas, without a newline.
std::string numberRow(const std::vector<double> &values, int digits = 10);

} // namespace rcfd
