// Tracing of an Eulerian frame (eulerian_frames.hpp, traceShift): tracers
// started on a jittered pattern in every occupied cell move through the frozen
// solid velocity field for dt_rec; the shift they give is then balanced
// (eulerian_balancing.hpp).
#include "builders/eulerian/eulerian_frames.hpp"

#include "base/random.hpp"
#include "builders/eulerian/eulerian_balancing.hpp"
#include "builders/eulerian/eulerian_cells.hpp"
#include "database/csr.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <limits>
#include <stdexcept>
#include <tuple>
#include <utility>

namespace rcfd {

using eulerian::cellIjk;
using eulerian::cellCentre;
using eulerian::number;
using eulerian::forEachInRing;

namespace {

// Far more sub-steps than a tracer can need once velocities moving more than
// 1000 cells per dt_rec are refused; only a guard against endless loops.
constexpr int kMaxSubsteps = 100000;

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

/// Mirror a point that crossed the vessel's wall back in: the vessel's level is
/// the distance to the wall (a lower bound of it, exact on a plane, a
/// cylinder's or a cone's side) and its gradient the wall's normal, so
/// p - 2 level n lies as far inside as p lay outside, and a tracer bounces off
/// the wall as off the box's.  Where that is still outside (a rim, where two
/// walls meet) p stays: it ends, as before, in the nearest cell with solid.
void reflectAtVessel(const Vessel &vessel, const BoxSpec &box, double step, Vec3 &p) {
  const double level = vessel.level(p);
  if (!(level < 0.0)) return;
  Vec3 normal;
  double norm2 = 0.0;
  for (int a = 0; a < 3; ++a) {
    Vec3 up = p, down = p;
    up[a] += step;
    down[a] -= step;
    normal[a] = (vessel.level(up) - vessel.level(down)) / (2.0 * step);
    norm2 += normal[a] * normal[a];
  }
  if (!(norm2 > 0.0)) return;
  const double scale = -2.0 * level / std::sqrt(norm2);
  Vec3 mirrored = p;
  for (int a = 0; a < 3; ++a) mirrored[a] += scale * normal[a];
  reflect(box, mirrored);
  if (vessel.level(mirrored) > 0.0) p = mirrored;
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

} // namespace

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
  // In a vessel a cut cell holds solid in its inside part only.
  auto volumeOf = [&](int c) { return opt.cellVolume.empty() ? V : opt.cellVolume[c]; };
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
  const bool walled = !opt.vessel.isWholeBox();
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
              if (walled) reflectAtVessel(opt.vessel, box, 1e-3 * hMin, p);
              remaining = dt < remaining ? remaining - dt : 0.0;
              ++steps;
            }
            st.maxSubsteps = std::max(st.maxSubsteps, steps);
            deposit(box.locate(p), p, (1.0 - stay) * tracerShare);
          }
    }
    std::sort(local.begin(), local.end());
    const double w0 = volumeOf(c0) * now.alphaS[c0];
    for (std::size_t e = 0; e < local.size();) {
      const int32_t d = local[e].first;
      double w = 0.0;
      for (; e < local.size() && local[e].first == d; ++e) w += local[e].second;
      dest.push_back(d);
      src.push_back(c0);
      weight.push_back(w * w0);
    }
  }
  std::vector<double> m(N), mNext(N);
  for (int c = 0; c < N; ++c) m[c] = volumeOf(c) * now.alphaS[c], mNext[c] = volumeOf(c) * alphaNext[c];
  CsrMatrix T = balanceShift(shiftFromTransfers(N, dest, src, weight), m, mNext, fullNext, opt, &st);
  if (stats) *stats = st;
  return T;
}

} // namespace rcfd
