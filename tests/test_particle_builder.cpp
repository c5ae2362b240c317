// Database frames and reference answers from particle snapshots: a known
// shift matrix, vanished / appeared / escaping particles, the exact identity
// T_k alpha_k = alpha_{k+1} on a random cloud (and T_k m_k = m_{k+1} with
// two densities), file-driven builds with stride and window, and a
// hand-computed centre of gravity.
#include "check.hpp"
#include "builders/particles/particle_builder.hpp"
#include "analysis/particle_reference.hpp"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

using namespace rcfd;

namespace {

constexpr double kPi = 3.14159265358979323846;

double sphereVolume(double d) { return kPi / 6.0 * d * d * d; }

struct P {
  int64_t id;
  Vec3 x;
  double d, rho;
};

ParticleSnapshot snapshot(const std::vector<P> &ps, int64_t timestep) {
  ParticleSnapshot s;
  s.source = "memory:" + std::to_string(timestep);
  s.timestep = timestep;
  for (const P &p : ps) {
    s.id.push_back(p.id);
    s.type.push_back(1);
    s.position.push_back(p.x);
    s.diameter.push_back(p.d);
    s.mass.push_back(p.rho * sphereVolume(p.d));
  }
  return s;
}

/// Dense copy of a CSR matrix, [row][col].
std::vector<std::vector<double>> dense(const CsrMatrix &T) {
  std::vector<std::vector<double>> A(T.n, std::vector<double>(T.n, 0.0));
  for (int r = 0; r < T.n; ++r)
    for (int64_t e = T.rowPtr[r]; e < T.rowPtr[r + 1]; ++e) A[r][T.col[e]] += T.val[e];
  return A;
}

std::vector<double> times(const CsrMatrix &T, const std::vector<double> &x) {
  std::vector<double> y(T.n, 0.0);
  for (int r = 0; r < T.n; ++r)
    for (int64_t e = T.rowPtr[r]; e < T.rowPtr[r + 1]; ++e) y[r] += T.val[e] * x[T.col[e]];
  return y;
}

double maxColumnSumError(const CsrMatrix &T) {
  std::vector<double> sum(T.n, 0.0);
  for (std::size_t e = 0; e < T.val.size(); ++e) sum[T.col[e]] += T.val[e];
  double err = 0.0;
  for (double s : sum) err = std::fmax(err, std::fabs(s - 1.0));
  return err;
}

/// Unit cells: 2 x 1 x 2 cells over [0,2] x [0,1] x [0,2].
/// Cell index i + 2 k: 0 = (0,0), 1 = (1,0), 2 = (0,1), 3 = (1,1).
BoxSpec smallBox() {
  BoxSpec b;
  b.nx = 2;
  b.ny = 1;
  b.nz = 2;
  b.origin = {0.0, 0.0, 0.0};
  b.length = {2.0, 1.0, 2.0};
  return b;
}

void testKnownMatrix() {
  ParticleBuildOptions opt;
  opt.volume = ParticleVolume::Centre; // hand-computed for whole particles
  opt.mesh = smallBox();
  std::vector<FrameRecord> frames;
  ParticleFrameBuilder b(opt, [&](const FrameRecord &f) { frames.push_back(f); });
  // A: cell 0 -> cell 3; B: stays in cell 0, twice A's mass; C: cell 1 -> cell 2.
  const double dA = 0.2, dB = 0.2, dC = 0.3;
  b.add(snapshot({{1, {0.5, 0.5, 0.5}, dA, 1000.0},
                  {2, {0.2, 0.3, 0.4}, dB, 2000.0},
                  {3, {1.5, 0.5, 0.5}, dC, 1000.0}},
                 0));
  b.add(snapshot({{1, {1.5, 0.5, 1.5}, dA, 1000.0},
                  {2, {0.6, 0.7, 0.8}, dB, 2000.0},
                  {3, {0.5, 0.5, 1.5}, dC, 1000.0}},
                 10));
  RCFD_CHECK(frames.size() == 1);
  if (frames.empty()) return;
  const auto A = dense(frames[0].shift);
  const double expected[4][4] = {
      {2.0 / 3.0, 0, 0, 0}, {0, 0, 0, 0}, {0, 1, 1, 0}, {1.0 / 3.0, 0, 0, 1}};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) RCFD_CHECK_CLOSE(A[r][c], expected[r][c], 1e-15);
  // alpha_s of frame 0 is at t_0: cells are 1 m^3.
  RCFD_CHECK_CLOSE(frames[0].alphaS[0], sphereVolume(dA) + sphereVolume(dB), 1e-15);
  RCFD_CHECK_CLOSE(frames[0].alphaS[1], sphereVolume(dC), 1e-15);
  RCFD_CHECK(frames[0].alphaS[2] == 0.0 && frames[0].alphaS[3] == 0.0);
  const ParticleBuildReport &r = b.report();
  RCFD_CHECK(r.snapshots == 2 && r.frames == 1 && r.cells == 4 && r.particles == 3);
  RCFD_CHECK(r.maxNnzPerColumn == 2);
  RCFD_CHECK_CLOSE(r.meanNnzPerColumn, 5.0 / 4.0, 1e-15);         // columns 0..3: 2, 1, 1, 1
  RCFD_CHECK_CLOSE(r.meanNnzPerOccupiedColumn, 3.0 / 2.0, 1e-15); // columns 0, 1
  RCFD_CHECK(r.appeared == 0 && r.vanished == 0 && r.outside == 0);
  // Two densities, but A and B share a cell and go different ways, so the
  // mass shift is exact while the volume identity is not.
  RCFD_CHECK(r.maxMassResidual < 1e-15);
  RCFD_CHECK(r.maxAlphaResidual > 1e-4);
}

