// What the Eulerian reader, tracer and balancing share: the cells of a box
// mesh by (i, j, k), the rings of cells around one, and how messages name
// numbers, points and cells.
#pragma once

#include "rcfd/mesh.hpp"

#include <array>
#include <cstdlib>
#include <string>

namespace rcfd::eulerian {

/// Integer cell coordinates of a natural index.
inline std::array<int, 3> cellIjk(const BoxSpec &b, int c) {
  return {c % b.nx, (c / b.nx) % b.ny, c / (b.nx * b.ny)};
}

/// Centre of the cell (i, j, k).
inline Vec3 cellCentre(const BoxSpec &b, const std::array<int, 3> &ijk) {
  const Vec3 h = b.spacing();
  return {b.origin[0] + (ijk[0] + 0.5) * h[0], b.origin[1] + (ijk[1] + 0.5) * h[1],
          b.origin[2] + (ijk[2] + 0.5) * h[2]};
}

/// A number for a message, nine significant digits.
std::string number(double v);
/// "(x, y, z)" for a message.
std::string point(const Vec3 &p);
/// "mesh cell (i, j, k) centred at (x, y, z)" for a message.
std::string cellName(const BoxSpec &b, int c);

/// Calls f(cell) for every cell of the box at Chebyshev distance exactly R
/// from cell ijk (R = 0: the cell itself).
template <typename F> void forEachInRing(const BoxSpec &b, const std::array<int, 3> &c, int R, F &&f) {
  const int n[3] = {b.nx, b.ny, b.nz};
  for (int dk = -R; dk <= R; ++dk) {
    const int k = c[2] + dk;
    if (k < 0 || k >= n[2]) continue;
    for (int dj = -R; dj <= R; ++dj) {
      const int j = c[1] + dj;
      if (j < 0 || j >= n[1]) continue;
      const bool shell = std::abs(dk) == R || std::abs(dj) == R;
      for (int di = -R; di <= R; di += (shell || R == 0) ? 1 : 2 * R) {
        const int i = c[0] + di;
        if (i >= 0 && i < n[0]) f(b.cellIndex(i, j, k));
      }
    }
  }
}

} // namespace rcfd::eulerian
