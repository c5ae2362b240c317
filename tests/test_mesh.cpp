// Box mesh connectivity and the shift-from-transfers builder.
#include "check.hpp"
#include "rcfd/frames.hpp"
#include "rcfd/mesh.hpp"

#include <cmath>
#include <stdexcept>

using namespace rcfd;

int main() {
  BoxSpec spec;
  spec.nx = 4;
  spec.ny = 3;
  spec.nz = 5;
  spec.origin = {-1.0, 0.0, 2.0};
  spec.length = {0.4, 0.3, 1.0};
  const Mesh m = Mesh::box(spec);
  RCFD_CHECK(m.numCells() == 60);
  // Internal faces: (nx-1) ny nz + nx (ny-1) nz + nx ny (nz-1).
  RCFD_CHECK(m.numFaces() == 3 * 3 * 5 + 4 * 2 * 5 + 4 * 3 * 4);
  RCFD_CHECK(m.numBoundaryFaces() == 2 * (3 * 5 + 4 * 5 + 4 * 3));
  RCFD_CHECK_CLOSE(m.totalVolume(), 0.4 * 0.3 * 1.0, 1e-14);
  // Closed cells: the area vectors of each cell's faces sum to zero.
  std::vector<Vec3> closure(m.numCells(), Vec3{0, 0, 0});
  for (int f = 0; f < m.numFaces(); ++f)
    for (int a = 0; a < 3; ++a) {
      closure[m.faceOwner[f]][a] += m.faceArea[f][a];
      closure[m.faceNeighbour[f]][a] -= m.faceArea[f][a];
    }
  for (int f = 0; f < m.numBoundaryFaces(); ++f)
    for (int a = 0; a < 3; ++a) closure[m.boundaryOwner[f]][a] += m.boundaryArea[f][a];
  double worst = 0;
  for (const auto &c : closure)
    for (double x : c) worst = std::fmax(worst, std::fabs(x));
  RCFD_CHECK(worst < 1e-15);
  // Area vectors point from owner to neighbour: the neighbour's centre is further along.
  for (int f = 0; f < m.numFaces(); ++f) {
    const auto &a = m.cellCentre[m.faceOwner[f]], &b = m.cellCentre[m.faceNeighbour[f]];
    const double dot = (b[0] - a[0]) * m.faceArea[f][0] + (b[1] - a[1]) * m.faceArea[f][1] +
                       (b[2] - a[2]) * m.faceArea[f][2];
    RCFD_CHECK(dot > 0);
  }
  // locate: centres map to their own cell, outside points to -1.
  for (int c = 0; c < m.numCells(); ++c) RCFD_CHECK(spec.locate(m.cellCentre[c]) == c);
  RCFD_CHECK(spec.locate({-1.01, 0.1, 2.5}) == -1);
  RCFD_CHECK(spec.locate({-0.65, 0.1, 3.0}) == spec.cellIndex(3, 1, 4)); // the top face belongs to the top cell
  RCFD_CHECK(spec.locate({NAN, 0.1, 2.5}) == -1);

  // shiftFromTransfers: weights 3 and 1 out of cell 0, nothing out of cell 2.
  const CsrMatrix T = shiftFromTransfers(3, {0, 1, 1, 1}, {0, 0, 1, 0}, {2.0, 1.0, 5.0, 1.0});
  RCFD_CHECK(T.nnz() == 4);
  // Row 0: (0,0) = 2/4; row 1: (1,0) = 2/4, (1,1) = 1; row 2: identity (2,2) = 1.
  RCFD_CHECK(T.rowPtr == (std::vector<int64_t>{0, 1, 3, 4}));
  RCFD_CHECK(T.col == (std::vector<int32_t>{0, 0, 1, 2}));
  RCFD_CHECK_CLOSE(T.val[0], 0.5, 1e-15);
  RCFD_CHECK_CLOSE(T.val[1], 0.5, 1e-15);
  RCFD_CHECK_CLOSE(T.val[2], 1.0, 1e-15);
  RCFD_CHECK_CLOSE(T.val[3], 1.0, 1e-15);
  bool threw = false;
  try {
    shiftFromTransfers(2, {0}, {5}, {1.0});
  } catch (const std::out_of_range &) {
    threw = true;
  }
  RCFD_CHECK(threw);
  return RCFD_TEST_RESULT();
}
