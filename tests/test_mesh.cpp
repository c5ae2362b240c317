// Box mesh connectivity, its refusals, and the shift-from-transfers builder.
#include "check.hpp"
#include "box_meshes.hpp"
#include "rcfd/frames.hpp"
#include "rcfd/mesh.hpp"

#include <climits>
#include <cmath>
#include <stdexcept>
#include <string>

using namespace rcfd;

namespace {

/// Mesh::createBox refuses nx x ny x nz with PETSC_ERR_ARG_OUTOFRANGE and the
/// sentence `expected`, leaving the mesh it was given as it was.
void expectRefusal(int nx, int ny, int nz, const std::string &expected) {
  BoxSpec spec;
  spec.nx = nx, spec.ny = ny, spec.nz = nz;
  BoxSpec small;
  small.nx = 2, small.ny = 1, small.nz = 1;
  Mesh mesh = rcfd::test::boxMesh(small);
  const PetscErrorCode ierr = Mesh::createBox(spec, &mesh);
  char *why = nullptr;
  PetscErrorMessage(ierr, nullptr, &why);
  RCFD_CHECK(ierr == PETSC_ERR_ARG_OUTOFRANGE);
  RCFD_CHECK(why && std::string(why) == expected);
  if (why && std::string(why) != expected) std::printf("got '%s'\n", why);
  RCFD_CHECK(mesh.numCells() == 2 && mesh.boxSpec().nx == 2);
}

} // namespace

int main(int argc, char **argv) {
  if (PetscInitialize(&argc, &argv, nullptr, nullptr)) return 1;
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr); // the refusals print no traceback
  BoxSpec spec;
  spec.nx = 4;
  spec.ny = 3;
  spec.nz = 5;
  spec.origin = {-1.0, 0.0, 2.0};
  spec.length = {0.4, 0.3, 1.0};
  const Mesh m = rcfd::test::boxMesh(spec);
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

  // A box of no cell along an axis, or of more cells than an int numbers, is
  // refused in one sentence (no exception leaves the public API).
  expectRefusal(0, 2, 2, "a box mesh of 0 x 2 x 2 cells needs at least one cell along each axis");
  expectRefusal(4, -1, 2, "a box mesh of 4 x -1 x 2 cells needs at least one cell along each axis");
  char tooMany[200];
  std::snprintf(tooMany, sizeof tooMany,
                "a box mesh of 2000 x 2000 x 2000 cells asks for 8e+09 cells, more than the %d a mesh can number",
                INT_MAX);
  expectRefusal(2000, 2000, 2000, tooMany);
  PetscPopErrorHandler();
  const int result = RCFD_TEST_RESULT();
  if (PetscFinalize()) return 1;
  return result;
}
