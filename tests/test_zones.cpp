// Named zones resolved onto a box mesh: every shape holds the cells counted by
// hand, the same cells on 1 and 2 ranks (global counts and volumes), gravity
// along another axis moves "bottom" with it, and bad zones are refused with a
// sentence naming them.  Runs at 1 and 2 ranks.
#include "check.hpp"
#include "box_meshes.hpp"
#include "base/petsc_compat.hpp"
#include "rcfd/zone.hpp"

#include <string>

using namespace rcfd;

namespace {

// 4 x 2 x 10 cells of 0.1 x 0.1 x 0.1 m, origin 0.
Mesh column() {
  BoxSpec s;
  s.nx = 4;
  s.ny = 2;
  s.nz = 10;
  s.length = {0.4, 0.2, 1.0};
  return rcfd::test::boxMesh(s);
}

PetscInt cellsOf(Zone zone, const Mesh &mesh, const Layout &layout, const Vec3 &g, PetscErrorCode *ierr) {
  *ierr = zone.setUp(mesh, layout, g);
  return *ierr ? -1 : zone.numCells();
}

PetscErrorCode run() {
  PetscFunctionBeginUser;
  const Mesh mesh = column();
  Layout layout;
  PetscCall(Layout::create(PETSC_COMM_WORLD, mesh, &layout));
  const Vec3 down{0.0, 0.0, -9.81};
  PetscErrorCode ierr = 0;
  using S = Zone::Shape;
  // The bottom layer: one row of 4 x 2 cells; layers 2..4: 24 cells.
  RCFD_CHECK(cellsOf(Zone("bottom", S::Layers, {0, 0}), mesh, layout, down, &ierr) == 8 && !ierr);
  RCFD_CHECK(cellsOf(Zone("l", S::Layers, {2, 4}), mesh, layout, down, &ierr) == 24);
  // Heights 0.3..0.5 m hold the centres 0.35 and 0.45 (cell centres are 0.05, 0.15, ...): 2 layers.
  RCFD_CHECK(cellsOf(Zone("h", S::Heights, {0.3, 0.5}), mesh, layout, down, &ierr) == 16);
  // Box x in [0, 0.2], z in [0.9, 1.0]: 2 x 2 x 1 cells.
  RCFD_CHECK(cellsOf(Zone("b", S::Box, {0, 0.2, 0, 0.2, 0.9, 1.0}), mesh, layout, down, &ierr) == 4);
  // Half-space x <= 0.1: one column of cells of 2 x 10.
  RCFD_CHECK(cellsOf(Zone("hs", S::HalfSpace, {1, 0, 0, 0.1}), mesh, layout, down, &ierr) == 20);
  // Vertical cylinder around (0.2, 0.1), radius 0.08, heights 0..0.1: the four
  // centres (0.15|0.25, 0.05|0.15) at distance 0.0707 in the bottom layer.
  RCFD_CHECK(cellsOf(Zone("c", S::Cylinder, {0.2, 0.1, 0.08, 0.0, 0.1}), mesh, layout, down, &ierr) == 4);
  // Gravity along +x: the "bottom" layer is the column of cells at the largest x.
  Zone sideways("s", S::Layers, {0, 0});
  PetscCall(sideways.setUp(mesh, layout, Vec3{9.81, 0.0, 0.0}));
  RCFD_CHECK(sideways.numCells() == 20);
  for (PetscInt i : sideways.localCells())
    RCFD_CHECK(mesh.cellCentre[layout.ownedNatural()[i]][0] > 0.3);
  RCFD_CHECK_CLOSE(sideways.volume(), 20 * 1e-3, 1e-14);
  // Refused: a zone outside the mesh, wrong numbers, a non-box shape given wrongly.
  RCFD_CHECK(cellsOf(Zone("empty", S::Box, {1, 2, 1, 2, 1, 2}), mesh, layout, down, &ierr) == -1 && ierr);
  RCFD_CHECK(cellsOf(Zone("few", S::Box, {0, 1}), mesh, layout, down, &ierr) == -1 && ierr);
  RCFD_CHECK(cellsOf(Zone("inv", S::Layers, {3, 1}), mesh, layout, down, &ierr) == -1 && ierr);
  RCFD_CHECK(cellsOf(Zone("r0", S::Cylinder, {0, 0, 0, 0, 1}), mesh, layout, down, &ierr) == -1 && ierr);
  // From options: two zones, each with one shape.
  PetscCall(PetscOptionsSetValue(nullptr, "-zones", "spray,discharge"));
  PetscCall(PetscOptionsSetValue(nullptr, "-zone_spray_heights", "0.5,0.7"));
  PetscCall(PetscOptionsSetValue(nullptr, "-zone_discharge_box", "0,0.1,0,0.2,0,0.1"));
  ZoneSet zones;
  PetscCall(zones.setFromOptions(PETSC_COMM_WORLD));
  PetscCall(zones.setUp(mesh, layout, down));
  RCFD_CHECK(zones.all().size() == 2 && zones.find("spray") && zones.find("spray")->numCells() == 16);
  RCFD_CHECK(zones.find("discharge") && zones.find("discharge")->numCells() == 2 && !zones.find("feed"));
  // A zone with two shapes is refused.
  PetscCall(PetscOptionsSetValue(nullptr, "-zone_spray_layers", "0,1"));
  ZoneSet twice;
  RCFD_CHECK(twice.setFromOptions(PETSC_COMM_WORLD) != 0);
  PetscCall(PetscOptionsClear(nullptr));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  const PetscErrorCode ierr = run();
  RCFD_CHECK(ierr == 0);
  PetscPopErrorHandler();
  PetscCall(PetscFinalize());
  return RCFD_TEST_RESULT();
}
