#include "builders/eulerian/eulerian_frames.hpp"

#include "base/atomic_file.hpp"
#include "base/input_file.hpp"
#include "base/random.hpp"
#include "database/csr.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <deque>
#include <fstream>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <tuple>

namespace rcfd {
namespace {

constexpr int kColumns = 10;
constexpr const char *kColumnNames[kColumns] = {"x",  "y",  "z",   "alpha", "Ux",
                                                "Uy", "Uz", "Usx", "Usy",   "Usz"};
constexpr const char *kAxisNames[3] = {"x", "y", "z"};
// Far more sub-steps than a tracer can need once velocities moving more than
// 1000 cells per dt_rec are refused; only a guard against endless loops.
constexpr int kMaxSubsteps = 100000;
// Scaling widens the support of the rows that miss their target by more than
// this share once it has stalled (the others converge with what they have).
constexpr double kStuckShare = 5e-2;

std::string where(const std::string &path, int line) {
  return "Eulerian frame '" + path + "', line " + std::to_string(line) + ": ";
}

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", v);
  return text;
}

std::string point(const Vec3 &p) {
  return "(" + number(p[0]) + ", " + number(p[1]) + ", " + number(p[2]) + ")";
}

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

/// Parses one whole token as a finite double (a leading '+' is allowed).
bool parseNumber(const char *begin, const char *end, double *out) {
  if (begin < end && *begin == '+') ++begin;
  const auto [ptr, ec] = std::from_chars(begin, end, *out);
  return ec == std::errc() && ptr == end && std::isfinite(*out);
}

/// Integer cell coordinates of a natural index.
std::array<int, 3> cellIjk(const BoxSpec &b, int c) {
  return {c % b.nx, (c / b.nx) % b.ny, c / (b.nx * b.ny)};
}

Vec3 cellCentre(const BoxSpec &b, const std::array<int, 3> &ijk) {
  const Vec3 h = b.spacing();
  return {b.origin[0] + (ijk[0] + 0.5) * h[0], b.origin[1] + (ijk[1] + 0.5) * h[1],
          b.origin[2] + (ijk[2] + 0.5) * h[2]};
}

std::string cellName(const BoxSpec &b, int c) {
  const auto ijk = cellIjk(b, c);
  return "mesh cell (" + std::to_string(ijk[0]) + ", " + std::to_string(ijk[1]) + ", " +
         std::to_string(ijk[2]) + ") centred at " + point(cellCentre(b, ijk));
}

/// Calls f(cell) for every cell of the box at Chebyshev distance exactly R
/// from cell ijk (R = 0: the cell itself).
template <typename F> void forEachInRing(const BoxSpec &b, const std::array<int, 3> &c, int R, F &&f) {
  const int n[3] = {b.nx, b.ny, b.nz};
  for (int dk = -R; dk <= R; ++dk) {
    const int k = c[2] + dk;
    if (k < 0 || k >= n[2]) continue;
    for (int dj = -R; dj <= R; ++dj) {
      const int j = c[1] + dj;
      if (j < 0 || j >= n[1]) continue;
      const bool shell = std::abs(dk) == R || std::abs(dj) == R;
      for (int di = -R; di <= R; di += (shell || R == 0) ? 1 : 2 * R) {
        const int i = c[0] + di;
        if (i >= 0 && i < n[0]) f(b.cellIndex(i, j, k));
      }
    }
  }
}

/// Tracer strata per axis (sx * sy * sz = n), as even as possible; ties go
/// to more strata along z, then x.
std::array<int, 3> strata(int n) {
  std::array<int, 3> best{1, 1, n};
  auto score = [](const std::array<int, 3> &s) {
    const int spread = std::max({s[0], s[1], s[2]}) - std::min({s[0], s[1], s[2]});
    return std::make_tuple(spread, -s[2], -s[0]);
  };
  for (int a = 1; a <= n; ++a)
    for (int b = 1; a * b <= n; ++b)
      if (n % (a * b) == 0) {
        const std::array<int, 3> s{a, b, n / (a * b)};
        if (score(s) < score(best)) best = s;
      }
  return best;
}

/// Open interval (0, 1), 53 random bits.
double jitter(Xoshiro256 &rng) { return (static_cast<double>(rng.next() >> 11) + 0.5) * 0x1.0p-53; }

/// The frozen solid velocity field of one frame.
class VelocityField {
public:
  VelocityField(const BoxSpec &box, const EulerianFrame &f, TracerInterpolation kind, double empty)
      : box(box), h(box.spacing()), frame(f), kind(kind), empty(empty) {}