void testVanishedAppearedOutside() {
  ParticleBuildOptions opt;
  opt.volume = ParticleVolume::Centre; // hand-computed for whole particles
  opt.mesh = smallBox();
  std::vector<FrameRecord> frames;
  ParticleFrameBuilder b(opt, [&](const FrameRecord &f) { frames.push_back(f); });
  const double d = 0.1, rho = 1000.0, m = rho * sphereVolume(d);
  b.add(snapshot({{1, {0.5, 0.5, 0.5}, d, rho},
                  {2, {0.5, 0.5, 0.6}, d, rho},
                  {3, {1.5, 0.5, 0.5}, d, rho},
                  {4, {1.5, 0.5, 1.5}, d, rho},
                  {5, {3.0, 0.5, 0.5}, d, rho}},
                 0));
  // 2 vanishes from cell 0; 1 moves to cell 1; 3 leaves the mesh; 5 enters
  // cell 3; 6 appears in cell 2; 4 stays.
  b.add(snapshot({{1, {1.5, 0.5, 0.5}, d, rho},
                  {3, {1.5, 0.5, 2.5}, d, rho},
                  {4, {1.5, 0.5, 1.5}, d, rho},
                  {5, {1.5, 0.5, 1.2}, d, rho},
                  {6, {0.5, 0.5, 1.5}, d, rho}},
                 1));
  const ParticleBuildReport &r = b.report();
  RCFD_CHECK(r.vanished == 1 && r.appeared == 1 && r.leftMesh == 1 && r.enteredMesh == 1);
  RCFD_CHECK_CLOSE(r.vanishedMass, m, 1e-15);
  RCFD_CHECK_CLOSE(r.appearedMass, m, 1e-15);
  RCFD_CHECK_CLOSE(r.leftMeshMass, m, 1e-15);
  RCFD_CHECK_CLOSE(r.enteredMeshMass, m, 1e-15);
  RCFD_CHECK(r.outside == 2 && r.maxOutsidePerSnapshot == 1);
  if (frames.size() != 1) {
    RCFD_CHECK(frames.size() == 1);
    return;
  }
  RCFD_CHECK(maxColumnSumError(frames[0].shift) < 1e-15);
  const auto A = dense(frames[0].shift);
  // Cell 0: particle 1 (to cell 1) and the vanished 2 (kept in cell 0).
  RCFD_CHECK_CLOSE(A[1][0], 0.5, 1e-15);
  RCFD_CHECK_CLOSE(A[0][0], 0.5, 1e-15);
  // Cell 1: particle 3 left the mesh and is kept in cell 1.
  RCFD_CHECK_CLOSE(A[1][1], 1.0, 1e-15);
  RCFD_CHECK_CLOSE(A[3][3], 1.0, 1e-15);
  // The residual shows exactly the kept volume (cell 0: one particle too
  // many; cells 2 and 3: appeared / entered particles missing).
  RCFD_CHECK_CLOSE(r.maxAlphaResidual, sphereVolume(d), 1e-12);
}

