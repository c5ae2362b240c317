#include "particles/sphere_overlap.hpp"

#include <algorithm>
#include <cmath>

namespace rcfd {
namespace {

// Antiderivative of the half chord s(x) = sqrt(r^2 - x^2) on [-r, r].
double halfChordIntegral(double r, double x) {
  const double t = std::clamp(x / r, -1.0, 1.0);
  return 0.5 * r * r * (t * std::sqrt(1.0 - t * t) + std::asin(t));
}

// 16-point Gauss-Legendre nodes and weights on [-1, 1] (positive half).
constexpr double kNodes[8] = {0.0950125098376374, 0.2816035507792589, 0.4580167776572274,
                              0.6178762444026438, 0.7554044083550030, 0.8656312023878318,
                              0.9445750230732326, 0.9894009349916499};
constexpr double kWeights[8] = {0.1894506104550685, 0.1826034150449236, 0.1691565193950025,
                                0.1495959888165767, 0.1246289712555339, 0.0951585116824928,
                                0.0622535239386479, 0.0271524594117541};

// Sorts the few values of [first, first + n) in place.  std::sort here makes GCC 12 warn
// (-Warray-bounds) about its branch for more than 16 values, which a 6-value array never takes.
void sortFew(double *first, std::size_t n) {
  for (std::size_t i = 1; i < n; ++i)
    for (std::size_t j = i; j > 0 && first[j] < first[j - 1]; --j) std::swap(first[j], first[j - 1]);
}

} // namespace

double diskRectangleArea(double r, double x0, double x1, double y0, double y1) {
  const double a = std::max(x0, -r), b = std::min(x1, r);
  if (!(r > 0.0) || a >= b || y0 >= y1 || y0 >= r || y1 <= -r) return 0.0;
  // Between consecutive breakpoints each of the two bounds is either the
  // rectangle's edge or the circle.
  double cuts[6] = {a, b};
  std::size_t n = 2;
  for (double y : {y0, y1})
    if (std::fabs(y) < r) {
      const double x = std::sqrt(r * r - y * y);
      for (double v : {-x, x})
        if (v > a && v < b) cuts[n++] = v;
    }
  sortFew(cuts, n);
  double area = 0.0;
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double lo = cuts[i], hi = cuts[i + 1];
    if (hi <= lo) continue;
    const double mid = 0.5 * (lo + hi), s = std::sqrt(std::max(0.0, r * r - mid * mid));
    const bool topIsCircle = s < y1, bottomIsCircle = -s > y0;
    if ((topIsCircle ? s : y1) <= (bottomIsCircle ? -s : y0)) continue; // disk misses the band here
    const double chord = halfChordIntegral(r, hi) - halfChordIntegral(r, lo);
    area += (topIsCircle ? chord : y1 * (hi - lo)) - (bottomIsCircle ? -chord : y0 * (hi - lo));
  }
  return area;
}

double sphereBoxVolume(const Vec3 &c, double R, const Vec3 &lo, const Vec3 &hi, int panels) {
  const double x0 = lo[0] - c[0], x1 = hi[0] - c[0], y0 = lo[1] - c[1], y1 = hi[1] - c[1];
  const double za = std::max(lo[2] - c[2], -R), zb = std::min(hi[2] - c[2], R);
  if (!(R > 0.0) || za >= zb) return 0.0;
  // Heights where the disk's radius passes an edge or a corner distance: the
  // area is smooth in between.
  double cuts[20] = {za, zb};
  std::size_t n = 2;
  auto addDistance = [&](double d2) {
    if (d2 < R * R) {
      const double z = std::sqrt(R * R - d2);
      for (double v : {-z, z})
        if (v > za && v < zb) cuts[n++] = v;
    }
  };
  for (double x : {x0, x1}) addDistance(x * x);
  for (double y : {y0, y1}) addDistance(y * y);
  for (double x : {x0, x1})
    for (double y : {y0, y1}) addDistance(x * x + y * y);
  cuts[n++] = 0.0; // the disk's radius turns there
  std::sort(cuts, cuts + n);
  double volume = 0.0;
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double a = cuts[i], b = cuts[i + 1];
    if (!(b > a) || a < za || b > zb) continue;
    // z = a + (b - a)(1 - cos(pi t))/2, t in [0, 1]: dz/dt vanishes at both ends,
    // which smooths the (z - a)^(1/2) and ^(3/2) behaviour there.
    auto integrand = [&](double t) {
      const double z = a + (b - a) * 0.5 * (1.0 - std::cos(M_PI * t));
      const double rho = std::sqrt(std::max(0.0, R * R - z * z));
      return diskRectangleArea(rho, x0, x1, y0, y1) * (b - a) * 0.5 * M_PI * std::sin(M_PI * t);
    };
    // Composite: `panels` panels of 16-point Gauss-Legendre in t.
    for (int p = 0; p < panels; ++p) {
      const double t0 = static_cast<double>(p) / panels, h = 0.5 / panels, m = t0 + h;
      for (int k = 0; k < 8; ++k)
        volume += h * kWeights[k] * (integrand(m - h * kNodes[k]) + integrand(m + h * kNodes[k]));
    }
  }
  return volume;
}

} // namespace rcfd
