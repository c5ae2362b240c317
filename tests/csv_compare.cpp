// csv_compare A B TOL [ABS [COLUMN=ABS ...]]: the two CSV files have the same
// header and the same number of rows, and every number agrees within TOL
// relative to max(|a|, |b|) or within the absolute floor ABS (default 1e-15).
// COLUMN=ABS gives a column its own floor, e.g. for a column that is itself a
// relative round-off figure (bulk_mismatch), where a relative test means
// nothing.  Prints the worst difference.
#include "base/csv.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

using rcfd::csv::Table;

static int compare(int argc, char **argv) {
  const double rel = std::atof(argv[3]), abs = argc > 4 ? std::atof(argv[4]) : 1e-15;
  const Table a = Table::read(argv[1]), b = Table::read(argv[2]);
  if (a.columns() != b.columns() || a.numRows() != b.numRows()) {
    std::fprintf(stderr, "csv_compare: %s and %s differ in header or length (%zu vs %zu rows)\n",
                 argv[1], argv[2], a.numRows(), b.numRows());
    return 1;
  }
  const auto &names = a.columns();
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
  for (size_t r = 0; r < a.numRows(); ++r)
    for (int c = 0; c < static_cast<int>(names.size()); ++c) {
      if (a.field(r, c) == b.field(r, c)) continue; // same text (also nan, inf)
      const double u = a.number(r, c), v = b.number(r, c);
      const double d = std::fabs(u - v);
      const double scaled = d / std::fmax(std::fmax(std::fabs(u), std::fabs(v)), 1e-300);
      if (d > floors[c] && scaled > rel) {
        std::fprintf(stderr, "csv_compare: %s, column '%s': %s vs %s (relative %.3g > %g)\n",
                     a.where(r).c_str(), names[c].c_str(), std::string(a.field(r, c)).c_str(),
                     std::string(b.field(r, c)).c_str(), scaled, rel);
        return 1;
      }
      if (d > floors[c]) worst = std::fmax(worst, scaled);
    }
  std::printf("csv_compare: %zu rows agree; largest relative difference %.3g\n", a.numRows(), worst);
  return 0;
}

int main(int argc, char **argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: csv_compare A B RELTOL [ABSTOL [COLUMN=ABSTOL ...]]\n");
    return 2;
  }
  try {
    return compare(argc, argv);
  } catch (const std::exception &e) {
    std::fprintf(stderr, "csv_compare: %s\n", e.what());
    return 2;
  }
}
