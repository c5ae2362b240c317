// Database frames from Eulerian frames (src/database/eulerian_frames.hpp):
// file round trip in any line order, the mesh from the cell centres, every
// error message, hand-computed traced shifts (uniform field, slow cells, a
// tracer ending in an empty cell, a cell no tracer reaches), the velocity a
// shift implies, and proportional scaling to a feasible target.
#include "check.hpp"
#include "box_meshes.hpp"
#include "builders/eulerian/eulerian_frames.hpp"
#include "database/csr.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

using namespace rcfd;

namespace {

std::string tempDir() {
  const auto dir = std::filesystem::temp_directory_path() / "rcfd-test-eulerian-frames";
  std::filesystem::create_directories(dir);
  return dir.string();
}

void writeText(const std::string &path, const std::string &text) {
  std::ofstream(path) << text;
}

/// The message of the exception f throws, or "" if it does not throw.
std::string errorOf(const std::function<void()> &f) {
  try {
    f();
  } catch (const std::exception &e) {
    return e.what();
  }
  return "";
}

#define CHECK_ERROR(call, text)                                                                    \
  do {                                                                                             \
    const std::string what_ = errorOf([&] { call; });                                              \
    if (what_.find(text) == std::string::npos)                                                     \
      rcfd::test::fail(__FILE__, __LINE__, std::string("expected '") + (text) + "', got '" +       \
                                               what_ + "'");                                       \
  } while (0)

double entry(const CsrMatrix &T, int j, int i) {
  for (int64_t e = T.rowPtr[j]; e < T.rowPtr[j + 1]; ++e)
    if (T.col[e] == i) return T.val[e];
  return 0.0;
}

void checkColumnSums(const CsrMatrix &T) {
  std::vector<double> sum(T.n, 0.0);
  for (std::size_t e = 0; e < T.val.size(); ++e) sum[T.col[e]] += T.val[e];
  for (int i = 0; i < T.n; ++i) RCFD_CHECK_CLOSE(sum[i], 1.0, 1e-14);
}

/// A column of nz cubic cells of 1 cm (nx cells wide), alpha_s per layer,
/// solid velocity (0, 0, w) everywhere.
BoxSpec column(int nx, int nz) {
  BoxSpec b;
  b.nx = nx;
  b.ny = 1;
  b.nz = nz;
  b.origin = {0.0, 0.0, 0.0};
  b.length = {0.01 * nx, 0.01, 0.01 * nz};
  return b;
}

EulerianFrame layered(const BoxSpec &b, const std::vector<double> &alphaPerLayer, double w) {
  EulerianFrame f;
  const int N = b.numCells();
  f.alphaS.resize(N);
  f.gasVelocity.assign(N, Vec3{0.0, 0.0, 0.0});
  f.solidVelocity.assign(N, Vec3{0.0, 0.0, w});
  for (int c = 0; c < N; ++c) f.alphaS[c] = alphaPerLayer[c / (b.nx * b.ny)];
  return f;
}

void fileRoundTrip(const std::string &dir) {
  BoxSpec b;
  b.nx = 2, b.ny = 3, b.nz = 4;
  b.origin = {1.0, -0.5, 0.25};
  b.length = {0.02, 0.03, 0.04};
  const Mesh mesh = rcfd::test::boxMesh(b);
  EulerianFrame f;
  for (int c = 0; c < b.numCells(); ++c) {
    f.alphaS.push_back(0.6 * std::fmod(0.37 * c + 0.11, 1.0));
    f.gasVelocity.push_back({0.1 * c, -1e-3 * c, 1.0 / (c + 3.0)});
    f.solidVelocity.push_back({-0.2 * c, 1e-17 * c, 0.5 / (c + 7.0)});
  }
  const std::string path = dir + "/roundtrip.txt";
  writeEulerianFrame(path, mesh, f);
  // Lines in reverse order, with a comment and a blank line.
  std::vector<std::string> lines;
  {
    std::ifstream in(path);
    for (std::string l; std::getline(in, l);) lines.push_back(l);
  }
  RCFD_CHECK(static_cast<int>(lines.size()) == b.numCells());
  std::reverse(lines.begin(), lines.end());
  std::string text = "# x y z alpha Ux Uy Uz Usx Usy Usz\n\n";
  for (const auto &l : lines) text += l + "\n";
  writeText(dir + "/reversed.txt", text);
  for (const std::string &file : {path, dir + "/reversed.txt"}) {
    const EulerianRows rows = readEulerianRows(file);
    const BoxSpec got = resolveEulerianMesh({}, rows);
    RCFD_CHECK(got.nx == 2 && got.ny == 3 && got.nz == 4);
    for (int a = 0; a < 3; ++a) {
      RCFD_CHECK_CLOSE(got.origin[a], b.origin[a], 1e-12);
      RCFD_CHECK_CLOSE(got.length[a], b.length[a], 1e-12);
    }
    const EulerianFrame back = mapOntoMesh(rows, b);
    for (int c = 0; c < b.numCells(); ++c) {
      RCFD_CHECK(std::fabs(back.alphaS[c] - f.alphaS[c]) <= 2.3e-16);
      RCFD_CHECK(back.gasVelocity[c] == f.gasVelocity[c]);
      RCFD_CHECK(back.solidVelocity[c] == f.solidVelocity[c]);
    }
  }
  // Explicit cells, or explicit bounds, give the same box.
  EulerianMeshRequest req;
  req.cells = std::array<int, 3>{2, 3, 4};
  RCFD_CHECK_CLOSE(resolveEulerianMesh(req, readEulerianRows(path)).length[2], 0.04, 1e-12);
  req.cells.reset();
  req.lo = Vec3{1.0, -0.5, 0.25};
  req.hi = Vec3{1.02, -0.47, 0.29};
  const BoxSpec fromBounds = resolveEulerianMesh(req, readEulerianRows(path));
  RCFD_CHECK(fromBounds.nx == 2 && fromBounds.ny == 3 && fromBounds.nz == 4);
}

void fileErrors(const std::string &dir) {
  const std::string good = "0.005 0.005 0.005 0.6 0 0 0 0 0 0\n0.005 0.005 0.015 0.6 0 0 0 0 0 0\n";
  const BoxSpec b = column(1, 2);
  auto parse = [&](const std::string &name, const std::string &text) {
    writeText(dir + "/" + name, text);
    return readEulerianRows(dir + "/" + name);
  };
  const std::string f = "Eulerian frame '" + dir + "/";
  CHECK_ERROR(parse("a.txt", good + "1 2 3\n"),
              f + "a.txt', line 3: expected 10 numbers (x y z alpha Ux Uy Uz Usx Usy Usz), found 3.");
  CHECK_ERROR(parse("b.txt", "# header\n\n" + good + "0 0 0 0.5 0 0 0 0 0 0 7\n"),
              f + "b.txt', line 5: expected 10 numbers (x y z alpha Ux Uy Uz Usx Usy Usz), found 11.");
  CHECK_ERROR(parse("c.txt", "0.0.1 0 0 0.5 0 0 0 0 0 0\n"),
              f + "c.txt', line 1: column 1 (x) is '0.0.1', not a finite number.");
  CHECK_ERROR(parse("d.txt", good + "0 0 0 0.5 0 inf 0 0 0 0\n"),
              f + "d.txt', line 3: column 6 (Uy) is 'inf', not a finite number.");
  CHECK_ERROR(parse("e.txt", "0 0 0 -0.25 0 0 0 0 0 0\n"),
              f + "e.txt', line 1: alpha (the void fraction, column 4) is -0.25, outside [0, 1].");
  CHECK_ERROR(parse("f.txt", "# nothing\n\n"), f + "f.txt' holds no cell.");
  CHECK_ERROR(readEulerianRows(dir + "/missing.txt"),
              "cannot open Eulerian frame '" + dir + "/missing.txt'.");
  // Leading '+' and CRLF line ends are fine.
  RCFD_CHECK(parse("g.txt", "+0.005 0.005 0.005 +0.6 0 0 0 0 0 1e-3\r\n").solidVelocity[0][2] == 1e-3);

  // Mapping onto the 1 x 1 x 2 column of 1 cm.
  CHECK_ERROR(mapOntoMesh(parse("h.txt", good + "0.005 0.005 0.025 0.6 0 0 0 0 0 0\n"), b),
              f + "h.txt', line 3: the cell centre (0.005, 0.005, 0.025) is outside the mesh "
                  "(0, 0, 0) to (0.01, 0.01, 0.02).");
  CHECK_ERROR(mapOntoMesh(parse("i.txt", "0.005 0.005 0.005 0.6 0 0 0 0 0 0\n"
                                         "0.005 0.005 0.006 0.6 0 0 0 0 0 0\n"),
                          b),
              f + "i.txt', line 2: the cell centre (0.005, 0.005, 0.006) gives mesh cell (0, 0, 0) "
                  "centred at (0.005, 0.005, 0.005), as line 1 does.");
  CHECK_ERROR(mapOntoMesh(parse("j.txt", "0.005 0.005 0.005 0.6 0 0 0 0 0 0\n"
                                         "0.005 0.005 0.0185 0.6 0 0 0 0 0 0\n"),
                          b),
              f + "j.txt', line 2: the cell centre (0.005, 0.005, 0.0185) lies in mesh cell (0, 0, 1) "
                  "centred at (0.005, 0.005, 0.015) but 0.35 cells away from its centre along z");
  CHECK_ERROR(mapOntoMesh(parse("k.txt", "0.005 0.005 0.015 0.6 0 0 0 0 0 0\n"), b),
              f + "k.txt' has 1 cells but the mesh 1 x 1 x 2 has 2: 1 missing, the first is mesh "
                  "cell (0, 0, 0) centred at (0.005, 0.005, 0.005).");
  CHECK_ERROR(resolveEulerianMesh({}, parse("l.txt", good)),
              f + "l.txt': every cell centre has x = 0.005, so the cells' extent along x is unknown; "
                  "give it with -mesh_lo and -mesh_hi.");
}

/// u dt_rec = half a cell: half of every cell moves up, the top layer stays.
void uniformField() {
  const BoxSpec b = column(2, 4);
  const EulerianFrame now = layered(b, {0.4, 0.4, 0.4, 0.4}, 0.5);
  const std::vector<double> next = layered(b, {0.2, 0.4, 0.4, 0.6}, 0.0).alphaS;
  for (auto interp : {TracerInterpolation::cell, TracerInterpolation::trilinear})
    for (int n : {8, 64}) {
      EulerianBuildOptions o;
      o.mesh = b;
      o.dtRec = 0.01;
      o.tracersPerCell = n;
      o.interpolation = interp;
      o.supportSeed = 0.0;
      EulerianFrameStats st;
      const CsrMatrix T = traceShift(now, next, o, 3, &st);
      checkColumnSums(T);
      for (int c = 0; c < b.numCells(); ++c) {
        const bool top = c >= 6;
        RCFD_CHECK_CLOSE(entry(T, c, c), top ? 1.0 : 0.5, 1e-14);
        if (!top) RCFD_CHECK_CLOSE(entry(T, c + 2, c), 0.5, 1e-14);
      }
      RCFD_CHECK(T.nnz() == 14);
      RCFD_CHECK(st.residualBefore < 1e-15 && st.iterations == 0 && st.slowCells == 0);
      RCFD_CHECK(st.tracers == static_cast<std::size_t>(8 * n) && st.redirected == 0);
      // The velocity this shift implies is the field's, except at the top.
      const auto u = impliedSolidVelocity(rcfd::test::boxMesh(b), T, o.dtRec);
      for (int c = 0; c < b.numCells(); ++c) {
        RCFD_CHECK_CLOSE(u[c][2], c >= 6 ? 0.0 : 0.5, 1e-12);
        RCFD_CHECK(u[c][0] == 0.0 && u[c][1] == 0.0);
      }
    }
  // With the default seeds the support is wider; scaling keeps it
  // mass-consistent and close to the hand matrix.
  EulerianBuildOptions o;
  o.mesh = b;
  o.dtRec = 0.01;
  EulerianFrameStats st;
  const CsrMatrix T = traceShift(now, next, o, 0, &st);
  checkColumnSums(T);
  RCFD_CHECK(st.residualAfter < 1e-6);
  for (int c = 0; c < 6; ++c) RCFD_CHECK_CLOSE(entry(T, c + 2, c), 0.5, 0.05);
}

/// u dt_rec = h / 8: t_cross = 8 dt_rec, r = 4; 3/4 stays, 1/4 moves half a
/// cell with 4 u, of which half crosses: T(k+1, k) = 1/8 = u dt_rec / h.
void slowCells() {
  const BoxSpec b = column(1, 4);
  EulerianBuildOptions o;
  o.mesh = b;
  o.dtRec = 0.01;
  o.supportSeed = 0.0;
  o.scalingIterations = 0;
  const EulerianFrame now = layered(b, {0.4, 0.4, 0.4, 0.4}, 0.125);
  EulerianFrameStats st;
  const CsrMatrix T = traceShift(now, now.alphaS, o, 0, &st);
  checkColumnSums(T);
  RCFD_CHECK(st.slowCells == 4);
  for (int c = 0; c < 3; ++c) {
    RCFD_CHECK_CLOSE(entry(T, c, c), 7.0 / 8.0, 1e-14);
    RCFD_CHECK_CLOSE(entry(T, c + 1, c), 1.0 / 8.0, 1e-14);
  }
  RCFD_CHECK_CLOSE(entry(T, 3, 3), 1.0, 1e-14);
  // A cell at rest keeps everything.
  const CsrMatrix R = traceShift(layered(b, {0.4, 0.4, 0.4, 0.4}, 0.0), now.alphaS, o, 0, &st);
  for (int c = 0; c < 4; ++c) RCFD_CHECK(entry(R, c, c) == 1.0);
}

/// Tracers that end in a cell empty at t_{k+1} go to the nearest full cell;
/// a full cell that no tracer reaches borrows its neighbours' sources.
void emptyAndUnreached() {
  const BoxSpec b = column(1, 4);
  EulerianBuildOptions o;
  o.mesh = b;
  o.dtRec = 0.01;
  o.supportSeed = 0.0;
  o.scalingTolerance = 1e-14;
  EulerianFrameStats st;
  // Cells 0, 1 full and moving up by half a cell; cell 2 stays empty.
  const CsrMatrix T = traceShift(layered(b, {0.4, 0.4, 0.0, 0.0}, 0.5), {0.2, 0.6, 0.0, 0.0}, o, 0, &st);
  checkColumnSums(T);
  RCFD_CHECK(st.redirected == 4);
  RCFD_CHECK_CLOSE(entry(T, 0, 0), 0.5, 1e-14);
  RCFD_CHECK_CLOSE(entry(T, 1, 0), 0.5, 1e-14);
  RCFD_CHECK_CLOSE(entry(T, 1, 1), 1.0, 1e-14);
  RCFD_CHECK(entry(T, 2, 2) == 1.0 && entry(T, 3, 3) == 1.0); // empty: identity columns
  RCFD_CHECK(st.residualBefore < 1e-15);
  // Cell 0 at rest keeps its solid, but cell 1 holds solid at t_{k+1}.
  const CsrMatrix U = traceShift(layered(b, {0.4, 0.0, 0.0, 0.0}, 0.0), {0.2, 0.2, 0.0, 0.0}, o, 0, &st);
  checkColumnSums(U);
  RCFD_CHECK(st.filledCells == 1 && st.unreachedCells == 0);
  RCFD_CHECK(st.residualAfter < 1e-12);
  RCFD_CHECK_CLOSE(entry(U, 0, 0), 0.5, 1e-12);
  RCFD_CHECK_CLOSE(entry(U, 1, 0), 0.5, 1e-12);
}

/// A full positive 3 x 3 matrix reaches any target with the same total.
void scaling() {
  CsrMatrix T;
  T.n = 3;
  T.rowPtr = {0, 3, 6, 9};
  T.col = {0, 1, 2, 0, 1, 2, 0, 1, 2};
  T.val = {0.5, 0.2, 0.3, 0.25, 0.5, 0.3, 0.25, 0.3, 0.4};
  const std::vector<double> m{1.0, 2.0, 3.0}, target{3.0, 2.0, 1.0};
  RCFD_CHECK(relativeMismatch(T, m, target) > 0.1);
  const int it = scaleToTarget(T, m, target, 100, 1e-13);
  RCFD_CHECK(it > 0 && it < 100);
  RCFD_CHECK(relativeMismatch(T, m, target) < 1e-13);
  checkColumnSums(T);
  // A target with another total is reached up to that total.
  CsrMatrix S = T;
  scaleToTarget(S, m, {6.0, 4.0, 2.0}, 100, 1e-13);
  RCFD_CHECK(relativeMismatch(S, m, target) < 1e-13);
}

/// The builder emits one frame per file after the first.
void builder() {
  const BoxSpec b = column(1, 4);
  EulerianBuildOptions o;
  o.mesh = b;
  o.dtRec = 0.01;
  std::vector<FrameRecord> out;
  EulerianFrameBuilder build(o, [&](const FrameRecord &f) { out.push_back(f); });
  build.add(layered(b, {0.4, 0.4, 0.0, 0.0}, 0.1));
  RCFD_CHECK(out.empty());
  build.add(layered(b, {0.4, 0.3, 0.1, 0.0}, 0.1));
  build.add(layered(b, {0.3, 0.3, 0.2, 0.0}, 0.1));
  RCFD_CHECK(out.size() == 2 && build.report().frames == 2 && build.report().files == 3);
  RCFD_CHECK(out[0].alphaS[1] == 0.4 && out[1].alphaS[2] == 0.1);
  RCFD_CHECK(build.report().maxResidualAfter() < 1e-6);
  RCFD_CHECK(build.report().summary().find("2 database frames of 4 cells") != std::string::npos);
  CHECK_ERROR(EulerianFrameBuilder(EulerianBuildOptions{}, nullptr), "-dt_rec must be a positive time");
}

} // namespace

int main() {
  const std::string dir = tempDir();
  fileRoundTrip(dir);
  fileErrors(dir);
  uniformField();
  slowCells();
  emptyAndUnreached();
  scaling();
  builder();
  std::filesystem::remove_all(dir);
  return RCFD_TEST_RESULT();
}