void testErrorsAndAxes() {
  ParticleBuildOptions opt;
  opt.volume = ParticleVolume::Centre; // hand-computed for whole particles
  opt.mesh = smallBox();
  ParticleFrameBuilder b(opt, nullptr);
  bool threw = false;
  try {
    b.add(snapshot({{1, {0.5, 0.5, 0.5}, 0.1, 1.0}, {1, {1.5, 0.5, 0.5}, 0.1, 1.0}}, 0));
  } catch (const std::runtime_error &e) {
    threw = std::string(e.what()).find("lists particle id 1 more than once") != std::string::npos;
  }
  RCFD_CHECK(threw);
  ParticleFrameBuilder order(opt, nullptr);
  order.add(snapshot({{1, {0.5, 0.5, 0.5}, 0.1, 1.0}}, 5));
  threw = false;
  try {
    order.add(snapshot({{1, {0.5, 0.5, 0.5}, 0.1, 1.0}}, 5));
  } catch (const std::runtime_error &e) {
    threw = std::string(e.what()).find("time order") != std::string::npos;
  }
  RCFD_CHECK(threw);

  // File axes with y up: file (x, y, z) -> rcfd (z, x, y).
  opt.axes = AxisMap::verticalUp(1, -1);
  std::vector<FrameRecord> frames;
  ParticleFrameBuilder yUp(opt, [&](const FrameRecord &f) { frames.push_back(f); });
  // rcfd (1.5, 0.5, 0.5): cell 1, then rcfd (0.5, 0.5, 1.5): cell 2.
  yUp.add(snapshot({{9, {0.5, 0.5, 1.5}, 0.1, 1.0}}, 0));
  yUp.add(snapshot({{9, {0.5, 1.5, 0.5}, 0.1, 1.0}}, 1));
  RCFD_CHECK(frames.size() == 1 && frames[0].alphaS[1] > 0.0);
  if (!frames.empty()) RCFD_CHECK_CLOSE(dense(frames[0].shift)[2][1], 1.0, 1e-15);
}

/// Random cloud moving by random steps inside a 6 x 3 x 8 box; one or two
/// densities.  Checks the identity on every frame, computing alpha and the
/// cell masses of the last snapshot independently.
void testRandomCloud(bool twoDensities) {
  BoxSpec box;
  box.nx = 6;
  box.ny = 3;
  box.nz = 8;
  box.origin = {-0.03, -0.006, 0.0};
  box.length = {0.06, 0.012, 0.08};
  const Vec3 h = box.spacing();
  const double cellVolume = h[0] * h[1] * h[2];
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<P> cloud;
  for (int i = 0; i < 3000; ++i) {
    const bool large = i % 3 == 0;
    cloud.push_back(
        {1000 + 7 * i,
         {box.origin[0] + u(rng) * box.length[0], box.origin[1] + u(rng) * box.length[1],
          box.origin[2] + u(rng) * box.length[2]},
         large ? 0.0028 : 0.00195,
         twoDensities && large ? 2500.0 : 1440.0});
  }
  ParticleBuildOptions opt;
  opt.mesh = box;
  opt.volume = ParticleVolume::Centre; // alphaOf below counts by centre
  std::vector<double> alphaPrev, massPrev;
  std::vector<CsrMatrix> shifts;
  std::vector<std::vector<double>> alphas;
  ParticleFrameBuilder b(opt, [&](const FrameRecord &f) {
    shifts.push_back(f.shift);
    alphas.push_back(f.alphaS);
  });
  const std::size_t snapshots = 5;
  std::vector<std::vector<double>> massOf(snapshots), alphaOf(snapshots);
  for (std::size_t k = 0; k < snapshots; ++k) {
    // Shuffle the order in the file: matching must go by id, not position.
    std::shuffle(cloud.begin(), cloud.end(), rng);
    b.add(snapshot(cloud, static_cast<int64_t>(k)));
    massOf[k].assign(box.numCells(), 0.0);
    alphaOf[k].assign(box.numCells(), 0.0);
    for (const P &p : cloud) {
      const int c = box.locate(p.x);
      massOf[k][c] += p.rho * sphereVolume(p.d);
      alphaOf[k][c] += sphereVolume(p.d) / cellVolume;
    }
    for (P &p : cloud) // steps up to about 1.5 cells, reflected at the walls
      for (int a = 0; a < 3; ++a) {
        double x = p.x[a] + (u(rng) - 0.5) * 3.0 * h[a];
        const double lo = box.origin[a], hi = box.origin[a] + box.length[a];
        if (x < lo) x = 2 * lo - x;
        if (x > hi) x = 2 * hi - x;
        p.x[a] = x;
      }
  }
  const ParticleBuildReport &r = b.report();
  RCFD_CHECK(shifts.size() == snapshots - 1 && r.frames == snapshots - 1);
  RCFD_CHECK(r.outside == 0 && r.vanished == 0 && r.appeared == 0);
  RCFD_CHECK(r.maxNnzPerColumn > 5);
  double alphaResidual = 0.0, massResidual = 0.0, maxMass = 0.0;
  for (std::size_t k = 0; k < shifts.size(); ++k) {
    RCFD_CHECK(maxColumnSumError(shifts[k]) < 1e-14);
    for (int c = 0; c < box.numCells(); ++c) RCFD_CHECK_CLOSE(alphas[k][c], alphaOf[k][c], 1e-13);
    const auto ta = times(shifts[k], alphaOf[k]);
    const auto tm = times(shifts[k], massOf[k]);
    for (int c = 0; c < box.numCells(); ++c) {
      alphaResidual = std::fmax(alphaResidual, std::fabs(ta[c] - alphaOf[k + 1][c]));
      massResidual = std::fmax(massResidual, std::fabs(tm[c] - massOf[k + 1][c]));
      maxMass = std::fmax(maxMass, massOf[k + 1][c]);
    }
  }
  // Mass is always shifted exactly; the volume fraction only when all
  // particles have one density.
  RCFD_CHECK(massResidual <= 1e-13 * maxMass);
  RCFD_CHECK(r.maxMassResidual <= 1e-13 * maxMass);
  if (twoDensities) {
    RCFD_CHECK(alphaResidual > 1e-3);
    RCFD_CHECK(r.maxAlphaResidual > 1e-3);
  } else {
    RCFD_CHECK(alphaResidual < 1e-13);
    RCFD_CHECK(r.maxAlphaResidual < 1e-13);
  }
  RCFD_CHECK_CLOSE(r.maxAlphaResidual, alphaResidual, 1e-12);
}

