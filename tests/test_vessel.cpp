// Vessels cut out of a box mesh: cell volume shares against analytic
// volumes, open face areas against the cross-section, the masked mesh's
// numbering, and the whole box giving today's mesh bit for bit.
#include "base/collective.hpp"
#include "builders/particles/particle_builder.hpp"
#include "check.hpp"
#include "mesh/box_mesh.hpp"
#include "mesh/vessel_mesh.hpp"

#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>

using namespace rcfd;

namespace {

const double kPi = 3.14159265358979323846;

// The public calls, thrown on failure (the test checks their sentences as exceptions).
void addShape(Vessel &v, Vessel::Kind kind, std::vector<double> p, bool subtract = false) {
  throwOnError([&] { return v.add(kind, std::move(p), subtract); });
}
VesselCut cutOf(const Vessel &v, const BoxSpec &box) {
  VesselCut cut;
  throwOnError([&] { return cutVessel(v, box, &cut); });
  return cut;
}

// Area of the disk (centre cx, cy, radius R) inside [x0, x1] x [y0, y1], by a
// fine midpoint rule over x of the exact chord overlap (error ~1e-9 of a cell).
double diskInRectangle(double cx, double cy, double R, double x0, double x1, double y0, double y1) {
  const int n = 4000;
  double area = 0.0;
  for (int s = 0; s < n; ++s) {
    const double x = x0 + (s + 0.5) / n * (x1 - x0) - cx;
    if (std::fabs(x) >= R) continue;
    const double half = std::sqrt(R * R - x * x);
    const double lo = std::fmax(y0, cy - half), hi = std::fmin(y1, cy + half);
    if (hi > lo) area += (hi - lo) * (x1 - x0) / n;
  }
  return area;
}

bool sameMesh(const Mesh &a, const Mesh &b) {
  return a.cellCentre == b.cellCentre && a.cellVolume == b.cellVolume && a.faceOwner == b.faceOwner &&
         a.faceNeighbour == b.faceNeighbour && a.faceArea == b.faceArea && a.boundaryOwner == b.boundaryOwner &&
         a.boundaryPatch == b.boundaryPatch && a.boundaryArea == b.boundaryArea && a.isBox() == b.isBox();
}

// The particle builder in a cylinder: particles turning rigidly about the axis
// stay inside, so every shift moves mass exactly (T m_k = m_{k+1}), every frame is on the
// cylinder's cells with alpha_s over their inside volumes, and a particle in a
// box corner outside the cylinder is outside the mesh in every snapshot.
void particlesInCylinder(ParticleVolume rule) {
  BoxSpec box;
  box.nx = box.ny = 10;
  box.nz = 4;
  box.length = {0.1, 0.1, 0.04};
  Vessel cylinder;
  addShape(cylinder, Vessel::Kind::Cylinder, {0.05, 0.05, 0.048});
  const Mesh mesh = cutVesselMesh(cylinder, box);
  ParticleBuildOptions opt;
  opt.mesh = box;
  opt.vessel = &mesh;
  opt.volume = rule;
  std::vector<CsrMatrix> shifts;
  std::vector<std::vector<double>> alphas;
  ParticleFrameBuilder builder(opt, [&](const FrameRecord &f) {
    shifts.push_back(f.shift);
    alphas.push_back(f.alphaS);
  });
  const double d = 0.003, rho = 1500.0, volume = kPi / 6 * d * d * d;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int n = 400;
  std::vector<double> radius(n), angle(n), height(n);
  for (int p = 0; p < n; ++p) {
    radius[p] = 0.046 * std::sqrt(u(rng)); // the sphere inside the wall
    angle[p] = 2 * kPi * u(rng);
    height[p] = 0.002 + 0.036 * u(rng);
  }
  std::vector<std::vector<double>> massOf;
  for (int k = 0; k < 5; ++k) {
    ParticleSnapshot snap;
    snap.timestep = k;
    snap.source = "turning cloud";
    std::vector<double> mass(mesh.numCells(), 0.0);
    for (int p = 0; p <= n; ++p) {
      const double a = angle[p % n] + 0.4 * k; // about 2 cells at the wall per snapshot
      const Vec3 x = p < n ? Vec3{0.05 + radius[p] * std::cos(a), 0.05 + radius[p] * std::sin(a), height[p]}
                           : Vec3{0.002, 0.002, 0.02}; // the corner: outside the cylinder
      snap.id.push_back(p);
      snap.type.push_back(1);
      snap.position.push_back(x);
      snap.diameter.push_back(d);
      snap.mass.push_back(rho * volume);
      if (p < n && rule == ParticleVolume::Centre) mass[mesh.cellOfBoxCell(box.locate(x))] += rho * volume;
    }
    massOf.push_back(mass);
    builder.add(snap);
  }
  const ParticleBuildReport &r = builder.report();
  RCFD_CHECK(r.cells == mesh.numCells() && mesh.numCells() < box.numCells());
  RCFD_CHECK(r.outside == 5 && r.maxOutsidePerSnapshot == 1); // the corner particle, every snapshot
  std::printf("particles in a cylinder (%s): mass residual %.3g kg, alpha residual %.3g\n", particleVolumeName(rule),
              r.maxMassResidual, r.maxAlphaResidual);
  // T moves mass exactly; alpha_s only where the cells have one volume (a cut
  // cell's column shares its mass, so T alpha_k != alpha_k+1 there).
  RCFD_CHECK(r.maxMassResidual < 1e-12 * rho * volume);
  RCFD_CHECK(r.maxAlphaResidual > 1e-3);
  RCFD_CHECK(shifts.size() == 4);
  for (std::size_t k = 0; k < alphas.size(); ++k) {
    RCFD_CHECK(alphas[k].size() == static_cast<std::size_t>(mesh.numCells()));
    double solid = 0.0, moved = 0.0;
    for (int c = 0; c < mesh.numCells(); ++c) {
      solid += alphas[k][c] * mesh.cellVolume[c];
      if (rule == ParticleVolume::Centre)
        RCFD_CHECK_CLOSE(alphas[k][c] * mesh.cellVolume[c] * rho, massOf[k][c], 1e-12);
    }
    for (std::size_t e = 0; e < shifts[k].val.size(); ++e) moved += shifts[k].val[e] < 1.0;
    RCFD_CHECK_CLOSE(solid / (n * volume), 1.0, 1e-12); // real volumes: the particles' volume, all inside
    RCFD_CHECK(moved > 20); // the cloud turns: many cells pass solid on
  }
}

} // namespace

