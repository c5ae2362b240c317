// How messages about Eulerian frames name numbers, points and cells.
#include "builders/eulerian/eulerian_cells.hpp"

#include <cstdio>

namespace rcfd::eulerian {

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", v);
  return text;
}

std::string point(const Vec3 &p) {
  return "(" + number(p[0]) + ", " + number(p[1]) + ", " + number(p[2]) + ")";
}

std::string cellName(const BoxSpec &b, int c) {
  const auto ijk = cellIjk(b, c);
  return "mesh cell (" + std::to_string(ijk[0]) + ", " + std::to_string(ijk[1]) + ", " +
         std::to_string(ijk[2]) + ") centred at " + point(cellCentre(b, ijk));
}

} // namespace rcfd::eulerian