// ------------------------------------------------------------ file-driven

void writeDumpGz(const std::string &path, int64_t timestep, const std::vector<P> &ps) {
  std::string s = "ITEM: TIMESTEP\n" + std::to_string(timestep) + "\nITEM: NUMBER OF ATOMS\n" +
                  std::to_string(ps.size()) +
                  "\nITEM: BOX BOUNDS ff ff ff\n0 2\n0 1\n0 2\nITEM: ATOMS x id z y radius type\n";
  char line[256];
  for (const P &p : ps) {
    std::snprintf(line, sizeof line, "%.17g %lld %.17g %.17g %.17g 1\n", p.x[0],
                  static_cast<long long>(p.id), p.x[2], p.x[1], p.d / 2);
    s += line;
  }
  gzFile f = gzopen(path.c_str(), "wb");
  gzwrite(f, s.data(), static_cast<unsigned>(s.size()));
  gzclose(f);
}

void testFromFiles(const std::string &dir) {
  // Snapshot s holds one particle in cell s % 4 (cells 0, 1, 2, 3, 0, ...).
  const Vec3 centre[4] = {{0.5, 0.5, 0.5}, {1.5, 0.5, 0.5}, {0.5, 0.5, 1.5}, {1.5, 0.5, 1.5}};
  std::vector<std::string> files;
  for (int s = 0; s < 7; ++s) {
    files.push_back(dir + "/dump." + std::to_string(s) + ".gz");
    writeDumpGz(files.back(), 100 * s, {{42, centre[s % 4], 0.1, 0.0}});
  }
  ParticleBuildOptions opt;
  opt.volume = ParticleVolume::Centre;
  opt.mesh = smallBox();
  opt.read.defaultDensity = 1440.0;
  opt.stride = 2;
  opt.first = 1;
  opt.last = 5;
  const std::vector<std::size_t> sel = selectSnapshots(files.size(), opt);
  RCFD_CHECK((sel == std::vector<std::size_t>{1, 3, 5}));
  std::vector<FrameRecord> frames;
  const ParticleBuildReport r =
      buildFramesFromSnapshots(files, opt, [&](const FrameRecord &f) { frames.push_back(f); });
  RCFD_CHECK(r.snapshots == 3 && r.frames == 2 && frames.size() == 2);
  if (frames.size() == 2) {
    RCFD_CHECK(frames[0].alphaS[1] > 0.0 && frames[1].alphaS[3] > 0.0);
    RCFD_CHECK_CLOSE(dense(frames[0].shift)[3][1], 1.0, 1e-15); // snapshot 1 -> 3
    RCFD_CHECK_CLOSE(dense(frames[1].shift)[1][3], 1.0, 1e-15); // snapshot 3 -> 5
  }
  RCFD_CHECK(r.maxAlphaResidual < 1e-15);
  opt.first = 6;
  opt.last = 100; // clipped to the last file: one snapshot only
  bool threw = false;
  try {
    buildFramesFromSnapshots(files, opt, nullptr);
  } catch (const std::invalid_argument &e) {
    threw = std::string(e.what()).find("a frame needs two") != std::string::npos;
  }
  RCFD_CHECK(threw);
}

