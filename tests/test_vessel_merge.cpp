// Tiny cut cells merged into their neighbours (-vessel_merge_below, docs/vessels.md): the merged
// mesh keeps the vessel's volume and, at every height, its open cross-section; no cell is left
// below the threshold unless it has no open neighbour; every box cell inside maps to one cell;
// the threshold is in the vessel's line; a threshold of 0 is the unmerged mesh bit for bit.
#include "base/collective.hpp"
#include "check.hpp"
#include "mesh/vessel_mesh.hpp"

#include <cmath>
#include <cstdio>
#include <set>
#include <tuple>

using namespace rcfd;

namespace {

void addShape(Vessel &v, Vessel::Kind kind, std::vector<double> p, bool subtract = false) {
  throwOnError([&] { return v.add(kind, std::move(p), subtract); });
}

bool sameMesh(const Mesh &a, const Mesh &b) {
  return a.cellCentre == b.cellCentre && a.cellVolume == b.cellVolume && a.faceOwner == b.faceOwner &&
         a.faceNeighbour == b.faceNeighbour && a.faceArea == b.faceArea && a.boundaryOwner == b.boundaryOwner &&
         a.boundaryPatch == b.boundaryPatch && a.boundaryArea == b.boundaryArea && a.vessel() == b.vessel();
}

// The checks on `vessel` merged below S against the unmerged mesh; returns the merged cells.
int checkMerged(const char *label, Vessel vessel, double S, const BoxSpec &box) {
  const Mesh plain = cutVesselMesh(vessel, box);
  throwOnError([&] { return vessel.setMergeBelow(S); });
  const Mesh m = cutVesselMesh(vessel, box);
  const Vec3 h = box.spacing();
  const double V = h[0] * h[1] * h[2];

  // The volume: the same cells' inside volumes, added (rounding only).
  RCFD_CHECK_CLOSE(m.totalVolume(), plain.totalVolume(), 1e-13);
  // Every box cell of the unmerged mesh is in exactly one cell; none other is.
  for (int b = 0; b < box.numCells(); ++b) RCFD_CHECK((m.cellOfBoxCell(b) >= 0) == (plain.cellOfBoxCell(b) >= 0));
  RCFD_CHECK(m.numCells() + static_cast<int>(m.mergedBoxCells().size()) == plain.numCells());
  std::vector<double> gathered(m.numCells(), 0.0);
  for (int c = 0; c < plain.numCells(); ++c) gathered[m.cellOfBoxCell(plain.boxCell(c))] += plain.cellVolume[c];
  for (int c = 0; c < m.numCells(); ++c) {
    RCFD_CHECK_CLOSE(gathered[c], m.cellVolume[c], 1e-13);
    RCFD_CHECK(m.cellOfBoxCell(m.boxCell(c)) == c);
    if (c > 0) RCFD_CHECK(m.boxCell(c) > m.boxCell(c - 1)); // the box's order, as the database requires
  }
  // No face inside a cell, each pair of cells along an axis once, areas pointing from owner to neighbour.
  std::set<std::tuple<int, int, int>> pairs;
  for (int f = 0; f < m.numFaces(); ++f) {
    RCFD_CHECK(m.faceOwner[f] != m.faceNeighbour[f]);
    const Vec3 &a = m.faceArea[f];
    const int axis = a[0] != 0.0 ? 0 : a[1] != 0.0 ? 1 : 2;
    RCFD_CHECK(pairs.insert({m.faceOwner[f], m.faceNeighbour[f], axis}).second);
  }
  // At every height the horizontal faces' open areas (the box's floor and top as boundary faces)
  // sum to the same cross-section as without merging: faces inside a merged cell drop out of
  // the planes they lie in, so they are counted from the unmerged mesh's faces there.
  std::vector<double> plane(box.nz + 1, 0.0), plainPlane(box.nz + 1, 0.0);
  const int perLayer = box.nx * box.ny;
  for (int f = 0; f < plain.numFaces(); ++f)
    if (plain.faceArea[f][2] != 0.0) {
      const int k = plain.boxCell(plain.faceOwner[f]) / perLayer + 1;
      plainPlane[k] += plain.faceArea[f][2];
      // a face of the box between two members of one merged cell: open inside it
      if (m.cellOfBoxCell(plain.boxCell(plain.faceOwner[f])) == m.cellOfBoxCell(plain.boxCell(plain.faceNeighbour[f])))
        plane[k] += plain.faceArea[f][2];
    }
  for (int f = 0; f < m.numFaces(); ++f) {
    if (m.faceArea[f][2] == 0.0) continue;
    // the plane of a merged face: below the lowest member of its neighbour that touches its owner
    // (all of its box faces lie in one plane when both cells are one layer thick there)
    const int o = m.faceOwner[f], n = m.faceNeighbour[f];
    std::set<int> planes;
    for (int g = 0; g < plain.numFaces(); ++g)
      if (plain.faceArea[g][2] != 0.0 && m.cellOfBoxCell(plain.boxCell(plain.faceOwner[g])) == o &&
          m.cellOfBoxCell(plain.boxCell(plain.faceNeighbour[g])) == n)
        planes.insert(plain.boxCell(plain.faceOwner[g]) / perLayer + 1);
    RCFD_CHECK(!planes.empty());
    if (planes.size() == 1) plane[*planes.begin()] += m.faceArea[f][2];
    else // parallel faces in several planes: each box face where it lies
      for (int g = 0; g < plain.numFaces(); ++g)
        if (plain.faceArea[g][2] != 0.0 && m.cellOfBoxCell(plain.boxCell(plain.faceOwner[g])) == o &&
            m.cellOfBoxCell(plain.boxCell(plain.faceNeighbour[g])) == n)
          plane[plain.boxCell(plain.faceOwner[g]) / perLayer + 1] += plain.faceArea[g][2];
  }
  for (int f = 0; f < m.numBoundaryFaces(); ++f)
    if (m.boundaryPatch[f] == 4) plane[0] -= m.boundaryArea[f][2];
    else if (m.boundaryPatch[f] == 5) plane[box.nz] += m.boundaryArea[f][2];
  for (int f = 0; f < plain.numBoundaryFaces(); ++f)
    if (plain.boundaryPatch[f] == 4) plainPlane[0] -= plain.boundaryArea[f][2];
    else if (plain.boundaryPatch[f] == 5) plainPlane[box.nz] += plain.boundaryArea[f][2];
  double worstPlane = 0.0;
  for (int p = 0; p <= box.nz; ++p) worstPlane = std::fmax(worstPlane, std::fabs(plane[p] / plainPlane[p] - 1));
  RCFD_CHECK(worstPlane <= 1e-13);
  // The open areas between cells, all together, are the unmerged ones less those inside merged cells.
  double plainOpen = 0.0, open = 0.0, within = 0.0;
  for (int f = 0; f < plain.numFaces(); ++f) {
    const Vec3 &a = plain.faceArea[f];
    const double area = std::fabs(a[0]) + std::fabs(a[1]) + std::fabs(a[2]);
    plainOpen += area;
    if (m.cellOfBoxCell(plain.boxCell(plain.faceOwner[f])) == m.cellOfBoxCell(plain.boxCell(plain.faceNeighbour[f])))
      within += area;
  }
  for (const Vec3 &a : m.faceArea) open += std::fabs(a[0]) + std::fabs(a[1]) + std::fabs(a[2]);
  RCFD_CHECK_CLOSE(open + within, plainOpen, 1e-12);
  // No cell below S unless it has no open face to another cell.
  std::vector<int> faces(m.numCells(), 0);
  for (int f = 0; f < m.numFaces(); ++f) ++faces[m.faceOwner[f]], ++faces[m.faceNeighbour[f]];
  int small = 0, isolated = 0;
  double smallest = 1.0;
  for (int c = 0; c < m.numCells(); ++c) {
    smallest = std::fmin(smallest, m.cellVolume[c] / V);
    if (!(m.cellVolume[c] < S * V)) continue;
    faces[c] > 0 ? ++small : ++isolated;
  }
  double plainSmallest = 1.0;
  for (double v : plain.cellVolume) plainSmallest = std::fmin(plainSmallest, v / V);
  RCFD_CHECK(small == 0);
  // The centroid: volume-weighted over the members, and the cell's own box cell holds it when one does.
  std::vector<Vec3> weighted(m.numCells(), Vec3{0.0, 0.0, 0.0});
  for (int c = 0; c < plain.numCells(); ++c)
    for (int d = 0; d < 3; ++d)
      weighted[m.cellOfBoxCell(plain.boxCell(c))][d] += plain.cellVolume[c] * plain.cellCentre[c][d];
  for (int c = 0; c < m.numCells(); ++c)
    for (int d = 0; d < 3; ++d) RCFD_CHECK_CLOSE(weighted[c][d] / m.cellVolume[c], m.cellCentre[c][d], 1e-12);
  // The line records the threshold, and reads back to it.
  RCFD_CHECK(m.vessel() == vessel.describe() && m.vessel() != plain.vessel());
  RCFD_CHECK(parseVessel(m.vessel()).mergeBelow() == S);
  std::printf("%s, S = %g: %d cells -> %d (%zu box cells merged into others), smallest share %.4f -> %.4f, "
              "%d isolated below S, planes to %.1e\n",
              label, S, plain.numCells(), m.numCells(), m.mergedBoxCells().size(), plainSmallest, smallest, isolated,
              worstPlane);
  return static_cast<int>(m.mergedBoxCells().size());
}

} // namespace

