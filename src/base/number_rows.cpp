#include "base/number_rows.hpp"

#include <cstdio>

namespace rcfd {

std::string numberRow(const std::vector<double> &values, int digits) {
  std::string text;
  char number[32];
  for (std::size_t c = 0; c < values.size(); ++c) {
    std::snprintf(number, sizeof number, "%.*g", digits, values[c]);
    text += (c ? "," : "") + std::string(number);
  }
  return text;
}

} // namespace rcfd