  /// Velocity at p (inside the box); `fallback` where no solid is around.
  Vec3 at(const Vec3 &p, const Vec3 &fallback) const {
    if (kind == TracerInterpolation::cell) {
      const int c = box.locate(p);
      return c >= 0 && frame.alphaS[c] > empty ? frame.solidVelocity[c] : fallback;
    }
    const int n[3] = {box.nx, box.ny, box.nz};
    int i0[3];
    double f[3];
    for (int a = 0; a < 3; ++a) {
      const double s = std::clamp((p[a] - box.origin[a]) / h[a] - 0.5, 0.0, n[a] - 1.0);
      i0[a] = std::min(static_cast<int>(s), std::max(n[a] - 2, 0));
      f[a] = s - i0[a];
    }
    Vec3 u{0.0, 0.0, 0.0};
    double total = 0.0;
    for (int corner = 0; corner < 8; ++corner) {
      double w = 1.0;
      int idx[3];
      for (int a = 0; a < 3; ++a) {
        const int up = (corner >> a) & 1;
        w *= up ? f[a] : 1.0 - f[a];
        idx[a] = i0[a] + up;
      }
      if (w <= 0.0) continue;
      const int c = box.cellIndex(idx[0], idx[1], idx[2]);
      const double wa = w * frame.alphaS[c];
      if (!(frame.alphaS[c] > empty)) continue;
      total += wa;
      for (int a = 0; a < 3; ++a) u[a] += wa * frame.solidVelocity[c][a];
    }
    if (!(total > 0.0)) return fallback;
    for (double &x : u) x /= total;
    return u;
  }

private:
  const BoxSpec &box;
  Vec3 h;
  const EulerianFrame &frame;
  TracerInterpolation kind;
  double empty;
};

/// Mirror a point back into the box at the walls (clamped if it would still
/// be outside after one reflection).
void reflect(const BoxSpec &box, Vec3 &p) {
  for (int a = 0; a < 3; ++a) {
    const double lo = box.origin[a], hi = box.origin[a] + box.length[a];
    if (p[a] < lo) p[a] = 2 * lo - p[a];
    if (p[a] > hi) p[a] = 2 * hi - p[a];
    p[a] = std::clamp(p[a], lo, hi);
  }
}

/// Nearest cell (centre to p) among those with `ok`, found on demand from a
/// Chebyshev distance map to the nearest `ok` cell.
class NearestCell {
public:
  NearestCell(const BoxSpec &box, std::vector<char> ok) : box(box), ok(std::move(ok)) {}

  /// -1 when no cell is ok.
  int operator()(int from, const Vec3 &p) {
    if (ok[from]) return from;
    if (distance.empty()) buildDistance();
    const int D = distance[from];
    if (D < 0) return -1;
    int best = -1;
    double bestDist = std::numeric_limits<double>::infinity();
    const auto ijk = cellIjk(box, from);
    for (int R = D; R <= D + 1; ++R)
      forEachInRing(box, ijk, R, [&](int c) {
        if (!ok[c]) return;
        const Vec3 x = cellCentre(box, cellIjk(box, c));
        const double d = std::hypot(x[0] - p[0], x[1] - p[1], x[2] - p[2]);
        if (d < bestDist || (d == bestDist && c < best)) bestDist = d, best = c;
      });
    return best;
  }

private:
  void buildDistance() { // multi-source breadth-first search over the 26 neighbours
    distance.assign(ok.size(), -1);
    std::deque<int> queue;
    for (std::size_t c = 0; c < ok.size(); ++c)
      if (ok[c]) distance[c] = 0, queue.push_back(static_cast<int>(c));
    while (!queue.empty()) {
      const int c = queue.front();
      queue.pop_front();
      forEachInRing(box, cellIjk(box, c), 1, [&](int nb) {
        if (distance[nb] < 0) distance[nb] = distance[c] + 1, queue.push_back(nb);
      });
    }
  }