// ------------------------------------------------------------ reference

void testReference(const std::string &dir) {
  // Small: 1 mm at z = 0.1 and 0.4 m; large: 2 mm (8 times the mass) at 0.2 m.
  //   z_bed = (0.1 + 0.4 + 8 * 0.2) / 10 = 0.21, z_small = 0.25, z_large = 0.2,
  //   delta_z = 0.05.  Mass median: cumulative mass from below reaches half
  //   at the large particle, z_med = 0.2; bottom = {small at 0.1, large}.
  const double rho = 1000.0;
  const std::vector<P> ps = {{1, {0.0, 0.0, 0.1}, 0.001, rho},
                             {2, {0.0, 0.0, 0.4}, 0.001, rho},
                             {3, {0.0, 0.0, 0.2}, 0.002, rho}};
  BoxSpec layers;
  layers.nx = 1;
  layers.ny = 1;
  layers.nz = 4;
  layers.origin = {-0.5, -0.5, 0.0};
  layers.length = {1.0, 1.0, 0.4};
  ReferenceOptions opt;
  opt.volume = ParticleVolume::Centre; // whole particles in their centre's layer
  opt.profileMesh = layers;
  opt.windowBegin = 0.0;
  opt.windowEnd = 1.0;
  ParticleReference ref(opt);
  ref.add(0.5, snapshot(ps, 0));
  // Outside the window: everything 0.1 m higher.
  std::vector<P> higher = ps;
  for (P &p : higher) p.x[2] += 0.1;
  ref.add(2.0, snapshot(higher, 1));

  RCFD_CHECK(ref.classes().diameter.size() == 2);
  RCFD_CHECK(ref.classes().label(0) == "d1.000mm" && ref.classes().label(1) == "d2.000mm");
  RCFD_CHECK(ref.series().size() == 2 && ref.windowSnapshots() == 1);
  const CogSample &s = ref.series()[0];
  RCFD_CHECK_CLOSE(s.zBed, 0.21, 1e-14);
  RCFD_CHECK_CLOSE(s.zClass[0], 0.25, 1e-14);
  RCFD_CHECK_CLOSE(s.zClass[1], 0.2, 1e-14);
  RCFD_CHECK_CLOSE(ref.deltaZ(s), 0.05, 1e-14);
  RCFD_CHECK_CLOSE(s.zMedian, 0.2, 1e-15);
  RCFD_CHECK_CLOSE(s.lowerShare[0], 0.5, 1e-15);
  RCFD_CHECK_CLOSE(s.lowerShare[1], 1.0, 1e-15);
  RCFD_CHECK_CLOSE(ref.series()[1].zBed, 0.31, 1e-14);

  const auto halves = ref.halves();
  RCFD_CHECK_CLOSE(halves.bottom[0], 1.0 / 9.0, 1e-15);
  RCFD_CHECK_CLOSE(halves.bottom[1], 8.0 / 9.0, 1e-15);
  RCFD_CHECK_CLOSE(halves.top[0], 1.0, 1e-15);
  RCFD_CHECK_CLOSE(halves.top[1], 0.0, 1e-15);

  // Layers 0.1 m thick, 1 m^2: z = 0.1 is in layer 1, 0.2 in layer 2,
  // 0.4 (the top face) in layer 3.
  const auto prof = ref.profiles();
  const double layerVolume = 0.1;
  RCFD_CHECK_CLOSE(prof[0][1], sphereVolume(0.001) / layerVolume, 1e-15);
  RCFD_CHECK_CLOSE(prof[0][3], sphereVolume(0.001) / layerVolume, 1e-15);
  RCFD_CHECK_CLOSE(prof[1][2], sphereVolume(0.002) / layerVolume, 1e-15);
  RCFD_CHECK(prof[0][0] == 0.0 && prof[1][1] == 0.0);

  // The CSV: rcfd run's header (SI units in the names), one row per snapshot.
  const std::string csv = dir + "/cog.csv";
  ref.writeCogCsv(csv);
  std::ifstream in(csv);
  std::string header, row;
  std::getline(in, header);
  std::getline(in, row);
  RCFD_CHECK(header == "time_s,z_cog_bed_m,z_cog_d1.000mm_m,z_cog_d2.000mm_m,delta_z_m");
  double v[5] = {0, 0, 0, 0, 0};
  RCFD_CHECK(std::sscanf(row.c_str(), "%lf,%lf,%lf,%lf,%lf", v, v + 1, v + 2, v + 3, v + 4) == 5);
  RCFD_CHECK_CLOSE(v[0], 0.5, 1e-12);
  RCFD_CHECK_CLOSE(v[1], 0.21, 1e-8);
  RCFD_CHECK_CLOSE(v[4], 0.05, 1e-8);
  ref.writeProfilesCsv(dir + "/profiles.csv");
  ref.writeHalvesCsv(dir + "/halves.csv");
  RCFD_CHECK(std::filesystem::file_size(dir + "/profiles.csv") > 0);

  // Given classes with a tolerance: a 1.5 mm particle fits neither.
  ReferenceOptions given;
  given.classes.diameter = {0.002, 0.001};
  given.classes.relTol = 0.02;
  ParticleReference strict(given);
  strict.add(0.0, snapshot({{1, {0, 0, 0.1}, 0.00101, rho}, {2, {0, 0, 0.2}, 0.00199, rho}}, 0));
  RCFD_CHECK(strict.classes().diameter[0] == 0.001); // sorted
  bool threw = false;
  try {
    strict.add(1.0, snapshot({{7, {0, 0, 0.1}, 0.0015, rho}}, 1));
  } catch (const std::runtime_error &e) {
    threw = std::string(e.what()).find("particle id 7 has diameter 1.5000 mm") != std::string::npos;
  }
  RCFD_CHECK(threw);

  // Clustering: near-equal diameters join, distinct ones do not.
  const SizeClasses sc = SizeClasses::cluster({0.00195, 0.002, 0.001951, 0.00282, 0.00195}, 0.01);
  RCFD_CHECK(sc.diameter.size() == 3);
  RCFD_CHECK_CLOSE(sc.diameter[0], (2 * 0.00195 + 0.001951) / 3, 1e-15);
  RCFD_CHECK(sc.classOf(0.001952) == 0 && sc.classOf(0.00282) == 2 && sc.classOf(0.0025) == -1);
}

