// Sphere-box overlap volumes against analytic values: a sphere inside a box,
// cut by one plane (a cap), by two opposite planes (a slab), by two adjacent
// and by three planes through the centre (a quarter, an octant); the eight
// boxes around any point share the sphere exactly; disk-rectangle areas.
#include "check.hpp"

#include "particles/sphere_overlap.hpp"

#include <cmath>

using namespace rcfd;

int main() {
  const double R = 1.7e-3, V = 4.0 / 3.0 * M_PI * R * R * R, big = 1.0;
  const Vec3 c{0.01, -0.02, 0.03};
  auto box = [&](double x0, double x1, double y0, double y1, double z0, double z1) {
    return sphereBoxVolume(c, R, {c[0] + x0, c[1] + y0, c[2] + z0}, {c[0] + x1, c[1] + y1, c[2] + z1});
  };
  const double tol = 1e-12;
  // Inside.
  RCFD_CHECK_CLOSE(box(-big, big, -big, big, -big, big) / V, 1.0, tol);
  // A cap above z = h: pi (R - h)^2 (2R + h) / 3.
  for (double h : {-0.9 * R, -0.3 * R, 0.0, 0.45 * R, 0.99 * R}) {
    const double cap = M_PI * (R - h) * (R - h) * (2 * R + h) / 3.0;
    RCFD_CHECK_CLOSE(box(-big, big, -big, big, h, big) / V, cap / V, tol);
    RCFD_CHECK_CLOSE(box(h, big, -big, big, -big, big) / V, cap / V, tol); // the same cap along x
  }
  // A slab |y| <= h: pi (2 h R^2 - 2 h^3 / 3).
  for (double h : {0.1 * R, 0.5 * R, 0.97 * R}) {
    const double slab = M_PI * (2 * h * R * R - 2 * h * h * h / 3.0);
    RCFD_CHECK_CLOSE(box(-big, big, -h, h, -big, big) / V, slab / V, tol);
  }
  // Two adjacent planes through the centre: a quarter; three: an octant.
  RCFD_CHECK_CLOSE(box(0, big, 0, big, -big, big) / V, 0.25, tol);
  RCFD_CHECK_CLOSE(box(0, big, -big, 0, 0, big) / V, 0.125, tol);
  // The eight boxes around an arbitrary point inside the sphere share it exactly.
  for (const Vec3 &p : {Vec3{0.3 * R, -0.6 * R, 0.1 * R}, Vec3{0.9 * R, 0.05 * R, -0.2 * R},
                        Vec3{-0.5 * R, -0.5 * R, -0.5 * R}}) {
    double sum = 0.0;
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j)
        for (int k = 0; k < 2; ++k)
          sum += box(i ? p[0] : -big, i ? big : p[0], j ? p[1] : -big, j ? big : p[1], k ? p[2] : -big,
                     k ? big : p[2]);
    RCFD_CHECK_CLOSE(sum / V, 1.0, tol);
  }
  // Outside, and a box that only touches the sphere.
  RCFD_CHECK(box(R, big, -big, big, -big, big) == 0.0);
  RCFD_CHECK(box(2 * R, 3 * R, 0, R, 0, R) == 0.0);
  // Disk areas: whole, half, quarter, a band |y| <= r/2.
  const double r = 2.0, disk = M_PI * r * r;
  RCFD_CHECK_CLOSE(diskRectangleArea(r, -5, 5, -5, 5) / disk, 1.0, 1e-15);
  RCFD_CHECK_CLOSE(diskRectangleArea(r, 0, 5, -5, 5) / disk, 0.5, 1e-15);
  RCFD_CHECK_CLOSE(diskRectangleArea(r, -5, 0, 0, 5) / disk, 0.25, 1e-15);
  const double band = 2.0 * (0.5 * r * std::sqrt(r * r - 1.0) + r * r * std::asin(0.5)); // |y| <= 1
  RCFD_CHECK_CLOSE(diskRectangleArea(r, -5, 5, -1, 1), band, 1e-14);
  RCFD_CHECK(diskRectangleArea(r, 2.5, 5, -5, 5) == 0.0);
  return RCFD_TEST_RESULT();
}