  const BoxSpec &box;
  std::vector<char> ok;
  std::vector<int> distance;
};

double mean(const std::vector<EulerianFrameStats> &v, double EulerianFrameStats::*field) {
  if (v.empty()) return 0.0;
  double s = 0.0;
  for (const auto &f : v) s += f.*field;
  return s / static_cast<double>(v.size());
}

double largest(const std::vector<EulerianFrameStats> &v, double EulerianFrameStats::*field) {
  double s = 0.0;
  for (const auto &f : v) s = std::max(s, f.*field);
  return s;
}

/// T with seeds of `seed` times the source's share added within Chebyshev
/// distance R: into every row that still receives too little, from each
/// occupied cell around it; and out of every source of a row that receives
/// too much, to each cell around that row that holds solid at t_{k+1}.
CsrMatrix widenSupport(const CsrMatrix &T, const std::vector<double> &m,
                       const std::vector<double> &target, const std::vector<char> &fullNext,
                       const BoxSpec &box, int R, double seed) {
  const int n = T.n;
  const double mTotal = std::accumulate(m.begin(), m.end(), 0.0);
  const double tTotal = std::accumulate(target.begin(), target.end(), 0.0);
  std::vector<double> y;
  multiply(T, m, y);
  std::vector<int32_t> dest, src;
  std::vector<double> weight;
  for (int j = 0; j < n; ++j)
    for (int64_t e = T.rowPtr[j]; e < T.rowPtr[j + 1]; ++e) {
      dest.push_back(j);
      src.push_back(T.col[e]);
      weight.push_back(T.val[e] * m[T.col[e]]);
    }
  for (int j = 0; j < n; ++j) {
    const double t = target[j] * (mTotal / tTotal), d = t - y[j];
    if (!fullNext[j] || std::fabs(d) <= kStuckShare * std::max(t, y[j])) continue;
    for (int r = 0; r <= R; ++r)
      forEachInRing(box, cellIjk(box, j), r, [&](int c) {
        if (d > 0 && m[c] > 0.0) { // c may feed j
          dest.push_back(j);
          src.push_back(c);
          weight.push_back(seed * m[c]);
        }
        if (d < 0 && fullNext[c]) // j's sources may feed c
          for (int64_t e = T.rowPtr[j]; e < T.rowPtr[j + 1]; ++e)
            if (m[T.col[e]] > 0.0) {
              dest.push_back(c);
              src.push_back(T.col[e]);
              weight.push_back(seed * m[T.col[e]]);
            }
      });
  }
  return shiftFromTransfers(n, std::move(dest), std::move(src), std::move(weight));
}

} // namespace

// ------------------------------------------------------------------ files

EulerianRows readEulerianRows(const std::string &path) {
  requireRegularFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open Eulerian frame '" + path + "'.");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw std::runtime_error("cannot read Eulerian frame '" + path + "'.");
  const std::string text = buffer.str();

  EulerianRows rows;
  rows.source = path;
  const char *p = text.data(), *const end = text.data() + text.size();
  int line = 0;
  double v[kColumns];
  while (p < end) {
    const char *eol = static_cast<const char *>(std::memchr(p, '\n', end - p));
    if (!eol) eol = end;
    ++line;
    const char *q = p;
    while (q < eol && isBlank(*q)) ++q;
    if (q < eol && *q != '#') {
      int column = 0;
      while (q < eol) {
        const char *t = q;
        while (q < eol && !isBlank(*q)) ++q;
        if (column < kColumns && !parseNumber(t, q, &v[column]))
          throw std::runtime_error(where(path, line) + "column " + std::to_string(column + 1) +
                                   " (" + kColumnNames[column] + ") is '" + std::string(t, q) +
                                   "', not a finite number.");
        ++column;
        while (q < eol && isBlank(*q)) ++q;
      }
      if (column != kColumns)
        throw std::runtime_error(where(path, line) + "expected " + std::to_string(kColumns) +
                                 " numbers (x y z alpha Ux Uy Uz Usx Usy Usz), found " +
                                 std::to_string(column) + ".");
      if (v[3] < 0.0 || v[3] > 1.0)
        throw std::runtime_error(where(path, line) + "alpha (the void fraction, column 4) is " +
                                 number(v[3]) + ", outside [0, 1].");
      rows.line.push_back(line);
      rows.centre.push_back({v[0], v[1], v[2]});
      rows.voidFraction.push_back(v[3]);
      rows.gasVelocity.push_back({v[4], v[5], v[6]});
      rows.solidVelocity.push_back({v[7], v[8], v[9]});
    }
    p = eol + 1;
  }
  if (rows.size() == 0) throw std::runtime_error("Eulerian frame '" + path + "' holds no cell.");
  return rows;
}