// ------------------------------------------------------------ overlap

/// Particles as large as the cells, counted by overlap, with shares worked
/// out by hand: A straddles the plane x = 1 exactly (halves), then the
/// corner of four cells... D sits 0.1 m before x = 1 with R = 0.2 m, so the
/// cap beyond the plane, of height 0.1, is pi t^2 (3R - t) / 3 = pi 0.005 / 3
/// of the sphere's pi 0.032 / 3: a share of 0.15625.  E pokes out of the
/// domain's wall x = 0 and has all its volume in cell 0.
void testOverlapByHand() {
  ParticleBuildOptions opt;
  opt.mesh = smallBox(); // 2 x 1 x 2 cells of 1 m^3: 0 (0,0,0), 1 (1,0,0), 2 (0,0,1), 3 (1,0,1)
  opt.volume = ParticleVolume::Overlap;
  std::vector<FrameRecord> frames;
  ParticleFrameBuilder b(opt, [&](const FrameRecord &f) { frames.push_back(f); });
  const double d = 0.4, rho = 1000.0, V = sphereVolume(d), m = rho * V, cap = 0.15625;
  b.add(snapshot({{1, {1.0, 0.5, 0.5}, d, rho}, {4, {0.9, 0.5, 0.5}, d, rho}}, 0));
  // t_1: A on the edge x = 1, z = 1 (a quarter in each cell), D as before,
  // E appears; t_2: E at the wall.
  b.add(snapshot({{1, {1.0, 0.5, 1.0}, d, rho}, {4, {0.9, 0.5, 0.5}, d, rho}}, 1));
  b.add(snapshot({{1, {1.0, 0.5, 1.0}, d, rho}, {4, {0.9, 0.5, 0.5}, d, rho},
                  {5, {0.05, 0.9, 1.5}, d, rho}},
                 2));
  RCFD_CHECK(frames.size() == 2);
  if (frames.size() != 2) return;
  RCFD_CHECK_CLOSE(frames[0].alphaS[0], V * (0.5 + 1.0 - cap), 1e-12 * V);
  RCFD_CHECK_CLOSE(frames[0].alphaS[1], V * (0.5 + cap), 1e-12 * V);
  RCFD_CHECK(frames[0].alphaS[2] == 0.0 && frames[0].alphaS[3] == 0.0);
  // Column i: D rests, so it stays; A keeps a quarter in cells 0 and 1 and
  // moves the other quarter of each to cells 2 and 3 in proportion (1/8 each).
  const double m0 = m * (0.5 + 1.0 - cap), m1 = m * (0.5 + cap);
  const double expected[4][2] = {{m * (0.25 + 1 - cap) / m0, 0.0},
                                 {0.0, m * (0.25 + cap) / m1},
                                 {m * 0.125 / m0, m * 0.125 / m1},
                                 {m * 0.125 / m0, m * 0.125 / m1}};
  const auto A = dense(frames[0].shift);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 2; ++c) RCFD_CHECK_CLOSE(A[r][c], expected[r][c], 1e-12);
  // The wall: all of E in cell 2 (its centre's cell), nothing lost.
  RCFD_CHECK_CLOSE(frames[1].alphaS[2], 0.25 * V, 1e-12 * V);
  RCFD_CHECK_CLOSE(frames[1].alphaS[3], 0.25 * V, 1e-12 * V);
  const ParticleBuildReport &r = b.report();
  RCFD_CHECK(r.maxNnzPerColumn == 3 && r.appeared == 1 && r.outside == 0);
  // T_0 alpha_0 = alpha_1 (E's appearance breaks it for T_1, as it should).
  const auto ta = times(frames[0].shift, frames[0].alphaS);
  for (int c = 0; c < 4; ++c) RCFD_CHECK_CLOSE(ta[c], frames[1].alphaS[c], 1e-15);

  std::vector<CellShare> shares;
  cellShares(opt.mesh, {0.05, 0.9, 1.5}, d, ParticleVolume::Overlap, shares);
  RCFD_CHECK(shares.size() == 1 && shares[0].cell == 2 && shares[0].share == 1.0);
  // Out of the wall x = 0 and across the plane z = 1: the part outside stays
  // with the cell nearest to it, so the cap beyond z = 1 keeps its share.
  cellShares(opt.mesh, {0.05, 0.5, 0.9}, d, ParticleVolume::Overlap, shares);
  RCFD_CHECK(shares.size() == 2 && shares[0].cell == 0 && shares[1].cell == 2);
  if (shares.size() == 2) RCFD_CHECK_CLOSE(shares[1].share, cap, 1e-12);
  // Out of the wall y = 0 and across x = 1 and z = 1 (four cells, general
  // path): the two cells above z = 1 still hold exactly the cap's share.
  cellShares(opt.mesh, {0.95, 0.05, 0.9}, d, ParticleVolume::Overlap, shares);
  double above = 0.0, all = 0.0;
  for (const CellShare &c : shares) {
    all += c.share;
    if (c.cell >= 2) above += c.share;
  }
  RCFD_CHECK(shares.size() == 4);
  RCFD_CHECK_CLOSE(above, cap, 1e-12);
  RCFD_CHECK_CLOSE(all, 1.0, 1e-15);
  cellShares(opt.mesh, {-0.05, 0.5, 0.5}, d, ParticleVolume::Overlap, shares);
  RCFD_CHECK(shares.empty()); // centre outside: in no cell, as under the centre rule
  RCFD_CHECK(parseParticleVolume("centre") == ParticleVolume::Centre);
  bool threw = false;
  try {
    parseParticleVolume("volume");
  } catch (const std::invalid_argument &) {
    threw = true;
  }
  RCFD_CHECK(threw);
}

