// How much of a spherical particle lies in a box-shaped cell.  A particle as
// large as a cell straddles up to eight cells; counting its whole volume in
// the cell of its centre then pushes alpha_s above 1 there (issue 12).  These
// volumes let a builder count every particle in the cells it overlaps.
#pragma once

#include "rcfd/mesh.hpp"

namespace rcfd {

/// Area of a disk of radius r centred at the origin inside the rectangle
/// [x0, x1] x [y0, y1] (exact: piecewise antiderivatives of the chord).
double diskRectangleArea(double r, double x0, double x1, double y0, double y1);

/// Volume of the sphere (centre c, radius R) inside the box [lo, hi].  The disk
/// areas are integrated along z between the heights where the cut disk meets an
/// edge or corner of the box, with a cosine substitution that removes the square
/// root behaviour at those heights: relative error below 1e-12 of the sphere
/// with the default 4 panels of 16-point Gauss-Legendre per piece; 1 panel is
/// four times cheaper and still within 1e-9 of the sphere (shares that are
/// normalised afterwards need no more).
double sphereBoxVolume(const Vec3 &c, double R, const Vec3 &lo, const Vec3 &hi, int panels = 4);

} // namespace rcfd