BoxSpec resolveEulerianMesh(const EulerianMeshRequest &request, const EulerianRows &rows) {
  BoxSpec box;
  const std::string file = "Eulerian frame '" + rows.source + "'";
  for (int a = 0; a < 3; ++a) {
    std::vector<double> x(rows.size());
    for (std::size_t r = 0; r < rows.size(); ++r) x[r] = rows.centre[r][a];
    std::sort(x.begin(), x.end());
    const double lo = x.front(), hi = x.back();
    // Distinct coordinates, merging values closer than 1e-5 of the extent
    // (ASCII files round the centres).
    int distinct = 1;
    for (std::size_t r = 1; r < x.size(); ++r)
      if (x[r] - x[r - 1] > 1e-5 * (hi - lo)) ++distinct;
    const double spacing = distinct > 1 ? (hi - lo) / (distinct - 1) : 0.0;
    const bool hasBounds = request.lo && request.hi;
    int n = request.cells ? (*request.cells)[a] : distinct;
    if (hasBounds) {
      box.origin[a] = (*request.lo)[a];
      box.length[a] = (*request.hi)[a] - (*request.lo)[a];
      if (!request.cells && distinct > 1)
        n = std::max(1, static_cast<int>(std::lround(box.length[a] / spacing)));
    } else {
      if (n < 1)
        throw std::invalid_argument("the mesh needs at least one cell along each axis.");
      if (n == 1 && distinct == 1)
        throw std::runtime_error(file + ": every cell centre has " + kAxisNames[a] + " = " +
                                 number(lo) + ", so the cells' extent along " + kAxisNames[a] +
                                 " is unknown; give it with -mesh_lo and -mesh_hi.");
      const double h = n > 1 ? (hi - lo) / (n - 1) : 0.0;
      if (n == 1 || !(h > 0))
        throw std::runtime_error(file + ": the cell centres span " + number(lo) + " to " +
                                 number(hi) + " along " + kAxisNames[a] + ", which " +
                                 std::to_string(n) +
                                 " cell(s) cannot have as centres; give -mesh_lo and -mesh_hi.");
      box.origin[a] = lo - 0.5 * h;
      box.length[a] = (hi - lo) + h;
      // A box starting at 0 should say so, not 4e-19.
      if (std::fabs(box.origin[a]) < 1e-9 * box.length[a]) box.origin[a] = 0.0;
    }
    if (!(box.length[a] > 0))
      throw std::invalid_argument(std::string("-mesh_hi must exceed -mesh_lo along ") +
                                  kAxisNames[a] + ".");
    (a == 0 ? box.nx : a == 1 ? box.ny : box.nz) = n;
  }
  return box;
}

EulerianFrame mapOntoMesh(const EulerianRows &rows, const BoxSpec &mesh) {
  const int N = mesh.numCells();
  const Vec3 h = mesh.spacing();
  EulerianFrame f;
  f.source = rows.source;
  f.alphaS.assign(N, 0.0);
  f.gasVelocity.assign(N, Vec3{0.0, 0.0, 0.0});
  f.solidVelocity.assign(N, Vec3{0.0, 0.0, 0.0});
  std::vector<int> lineOf(N, 0);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const Vec3 &p = rows.centre[r];
    const int c = mesh.locate(p);
    if (c < 0) {
      const Vec3 hi{mesh.origin[0] + mesh.length[0], mesh.origin[1] + mesh.length[1],
                    mesh.origin[2] + mesh.length[2]};
      throw std::runtime_error(where(rows.source, rows.line[r]) + "the cell centre " + point(p) +
                               " is outside the mesh " + point(mesh.origin) + " to " + point(hi) +
                               ".");
    }
    const Vec3 x = cellCentre(mesh, cellIjk(mesh, c));
    for (int a = 0; a < 3; ++a)
      if (std::fabs(p[a] - x[a]) > 0.25 * h[a])
        throw std::runtime_error(where(rows.source, rows.line[r]) + "the cell centre " + point(p) +
                                 " lies in " + cellName(mesh, c) + " but " +
                                 number(std::fabs(p[a] - x[a]) / h[a]) + " cells away from its centre along " +
                                 kAxisNames[a] + ": the file's cells are not the mesh's.");
    if (lineOf[c])
      throw std::runtime_error(where(rows.source, rows.line[r]) + "the cell centre " + point(p) +
                               " gives " + cellName(mesh, c) + ", as line " +
                               std::to_string(lineOf[c]) + " does.");
    lineOf[c] = rows.line[r];
    f.alphaS[c] = 1.0 - rows.voidFraction[r];
    f.gasVelocity[c] = rows.gasVelocity[r];
    f.solidVelocity[c] = rows.solidVelocity[r];
  }
  const auto missing = std::find(lineOf.begin(), lineOf.end(), 0);
  if (missing != lineOf.end())
    throw std::runtime_error("Eulerian frame '" + rows.source + "' has " +
                             std::to_string(rows.size()) + " cells but the mesh " +
                             std::to_string(mesh.nx) + " x " + std::to_string(mesh.ny) + " x " +
                             std::to_string(mesh.nz) + " has " + std::to_string(N) + ": " +
                             std::to_string(std::count(lineOf.begin(), lineOf.end(), 0)) +
                             " missing, the first is " +
                             cellName(mesh, static_cast<int>(missing - lineOf.begin())) + ".");
  return f;
}