int main(int argc, char **argv) {
  if (PetscInitialize(&argc, &argv, nullptr, nullptr)) return 1;
  BoxSpec box;
  box.nx = box.ny = 20;
  box.nz = 6;
  box.origin = {-0.1, -0.1, 0.0};
  box.length = {0.2, 0.2, 0.12};

  Vessel cylinder;
  addShape(cylinder, Vessel::Kind::Cylinder, {0.0, 0.0, 0.083});
  Vessel cone;
  addShape(cone, Vessel::Kind::Cone, {0.0, 0.0, 0.01, 0.03, 0.11, 0.09});
  Vessel bank;
  addShape(bank, Vessel::Kind::Box, {-1, 1, -1, 1, -1, 1});
  addShape(bank, Vessel::Kind::TubeY, {-0.045, 0.06, 0.03}, true);
  addShape(bank, Vessel::Kind::TubeY, {0.045, 0.06, 0.03}, true);
  for (double S : {0.1, 0.25}) {
    RCFD_CHECK(checkMerged("cylinder", cylinder, S, box) > 0);
    RCFD_CHECK(checkMerged("cone", cone, S, box) > 0);
    RCFD_CHECK(checkMerged("tube bank", bank, S, box) > 0);
  }

  // A threshold of 0 is the mesh without merging, bit for bit, and its line.
  Vessel zero = cylinder;
  throwOnError([&] { return zero.setMergeBelow(0.0); });
  RCFD_CHECK(sameMesh(cutVesselMesh(zero, box), cutVesselMesh(cylinder, box)));
  RCFD_CHECK(zero.describe() == cylinder.describe() && zero.describe().find("merge") == std::string::npos);
  RCFD_CHECK(cutVesselMesh(zero, box).mergedBoxCells().empty());
  // A threshold with nothing below it merges nothing: the same mesh, another line.
  Vessel tiny = cylinder;
  throwOnError([&] { return tiny.setMergeBelow(1e-9); });
  const Mesh tinyMesh = cutVesselMesh(tiny, box), plain = cutVesselMesh(cylinder, box);
  RCFD_CHECK(tinyMesh.cellVolume == plain.cellVolume && tinyMesh.faceArea == plain.faceArea &&
             tinyMesh.vessel() != plain.vessel());
  // Wrong thresholds: one sentence.
  RCFD_CHECK(rcfd::test::throwsWith([] { Vessel v; throwOnError([&] { return v.setMergeBelow(1.5); }); },
                                    "between 0 and 1"));
  RCFD_CHECK(rcfd::test::throwsWith([] { parseVessel("+cylinder(0,0,1) samples 8 merge -1"); }, "between 0 and 1"));
  PetscFinalize();
  return RCFD_TEST_RESULT();
}
