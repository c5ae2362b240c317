// csv_compare A B TOL [ABS [COLUMN=ABS ...]]: the two CSV files have the same
// header and the same number of rows, and every number agrees within TOL
// relative to max(|a|, |b|) or within the absolute floor ABS (default 1e-15).
// COLUMN=ABS gives a column its own floor, e.g. for a column that is itself a
// relative round-off figure (bulk_mismatch), where a relative test means
// nothing.  Prints the worst difference.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

static std::vector<std::string> lines(const char *path) {
  std::ifstream in(path);
  std::vector<std::string> out;
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

int main(int argc, char **argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: csv_compare A B RELTOL [ABSTOL [COLUMN=ABSTOL ...]]\n");
    return 2;
  }
  const double rel = std::atof(argv[3]), abs = argc > 4 ? std::atof(argv[4]) : 1e-15;
  const auto a = lines(argv[1]), b = lines(argv[2]);
  if (a.empty() || a.size() != b.size() || a[0] != b[0]) {
    std::fprintf(stderr, "csv_compare: %s and %s differ in header or length (%zu vs %zu lines)\n",
                 argv[1], argv[2], a.size(), b.size());
    return 1;
  }
  std::vector<std::string> names;
  {
    std::stringstream h(a[0]);
    for (std::string name; std::getline(h, name, ',');) names.push_back(name);
  }
  std::vector<double> floors(names.size(), abs);
  for (int k = 5; k < argc; ++k) {
    const std::string spec = argv[k];
    const auto eq = spec.find('=');
    size_t c = 0;
    while (c < names.size() && (eq == std::string::npos || names[c] != spec.substr(0, eq))) ++c;
    if (c == names.size()) return std::fprintf(stderr, "csv_compare: no column '%s' in %s\n", spec.c_str(), argv[1]), 2;
    floors[c] = std::atof(spec.c_str() + eq + 1);
  }
  double worst = 0.0;
  for (size_t r = 1; r < a.size(); ++r) {
    std::stringstream sa(a[r]), sb(b[r]);
    std::string x, y;
    for (size_t c = 0; std::getline(sa, x, ','); ++c) {
      const double floor = c < floors.size() ? floors[c] : abs;
      if (!std::getline(sb, y, ',')) return std::fprintf(stderr, "row %zu differs in length\n", r), 1;
      const double u = std::atof(x.c_str()), v = std::atof(y.c_str());
      const double d = std::fabs(u - v);
      const double scaled = d / std::fmax(std::fmax(std::fabs(u), std::fabs(v)), 1e-300);
      if (d > floor && scaled > rel) {
        std::fprintf(stderr, "csv_compare: row %zu: %s vs %s (relative %.3g > %g)\n", r, x.c_str(),
                     y.c_str(), scaled, rel);
        return 1;
      }
      if (d > floor) worst = std::fmax(worst, scaled);
    }
  }
  std::printf("csv_compare: %zu rows agree; largest relative difference %.3g\n", a.size() - 1, worst);
  return 0;
}