/// Particles larger than the cells (3 mm in 2.4 mm cells), on a loose
/// lattice (3.6 mm apart, so they never overlap each other) that drifts and
/// jitters: every particle straddles cells, some poke out of the walls.
/// Counted by centre, a cell holding one centre has alpha_s 1.02; counted by
/// overlap alpha_s stays physical, the volume is all there, and
/// T_k alpha_k = alpha_{k+1} to round-off.
void testCellSizedParticles() {
  BoxSpec box;
  box.nx = 3;
  box.ny = 3;
  box.nz = 6;
  box.origin = {0.0, 0.0, 0.0};
  box.length = {0.0072, 0.0072, 0.0144};
  const double d = 0.003, cellVolume = 0.0024 * 0.0024 * 0.0024;
  std::vector<P> lattice;
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i)
        lattice.push_back({1 + i + 2 * j + 4 * k, {0.0018 + 0.0036 * i, 0.0018 + 0.0036 * j,
                                                   0.0018 + 0.0036 * k}, d, 2500.0});
  double maxAlphaCentre = 0.0;
  for (ParticleVolume rule : {ParticleVolume::Centre, ParticleVolume::Overlap}) {
    std::mt19937_64 rng(777);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    ParticleBuildOptions opt;
    opt.mesh = box;
    opt.volume = rule;
    std::vector<FrameRecord> frames;
    ParticleFrameBuilder b(opt, [&](const FrameRecord &f) { frames.push_back(f); });
    for (int k = 0; k < 5; ++k) {
      const Vec3 drift{0.0006 * u(rng), 0.0006 * u(rng), 0.0006 * u(rng)};
      std::vector<P> moved = lattice;
      for (P &p : moved)
        for (int a = 0; a < 3; ++a) p.x[a] += drift[a] + 0.0002 * u(rng);
      b.add(snapshot(moved, k));
    }
    const ParticleBuildReport &r = b.report();
    if (rule == ParticleVolume::Centre) {
      maxAlphaCentre = r.maxAlphaS;
      continue;
    }
    RCFD_CHECK(r.outside == 0);
    RCFD_CHECK(r.maxAlphaResidual < 1e-14 && r.maxMassResidual < 1e-17);
    RCFD_CHECK(r.meanNnzPerOccupiedColumn > 4.0);
    for (std::size_t k = 0; k + 1 < frames.size(); ++k) {
      const auto ta = times(frames[k].shift, frames[k].alphaS);
      for (int c = 0; c < box.numCells(); ++c)
        RCFD_CHECK_CLOSE(ta[c], frames[k + 1].alphaS[c], 1e-14);
    }
    double volume = 0.0;
    for (double a : frames[0].alphaS) volume += a * cellVolume;
    RCFD_CHECK_CLOSE(volume, 16 * sphereVolume(d), 1e-13 * volume);
    // A cell smaller than a particle can be mostly inside it (0.89 here), never full.
    RCFD_CHECK(r.maxAlphaS < 0.95);
  }
  RCFD_CHECK(maxAlphaCentre > 1.0); // the centre rule's failure this test is about
}