void writeEulerianFrame(const std::string &path, const Mesh &mesh, const EulerianFrame &frame) {
  const int N = mesh.numCells();
  if (static_cast<int>(frame.alphaS.size()) != N ||
      static_cast<int>(frame.gasVelocity.size()) != N ||
      static_cast<int>(frame.solidVelocity.size()) != N)
    throw std::invalid_argument("writeEulerianFrame: the frame does not match the mesh's cells");
  std::string out;
  out.reserve(static_cast<std::size_t>(N) * 120);
  char text[32];
  auto put = [&](double v, char sep) {
    const auto res = std::to_chars(text, text + sizeof text, v);
    out.append(text, res.ptr);
    out.push_back(sep);
  };
  for (int c = 0; c < N; ++c) {
    for (double x : mesh.cellCentre[c]) put(x, ' ');
    put(1.0 - frame.alphaS[c], ' ');
    for (double u : frame.gasVelocity[c]) put(u, ' ');
    put(frame.solidVelocity[c][0], ' ');
    put(frame.solidVelocity[c][1], ' ');
    put(frame.solidVelocity[c][2], '\n');
  }
  writeTextAtomically(path, out);
}

std::vector<Vec3> impliedSolidVelocity(const Mesh &mesh, const CsrMatrix &T, double dtRec) {
  std::vector<Vec3> u(T.n, Vec3{0.0, 0.0, 0.0});
  for (int j = 0; j < T.n; ++j)
    for (int64_t e = T.rowPtr[j]; e < T.rowPtr[j + 1]; ++e) {
      const int i = T.col[e];
      for (int a = 0; a < 3; ++a)
        u[i][a] += T.val[e] * (mesh.cellCentre[j][a] - mesh.cellCentre[i][a]) / dtRec;
    }
  return u;
}

// ---------------------------------------------------------------- tracing

void validateEulerianBuildOptions(const EulerianBuildOptions &o) {
  if (o.mesh.nx < 1 || o.mesh.ny < 1 || o.mesh.nz < 1)
    throw std::invalid_argument("the mesh needs at least one cell along each axis");
  if (!(o.dtRec > 0) || !std::isfinite(o.dtRec))
    throw std::invalid_argument("-dt_rec must be a positive time [s]");
  if (o.tracersPerCell < 1) throw std::invalid_argument("-tracers_per_cell must be at least 1");
  if (!(o.courant > 0) || o.courant > 1)
    throw std::invalid_argument("-tracer_courant must be in (0, 1]");
  if (!(o.slowCellFactor >= 0)) throw std::invalid_argument("-slow_cell_factor must be >= 0");
  if (!(o.emptyAlphaS >= 0 && o.emptyAlphaS < 1))
    throw std::invalid_argument("-empty_alpha_s must be in [0, 1)");
  if (!(o.supportSeed >= 0 && o.supportSeed < 1))
    throw std::invalid_argument("-scaling_support must be in [0, 1)");
  if (o.maxSupportRadius < 1) throw std::invalid_argument("-scaling_support_radius must be >= 1");
  if (o.scalingIterations < 0) throw std::invalid_argument("-scaling_iterations must be >= 0");
  if (!(o.scalingTolerance >= 0)) throw std::invalid_argument("-scaling_tolerance must be >= 0");
}

