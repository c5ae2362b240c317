#include "observable/number_rows.hpp"

#include <cstdio>

namespace rcfd {

std::string NumberRows::csv(const std::string &header) const {
  std::string text = header + "\n";
  char number[32];
  for (std::size_t r = 0; r < size(); ++r) {
    for (int c = 0; c < width; ++c) {
      std::snprintf(number, sizeof number, "%.10g", values[r * width + c]);
      text += (c ? "," : "") + std::string(number);
    }
    text += "\n";
  }
  return text;
}

bool NumberRows::restore(const double *begin, std::size_t n) {
  if (width == 0 || n % width != 0) return false;
  values.assign(begin, begin + n);
  return true;
}

} // namespace rcfd
