// Snapshot series and segregation scores: natural file order, list files,
// equally spaced times, the mesh from a (flipped) dump box, masses per cell
// and class, and the Eq. 7 / RMS scores on hand-computed curves.
#include "check.hpp"
#include "builders/particles/snapshot_series.hpp"
#include "analysis/segregation_score.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

using namespace rcfd;
using rcfd::test::throwsWith;

namespace {

void touch(const std::string &path, const std::string &text = "") { std::ofstream(path) << text; }

void files(const std::string &dir) {
  for (const char *n : {"dump.10.gz", "dump.9.gz", "dump.100.gz", "dump.009b.gz", "dump.0.gz"})
    touch(dir + "/" + n);
  const auto f = globSnapshotFiles(dir + "/dump.*.gz");
  std::vector<std::string> names;
  for (const auto &p : f) names.push_back(std::filesystem::path(p).filename().string());
  RCFD_CHECK((names == std::vector<std::string>{"dump.0.gz", "dump.9.gz", "dump.009b.gz",
                                                "dump.10.gz", "dump.100.gz"}));
  RCFD_CHECK(throwsWith([&] { globSnapshotFiles(dir + "/none.*"); }, "no particle snapshot file matches"));

  // A list: relative to its own directory, comments and blanks skipped.
  std::filesystem::create_directories(dir + "/sub");
  touch(dir + "/sub/list.txt", "# the snapshots\n\na.dump\n/abs/b.dump\n");
  const auto l = readSnapshotList(dir + "/sub/list.txt");
  RCFD_CHECK(l.size() == 2 && l[0] == dir + "/sub/a.dump" && l[1] == "/abs/b.dump");
  touch(dir + "/empty.txt", "# nothing\n");
  RCFD_CHECK(throwsWith([&] { readSnapshotList(dir + "/empty.txt"); }, "names no files"));
}

void intervals() {
  const std::vector<double> t{0.005, 0.010, 0.015, 0.020, 0.025};
  RCFD_CHECK_CLOSE(uniformInterval(t, {0, 1, 2, 3, 4}), 0.005, 1e-15);
  RCFD_CHECK_CLOSE(uniformInterval(t, {0, 2, 4}), 0.010, 1e-15);
  const std::vector<double> uneven{0.0, 0.1, 0.25};
  RCFD_CHECK(throwsWith([&] { uniformInterval(uneven, {0, 1, 2}); }, "not equally spaced"));
  const std::vector<double> back{0.2, 0.1};
  RCFD_CHECK(throwsWith([&] { uniformInterval(back, {0, 1}); }, "do not increase"));
}

void meshes() {
  ParticleSnapshot s;
  s.source = "memory";
  s.hasBox = true;
  s.boxLo = {-0.04, 0.0, -0.006};
  s.boxHi = {0.04, 0.3, 0.006};
  // Vertical file axis y, gravity towards -y: rcfd x <- file z, y <- file x, z <- file y.
  const AxisMap axes = AxisMap::verticalUp(1, -1);
  MeshRequest req;
  req.cellSize = 0.005;
  const BoxSpec b = resolveMesh(req, s, axes);
  RCFD_CHECK(b.nx == 2 && b.ny == 16 && b.nz == 60);
  RCFD_CHECK_CLOSE(b.origin[0], -0.006, 1e-15);
  RCFD_CHECK_CLOSE(b.origin[1], -0.04, 1e-15);
  RCFD_CHECK_CLOSE(b.length[2], 0.3, 1e-15);
  // Gravity towards +z in the file: z flips, its bounds swap.
  const BoxSpec f = resolveMesh(req, s, AxisMap::verticalUp(2, +1));
  RCFD_CHECK_CLOSE(f.origin[2], -0.006, 1e-15);
  RCFD_CHECK_CLOSE(f.length[2], 0.012, 1e-15);
  // Explicit cells and bounds win.
  req.cells = std::array<int, 3>{4, 1, 3};
  req.lo = Vec3{0, 0, 0};
  req.hi = Vec3{4, 1, 3};
  const BoxSpec e = resolveMesh(req, s, axes);
  RCFD_CHECK(e.nx == 4 && e.ny == 1 && e.nz == 3 && e.length[2] == 3.0);
  s.hasBox = false;
  RCFD_CHECK(throwsWith([&] { resolveMesh(MeshRequest{{}, 0.01, {}, {}}, s, axes); }, "-mesh_lo"));

  // Masses per cell and class: two classes, one particle outside.
  ParticleSnapshot p;
  p.source = "memory";
  p.id = {1, 2, 3, 4};
  p.position = {{0.5, 0.5, 0.5}, {0.5, 0.5, 2.5}, {3.5, 0.5, 2.5}, {9, 9, 9}};
  p.diameter = {1e-3, 2e-3, 1.001e-3, 1e-3};
  p.mass = {1.0, 8.0, 1.5, 7.0};
  SizeClasses cls = SizeClasses::cluster(p.diameter, 0.01);
  RCFD_CHECK(cls.diameter.size() == 2);
  std::size_t outside = 0;
  const auto m = classMassesPerCell(p, AxisMap{}, e, cls, ParticleVolume::Overlap, &outside);
  RCFD_CHECK(m.size() == 24 && outside == 1);
  RCFD_CHECK(m[0] == 1.0 && m[1] == 0.0);                 // cell 0, small
  RCFD_CHECK(m[2 * e.cellIndex(0, 0, 2) + 1] == 8.0);     // cell 8, large
  RCFD_CHECK(m[2 * e.cellIndex(3, 0, 2) + 0] == 1.5);     // cell 11, small
  double total = 0;
  for (double x : m) total += x;
  RCFD_CHECK(total == 10.5);
  p.diameter[1] = 3e-3;
  RCFD_CHECK(throwsWith([&] { classMassesPerCell(p, AxisMap{}, e, cls, ParticleVolume::Overlap, nullptr); }, "particle id 2"));
}

void scores(const std::string &dir) {
  // Reference: 0 at t = 0, 1, 2, 3 mm at 0.5 ... rising linearly from 0 to 2 mm over [0, 1] s,
  // sampled every 0.25 s; the model is 1 mm everywhere, sampled every 0.5 s.
  DeltaZSeries ref{{0.0, 0.25, 0.5, 0.75, 1.0}, {0.0, 0.5e-3, 1.0e-3, 1.5e-3, 2.0e-3}};
  DeltaZSeries model{{0.0, 0.5, 1.0}, {1e-3, 1e-3, 1e-3}};
  RCFD_CHECK_CLOSE(interpolate(ref, 0.6), 1.2e-3, 1e-15);
  const DeltaZScore s = scoreDeltaZ(ref, model, 0.5, 1.0);
  // Window means: reference (1 + 1.5 + 2) / 3 = 1.5 mm, model 1 mm: -33.3 %.
  RCFD_CHECK(s.windowSamplesRef == 3 && s.windowSamplesModel == 2);
  RCFD_CHECK_CLOSE(s.meanRef, 1.5e-3, 1e-15);
  RCFD_CHECK_CLOSE(s.segregationError, -100.0 / 3.0, 1e-12);
  // Curve at the model's times: differences 1, 0, -1 mm: RMS sqrt(2/3) mm, peak 2 mm.
  RCFD_CHECK(s.curveSamples == 3);
  RCFD_CHECK_CLOSE(s.rms, std::sqrt(2.0 / 3.0) * 1e-3, 1e-15);
  RCFD_CHECK_CLOSE(s.rmsRelative, std::sqrt(2.0 / 3.0) / 2.0, 1e-12);
  RCFD_CHECK(throwsWith([&] { scoreDeltaZ(ref, model, 2.0, 3.0); }, "no sample"));

  // Files: rcfd's column names with an offset, and a file with class columns only.
  touch(dir + "/run.csv", "time_s,z_cog_bed_m,z_cog_d1.950mm_m,z_cog_d2.820mm_m,delta_z_m,mass_kg\n"
                          "0,0.05,0.06,0.04,0.02,1\n0.005,0.05,0.061,0.04,0.021,1\n");
  const auto r = readDeltaZCsv(dir + "/run.csv", 0.005);
  RCFD_CHECK(r.time.size() == 2 && r.time[1] == 0.01 && r.deltaZ[1] == 0.021);
  touch(dir + "/classes.csv", "time,z_cog_bed,z_cog_d2.820mm,z_cog_d1.950mm,share\n"
                              "0.005,0.05,0.04,0.07,0.5\n");
  const auto c = readDeltaZCsv(dir + "/classes.csv");
  RCFD_CHECK_CLOSE(c.deltaZ[0], 0.03, 1e-15);
  touch(dir + "/bad.csv", "time_s,delta_z_m\n0,1\n0.1,x\n");
  RCFD_CHECK(throwsWith([&] { readDeltaZCsv(dir + "/bad.csv"); }, "line 3, column 'delta_z_m': expected a number, found 'x'"));
  touch(dir + "/none.csv", "t,z\n0,1\n");
  RCFD_CHECK(throwsWith([&] { readDeltaZCsv(dir + "/none.csv"); }, "is not a centre-of-gravity file"));
}

} // namespace

int main() {
  char tmpl[] = "/tmp/rcfd_test_series_XXXXXX";
  const char *dir = mkdtemp(tmpl);
  if (!dir) {
    std::fprintf(stderr, "mkdtemp failed\n");
    return 1;
  }
  files(dir);
  intervals();
  meshes();
  scores(dir);
  std::filesystem::remove_all(dir);
  return RCFD_TEST_RESULT();
}