CsrMatrix traceShift(const EulerianFrame &now, const std::vector<double> &alphaNext,
                     const EulerianBuildOptions &opt, std::uint64_t frameIndex,
                     EulerianFrameStats *stats) {
  const BoxSpec &box = opt.mesh;
  const int N = box.numCells();
  if (static_cast<int>(now.alphaS.size()) != N || static_cast<int>(alphaNext.size()) != N ||
      static_cast<int>(now.solidVelocity.size()) != N)
    throw std::invalid_argument("traceShift: the frames do not match the mesh's cells");
  EulerianFrameStats st;
  const Vec3 h = box.spacing();
  const double V = h[0] * h[1] * h[2], edge = std::cbrt(V);
  const VelocityField field(box, now, opt.interpolation, opt.emptyAlphaS);
  std::vector<char> fullNext(N);
  for (int c = 0; c < N; ++c) fullNext[c] = alphaNext[c] > opt.emptyAlphaS;
  NearestCell nearestFull(box, fullNext);
  const std::array<int, 3> s = strata(opt.tracersPerCell);
  const double tracerShare = 1.0 / opt.tracersPerCell;

  // A generous bound on the sub-steps a tracer needs; more means the
  // velocities or dt_rec are not what the files' authors meant.
  const double hMin = std::min({h[0], h[1], h[2]});
  double uMax = 0.0;
  for (int c = 0; c < N; ++c)
    if (now.alphaS[c] > opt.emptyAlphaS)
      uMax = std::max(uMax, std::hypot(now.solidVelocity[c][0], now.solidVelocity[c][1],
                                       now.solidVelocity[c][2]));
  const double cellsPerStep = uMax * opt.dtRec / hMin;
  if (cellsPerStep > 1000)
    throw std::runtime_error("Eulerian frame '" + now.source + "': a solid velocity of " +
                             number(uMax) + " m/s moves " + number(cellsPerStep) +
                             " cells in dt_rec = " + number(opt.dtRec) +
                             " s; check the velocity columns and -dt_rec.");

  std::vector<int32_t> dest, src;
  std::vector<double> weight;
  std::vector<std::pair<int32_t, double>> local;
  for (int c0 = 0; c0 < N; ++c0) {
    if (!(now.alphaS[c0] > opt.emptyAlphaS)) continue; // empty: identity column
    local.clear();
    auto deposit = [&](int cell, const Vec3 &p, double w) {
      const int target = nearestFull(cell, p);
      if (target >= 0 && target != cell) ++st.redirected;
      local.emplace_back(target >= 0 ? target : cell, w);
    };
    const Vec3 u0 = now.solidVelocity[c0];
    const double speed = std::hypot(u0[0], u0[1], u0[2]);
    double stay = 0.0, boost = 1.0; // slow cell: share kept at home, velocity factor r
    bool slow = false;
    if (opt.slowCellFactor > 0) {
      const double tCross = speed > 0 ? edge / speed : std::numeric_limits<double>::infinity();
      if (tCross > opt.slowCellFactor * opt.dtRec) {
        ++st.slowCells;
        slow = true;
        const double r = tCross / (opt.slowCellFactor * opt.dtRec);
        stay = std::isfinite(r) ? 1.0 - 1.0 / r : 1.0;
        boost = std::isfinite(r) ? r : 0.0;
      }
    }
    const auto ijk = cellIjk(box, c0);
    const Vec3 centre = cellCentre(box, ijk);
    if (stay > 0) deposit(c0, centre, stay);
    if (stay < 1.0) {
      Xoshiro256 rng(opt.seed * 0x9E3779B97F4A7C15ull + frameIndex * static_cast<std::uint64_t>(N) +
                     static_cast<std::uint64_t>(c0));
      for (int a = 0; a < s[0]; ++a)
        for (int b = 0; b < s[1]; ++b)
          for (int d = 0; d < s[2]; ++d) {
            ++st.tracers;
            const int strat[3] = {a, b, d};
            Vec3 p;
            for (int ax = 0; ax < 3; ++ax)
              p[ax] = centre[ax] + ((strat[ax] + jitter(rng)) / s[ax] - 0.5) * h[ax];
            // A slow cell's moving share goes straight with r times the
            // cell's velocity (half a cell in dt_rec); other tracers follow
            // the field.
            Vec3 uLast = u0;
            double remaining = opt.dtRec;
            int steps = 0;
            while (remaining > 0.0 && steps < kMaxSubsteps) {
              Vec3 u = slow ? u0 : field.at(p, uLast);
              uLast = u;
              for (double &x : u) x *= boost;
              double dt = remaining;
              for (int ax = 0; ax < 3; ++ax)
                if (std::fabs(u[ax]) * dt > opt.courant * h[ax])
                  dt = opt.courant * h[ax] / std::fabs(u[ax]);
              for (int ax = 0; ax < 3; ++ax) p[ax] += u[ax] * dt;
              reflect(box, p);
              remaining = dt < remaining ? remaining - dt : 0.0;
              ++steps;
            }
            st.maxSubsteps = std::max(st.maxSubsteps, steps);
            deposit(box.locate(p), p, (1.0 - stay) * tracerShare);
          }
    }
    std::sort(local.begin(), local.end());
    const double w0 = V * now.alphaS[c0];
    for (std::size_t e = 0; e < local.size();) {
      const int32_t d = local[e].first;
      double w = 0.0;
      for (; e < local.size() && local[e].first == d; ++e) w += local[e].second;
      dest.push_back(d);
      src.push_back(c0);
      weight.push_back(w * w0);
    }
  }
  CsrMatrix T = shiftFromTransfers(N, dest, src, weight);

  // Cells holding solid at t_{k+1} that no tracer reached borrow the sources
  // of their nearest reached neighbours (ring 1, else 2), in proportion to
  // their own target; scaling then settles the amounts.
  std::vector<double> m(N), mNext(N), y;
  for (int c = 0; c < N; ++c) m[c] = V * now.alphaS[c], mNext[c] = V * alphaNext[c];
  multiply(T, m, y);
  std::vector<int32_t> fillDest, fillSrc;
  std::vector<double> fillWeight;
  for (int j = 0; j < N; ++j) {
    if (!fullNext[j] || y[j] > 0.0) continue;
    std::vector<int> hit;
    for (int R = 1; R <= 2 && hit.empty(); ++R)
      forEachInRing(box, cellIjk(box, j), R, [&](int c) {
        if (y[c] > 0.0) hit.push_back(c);
      });
    if (hit.empty()) {
      ++st.unreachedCells;
      continue;
    }
    ++st.filledCells;
    for (int n : hit)
      for (int64_t e = T.rowPtr[n]; e < T.rowPtr[n + 1]; ++e) {
        const int i = T.col[e];
        if (!(m[i] > 0.0)) continue;
        fillDest.push_back(j);
        fillSrc.push_back(i);
        fillWeight.push_back(T.val[e] * m[i] * (mNext[j] / y[n]) / static_cast<double>(hit.size()));
      }
  }
  // Rebuilds T with extra (destination, source, mass) transfers.
  auto addTransfers = [&](std::vector<int32_t> d, std::vector<int32_t> sr, std::vector<double> w) {
    if (d.empty()) return;
    for (int j = 0; j < N; ++j)
      for (int64_t e = T.rowPtr[j]; e < T.rowPtr[j + 1]; ++e) {
        d.push_back(j);
        sr.push_back(T.col[e]);
        w.push_back(T.val[e] * m[T.col[e]]);
      }
    T = shiftFromTransfers(N, std::move(d), std::move(sr), std::move(w));
  };
  addTransfers(std::move(fillDest), std::move(fillSrc), std::move(fillWeight));
  st.residualBefore = relativeMismatch(T, m, mNext);

  // Support seeds: a small share of each occupied column at home and at the
  // face neighbours that will hold solid, so that scaling can move solid one
  // cell further than the tracers did where the target asks for it.
  std::vector<int32_t> seedDest, seedSrc;
  std::vector<double> seedWeight;
  if (opt.supportSeed > 0 && opt.scalingIterations > 0)
    for (int i = 0; i < N; ++i) {
      if (!(m[i] > 0.0)) continue;
      const auto ijk = cellIjk(box, i);
      for (int R = 0; R <= 1; ++R) // the cell itself and its face neighbours
        forEachInRing(box, ijk, R, [&](int c) {
          const auto q = cellIjk(box, c);
          if (std::abs(q[0] - ijk[0]) + std::abs(q[1] - ijk[1]) + std::abs(q[2] - ijk[2]) > 1) return;
          if (!fullNext[c]) return;
          seedDest.push_back(c);
          seedSrc.push_back(i);
          seedWeight.push_back(opt.supportSeed * m[i]);
        });
    }
  addTransfers(std::move(seedDest), std::move(seedSrc), std::move(seedWeight));

  const double mTotal = std::accumulate(m.begin(), m.end(), 0.0);
  const double nextTotal = std::accumulate(mNext.begin(), mNext.end(), 0.0);
  st.massChange = mTotal > 0 ? std::fabs(nextTotal - mTotal) / mTotal : 0.0;
  st.iterations = scaleToTarget(T, m, mNext, opt.scalingIterations, opt.scalingTolerance);
  // Where the target cannot be met (a cell fills from sources further than
  // one cell away, or must lose more than its sources can send elsewhere),
  // widen the support around the rows still off target, two cells, then
  // three, and scale again.
  for (int R = 2; R <= opt.maxSupportRadius && opt.supportSeed > 0 && opt.scalingIterations > 0 &&
                  scaledMismatch(T, m, mNext) > opt.scalingTolerance;
       ++R) {
    st.supportRadius = R;
    st.iterations += scaleToTarget(T = widenSupport(T, m, mNext, fullNext, box, R, opt.supportSeed),
                                   m, mNext, opt.scalingIterations, opt.scalingTolerance);
  }
  st.residualAfter = relativeMismatch(T, m, mNext);
  if (stats) *stats = st;
  return T;
}