int main(int argc, char **argv) {
  if (PetscInitialize(&argc, &argv, nullptr, nullptr)) return 1;
  BoxSpec box;
  box.nx = 20;
  box.ny = 20;
  box.nz = 6;
  box.origin = {-0.1, -0.1, 0.0};
  box.length = {0.2, 0.2, 0.12};
  const Vec3 h = box.spacing();
  const double V = h[0] * h[1] * h[2];

  // A vertical cylinder: every cell's share against the exact disk-rectangle area.
  const double R = 0.083;
  Vessel cylinder;
  addShape(cylinder, Vessel::Kind::Cylinder, {0.0, 0.0, R});
  const int n = cylinder.samples();
  const VesselCut cut = cutOf(cylinder, box);
  double volume = 0.0, worstCell = 0.0;
  int cutCells = 0;
  for (int j = 0; j < box.ny; ++j)
    for (int i = 0; i < box.nx; ++i) {
      const double x0 = box.origin[0] + i * h[0], y0 = box.origin[1] + j * h[1];
      const double exact = diskInRectangle(0.0, 0.0, R, x0, x0 + h[0], y0, y0 + h[1]) / (h[0] * h[1]);
      for (int k = 0; k < box.nz; ++k) {
        const double share = cut.cellShare[box.cellIndex(i, j, k)];
        if (share > 0 && share < 1) ++cutCells;
        worstCell = std::fmax(worstCell, std::fabs(share - exact));
        volume += share * V;
      }
    }
  const double cylinderVolume = kPi * R * R * box.length[2];
  std::printf("cylinder: %d cut cells, worst cell share error %.4f (n = %d), volume error %.2e\n",
              cutCells, worstCell, n, std::fabs(volume / cylinderVolume - 1));
  RCFD_CHECK(cutCells > 0);
  RCFD_CHECK(worstCell <= 0.01);                                 // the stated per-cell accuracy at n = 8
  RCFD_CHECK_CLOSE(volume / cylinderVolume, 1.0, 5e-4);          // the stated total accuracy

  // Open faces of the cylinder: at every height the horizontal faces' open areas
  // sum to the cross-section, and each equals its cells' share (a vertical wall).
  const Mesh mesh = cutVesselMesh(cylinder, box);
  RCFD_CHECK(mesh.isMasked() && !mesh.isBox() && mesh.onBoxLattice());
  std::vector<double> perPlane(box.nz + 1, 0.0);
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const Vec3 &S = mesh.faceArea[f];
    if (S[2] == 0.0) continue;
    const int o = mesh.faceOwner[f], b = mesh.boxCell(o);
    perPlane[b / (box.nx * box.ny) + 1] += S[2];
    RCFD_CHECK_CLOSE(S[2] * h[2] / mesh.cellVolume[o], 1.0, 1e-13); // the same sub-sample columns
  }
  for (int f = 0; f < mesh.numBoundaryFaces(); ++f)
    if (mesh.boundaryPatch[f] == 4) perPlane[0] -= mesh.boundaryArea[f][2];
    else if (mesh.boundaryPatch[f] == 5) perPlane[box.nz] += mesh.boundaryArea[f][2];
  for (int p = 0; p <= box.nz; ++p) RCFD_CHECK_CLOSE(perPlane[p] / (kPi * R * R), 1.0, 5e-4);
  for (int p = 1; p <= box.nz; ++p) RCFD_CHECK_CLOSE(perPlane[p] / perPlane[0], 1.0, 1e-13);

  // The masked mesh: compact numbering in box order, maps both ways, real volumes.
  int inside = 0;
  for (int b = 0; b < box.numCells(); ++b) inside += cut.cellShare[b] > 0;
  RCFD_CHECK(mesh.numCells() == inside);
  RCFD_CHECK(inside < box.numCells());
  for (int c = 0; c < mesh.numCells(); ++c) {
    RCFD_CHECK(mesh.cellOfBoxCell(mesh.boxCell(c)) == c);
    if (c > 0) RCFD_CHECK(mesh.boxCell(c) > mesh.boxCell(c - 1));
  }
  for (int b = 0; b < box.numCells(); ++b)
    RCFD_CHECK((mesh.cellOfBoxCell(b) >= 0) == (cut.cellShare[b] > 0));
  RCFD_CHECK_CLOSE(mesh.totalVolume(), volume, 1e-14);
  for (int f = 0; f < mesh.numFaces(); ++f) {
    RCFD_CHECK(mesh.faceOwner[f] >= 0 && mesh.faceOwner[f] < mesh.numCells());
    RCFD_CHECK(mesh.faceNeighbour[f] >= 0 && mesh.faceNeighbour[f] < mesh.numCells());
  }
  // No face to a cell outside, and none across the wall between two cells that
  // touch only outside: a face of the box between two inside cells whose
  // open share is 0 is missing.
  RCFD_CHECK(mesh.vessel() == cylinder.describe());

  // A cone (frustum) against its analytic volume.
  Vessel cone;
  const double r0 = 0.03, r1 = 0.09, z0 = 0.01, z1 = 0.11;
  addShape(cone, Vessel::Kind::Cone, {0.0, 0.0, z0, r0, z1, r1});
  const VesselCut coneCut = cutOf(cone, box);
  double coneVolume = 0.0;
  for (double s : coneCut.cellShare) coneVolume += s * V;
  const double exactCone = kPi * (z1 - z0) / 3.0 * (r0 * r0 + r0 * r1 + r1 * r1);
  std::printf("cone: volume error %.2e\n", std::fabs(coneVolume / exactCone - 1));
  RCFD_CHECK_CLOSE(coneVolume / exactCone, 1.0, 5e-4);

  // A tube bank: the box minus two horizontal tubes along y.
  Vessel bank;
  addShape(bank, Vessel::Kind::Box, {-1, 1, -1, 1, -1, 1});
  addShape(bank, Vessel::Kind::TubeY, {-0.045, 0.06, 0.03}, true);
  addShape(bank, Vessel::Kind::TubeY, {0.045, 0.06, 0.03}, true);
  const Mesh bankMesh = cutVesselMesh(bank, box);
  const double bankExact = 0.2 * 0.2 * 0.12 - 2 * kPi * 0.03 * 0.03 * 0.2;
  std::printf("tube bank: volume error %.2e, %d of %d cells\n", std::fabs(bankMesh.totalVolume() / bankExact - 1),
              bankMesh.numCells(), box.numCells());
  RCFD_CHECK_CLOSE(bankMesh.totalVolume() / bankExact, 1.0, 5e-4);
  RCFD_CHECK(bankMesh.numCells() < box.numCells());

  // A box minus a vertical tube (a draft tube's wall, an internal): the box's volume less the tube's,
  // and no face across the tube (its inside cells are gone).
  Vessel drafted;
  addShape(drafted, Vessel::Kind::Box, {-1, 1, -1, 1, -1, 1});
  addShape(drafted, Vessel::Kind::Cylinder, {0.0, 0.0, 0.035, 0.02, 0.1}, true);
  const Mesh draftedMesh = cutVesselMesh(drafted, box);
  const double draftedExact = 0.2 * 0.2 * 0.12 - kPi * 0.035 * 0.035 * 0.08;
  std::printf("box minus a vertical tube: volume error %.2e\n", std::fabs(draftedMesh.totalVolume() / draftedExact - 1));
  RCFD_CHECK_CLOSE(draftedMesh.totalVolume() / draftedExact, 1.0, 5e-4);
  RCFD_CHECK(draftedMesh.cellOfBoxCell(box.cellIndex(10, 10, 2)) < 0); // the tube's axis at z = 0.05 m

  // The whole box, as no shape or as a shape holding the box: today's mesh, bit for bit.
  RCFD_CHECK(sameMesh(cutVesselMesh(Vessel(), box), boxMesh(box)));
  Vessel around;
  addShape(around, Vessel::Kind::Box, {-0.1, 0.1, -0.1, 0.1, 0.0, 0.12}); // the box's own walls
  RCFD_CHECK(sameMesh(cutVesselMesh(around, box), boxMesh(box)));
  RCFD_CHECK(cutVesselMesh(Vessel(), box).vessel() == "box");

  // The recorded line names the vessel exactly.
  RCFD_CHECK(parseVessel(bank.describe()) == bank);
  RCFD_CHECK(parseVessel(cone.describe()).describe() == cone.describe());
  RCFD_CHECK(parseVessel("box").isWholeBox());
  RCFD_CHECK(bank != cylinder);
  RCFD_CHECK(rcfd::test::throwsWith([] { parseVessel("+sphere(1,2,3) samples 8"); }, "unknown vessel shape"));
  RCFD_CHECK(rcfd::test::throwsWith([] { Vessel v; addShape(v, Vessel::Kind::Cylinder, {0, 0, -1}); }, "positive radius"));
  RCFD_CHECK(rcfd::test::throwsWith([] { Vessel v; addShape(v, Vessel::Kind::Cone, {0, 0, 1, 1, 0, 1}); }, "low below high"));
  RCFD_CHECK(rcfd::test::throwsWith([] { Vessel v; addShape(v, Vessel::Kind::TubeX, {0, 0, 1}, true); }, "cannot start"));
  RCFD_CHECK(rcfd::test::throwsWith(
      [&] {
        Vessel v;
        addShape(v, Vessel::Kind::Cylinder, {5.0, 5.0, 0.1});
        cutVesselMesh(v, box);
      },
      "holds no cell"));
  particlesInCylinder(ParticleVolume::Centre);
  particlesInCylinder(ParticleVolume::Overlap);
  if (PetscFinalize()) return 1;
  return RCFD_TEST_RESULT();
}
