#include "particles/size_classes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace rcfd {

int SizeClasses::classOf(double d) const {
  int best = -1;
  double bestGap = 0.0;
  for (int c = 0; c < static_cast<int>(diameter.size()); ++c) {
    const double gap = std::fabs(d - diameter[c]);
    if (gap <= relTol * diameter[c] && (best < 0 || gap < bestGap)) {
      best = c;
      bestGap = gap;
    }
  }
  return best;
}

std::string SizeClasses::label(int c) const {
  char buf[64];
  std::snprintf(buf, sizeof buf, "d%.3fmm", diameter.at(c) * 1e3);
  return buf;
}

SizeClasses SizeClasses::cluster(std::vector<double> diameters, double relTol) {
  if (!(relTol >= 0.0))
    throw std::invalid_argument("SizeClasses::cluster: the tolerance must be >= 0");
  SizeClasses sc;
  sc.relTol = relTol;
  std::sort(diameters.begin(), diameters.end());
  std::size_t b = 0;
  while (b < diameters.size()) {
    std::size_t e = b;
    double sum = 0.0;
    while (e < diameters.size() && diameters[e] <= diameters[b] * (1.0 + relTol))
      sum += diameters[e++];
    sc.diameter.push_back(sum / static_cast<double>(e - b));
    b = e;
  }
  return sc;
}

} // namespace rcfd