// ---------------------------------------------------------------- builder

double EulerianBuildReport::maxResidualBefore() const {
  return largest(frame, &EulerianFrameStats::residualBefore);
}
double EulerianBuildReport::meanResidualBefore() const {
  return mean(frame, &EulerianFrameStats::residualBefore);
}
double EulerianBuildReport::maxResidualAfter() const {
  return largest(frame, &EulerianFrameStats::residualAfter);
}
double EulerianBuildReport::meanResidualAfter() const {
  return mean(frame, &EulerianFrameStats::residualAfter);
}
double EulerianBuildReport::maxMassChange() const {
  return largest(frame, &EulerianFrameStats::massChange);
}

std::string EulerianBuildReport::summary() const {
  std::ostringstream s;
  s.precision(3);
  s << "Eulerian frames: " << files << " files, " << frames << " database frames of " << cells
    << " cells\n"
    << "tracing: " << tracersPerCell << " tracers per occupied cell (" << tracers
    << " in all), velocity " << interpolation << ", at most " << maxSubsteps
    << " sub-steps; slow cells " << slowCells << ", tracers moved out of cells empty at t_k+1 "
    << redirected << ", cells reached by no tracer " << filledCells + unreachedCells
    << " (filled from neighbours " << filledCells << ")\n"
    << "shift nonzeros per column: mean " << meanNnzPerColumn << " (occupied cells "
    << meanNnzPerOccupiedColumn << "), max " << maxNnzPerColumn << "; largest alpha_s "
    << maxAlphaS << "\n"
    << "scaling support: seeds " << supportSeed << " of each occupied cell at home and at its face "
    << "neighbours; widened to 2 cells in " << framesWidened[0] << " frames, to 3 cells in "
    << framesWidened[1] << "\n"
    << "mass mismatch |T a_k - a_k+1|_1 / |a_k|_1 per frame: traced max " << maxResidualBefore()
    << ", mean " << meanResidualBefore() << "; after scaling max " << maxResidualAfter()
    << ", mean " << meanResidualAfter() << " (tolerance " << scalingTolerance << ", at most "
    << scalingIterations << " iterations, used up to " << maxIterations << "; "
    << framesAboveTolerance << " frames above the tolerance); largest change of the total "
    << "solid volume between frames " << maxMassChange();
  return s.str();
}