/// The reference under the overlap rule: the large particle at z_med = 0.2
/// (a layer plane) is half in each layer and half in each half of the bed.
void testReferenceOverlap() {
  const double rho = 1000.0;
  BoxSpec layers;
  layers.nx = layers.ny = 1;
  layers.nz = 4;
  layers.origin = {-0.5, -0.5, 0.0};
  layers.length = {1.0, 1.0, 0.4};
  ReferenceOptions opt;
  opt.profileMesh = layers;
  opt.volume = ParticleVolume::Overlap;
  ParticleReference ref(opt);
  ref.add(0.5, snapshot({{1, {0.0, 0.0, 0.1}, 0.001, rho},
                         {2, {0.0, 0.0, 0.4}, 0.001, rho},
                         {3, {0.0, 0.0, 0.2}, 0.002, rho}},
                        0));
  const CogSample &s = ref.series()[0];
  RCFD_CHECK_CLOSE(s.lowerShare[0], 0.5, 1e-15);
  RCFD_CHECK_CLOSE(s.lowerShare[1], 0.5, 1e-15);
  const auto h = ref.halves();
  RCFD_CHECK_CLOSE(h.bottom[0], 0.2, 1e-15);
  RCFD_CHECK_CLOSE(h.top[0], 0.2, 1e-15);
  const auto prof = ref.profiles();
  const double small = sphereVolume(0.001) / 0.1, large = sphereVolume(0.002) / 0.1;
  RCFD_CHECK_CLOSE(prof[0][0], 0.5 * small, 1e-15);
  RCFD_CHECK_CLOSE(prof[0][1], 0.5 * small, 1e-15);
  RCFD_CHECK_CLOSE(prof[0][3], small, 1e-15); // the part above the top face stays in
  RCFD_CHECK_CLOSE(prof[1][1], 0.5 * large, 1e-15);
  RCFD_CHECK_CLOSE(prof[1][2], 0.5 * large, 1e-15);
}

} // namespace

int main() {
  char tmpl[] = "/tmp/rcfd_test_builder_XXXXXX";
  const char *dir = mkdtemp(tmpl);
  if (!dir) {
    std::fprintf(stderr, "mkdtemp failed\n");
    return 1;
  }
  testKnownMatrix();
  testVanishedAppearedOutside();
  testErrorsAndAxes();
  testRandomCloud(false);
  testRandomCloud(true);
  testFromFiles(dir);
  testReference(dir);
  testOverlapByHand();
  testCellSizedParticles();
  testReferenceOverlap();
  std::filesystem::remove_all(dir);
  return RCFD_TEST_RESULT();
}