EulerianFrameBuilder::EulerianFrameBuilder(const EulerianBuildOptions &options, FrameSink sink)
    : opt(options), sink(std::move(sink)) {
  validateEulerianBuildOptions(opt);
  rep.cells = opt.mesh.numCells();
  rep.tracersPerCell = opt.tracersPerCell;
  rep.interpolation = opt.interpolation == TracerInterpolation::cell ? "cell-constant" : "trilinear";
  rep.scalingTolerance = opt.scalingTolerance;
  rep.scalingIterations = opt.scalingIterations;
  rep.supportSeed = opt.supportSeed;
}

void EulerianFrameBuilder::add(EulerianFrame frame) {
  const int N = opt.mesh.numCells();
  if (static_cast<int>(frame.alphaS.size()) != N)
    throw std::invalid_argument("EulerianFrameBuilder: frame '" + frame.source +
                                "' does not match the mesh's cells");
  ++rep.files;
  for (double a : frame.alphaS) rep.maxAlphaS = std::max(rep.maxAlphaS, a);
  if (prev) {
    EulerianFrameStats st;
    FrameRecord rec;
    rec.shift = traceShift(*prev, frame.alphaS, opt, rep.frames, &st);
    rec.alphaS = std::move(prev->alphaS);
    std::vector<int> perColumn(N, 0);
    for (int32_t c : rec.shift.col) ++perColumn[c];
    for (int c = 0; c < N; ++c) {
      nnzTotal += perColumn[c];
      rep.maxNnzPerColumn = std::max(rep.maxNnzPerColumn, perColumn[c]);
      if (rec.alphaS[c] > opt.emptyAlphaS) nnzOccupied += perColumn[c], ++occupiedColumns;
    }
    rep.tracers += st.tracers;
    rep.slowCells += st.slowCells;
    rep.redirected += st.redirected;
    rep.filledCells += st.filledCells;
    rep.unreachedCells += st.unreachedCells;
    rep.maxSubsteps = std::max(rep.maxSubsteps, st.maxSubsteps);
    rep.maxIterations = std::max(rep.maxIterations, st.iterations);
    for (int r = 2; r <= std::min(st.supportRadius, 3); ++r) ++rep.framesWidened[r - 2];
    if (st.residualAfter - st.massChange > opt.scalingTolerance) ++rep.framesAboveTolerance;
    rep.frame.push_back(st);
    ++rep.frames;
    rep.meanNnzPerColumn = static_cast<double>(nnzTotal) / (static_cast<double>(N) * rep.frames);
    rep.meanNnzPerOccupiedColumn =
        occupiedColumns ? static_cast<double>(nnzOccupied) / occupiedColumns : 0.0;
    sink(rec);
  }
  prev = std::move(frame);
}

} // namespace rcfd
