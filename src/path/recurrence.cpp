#include "path/recurrence.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <stdexcept>
#include <string>

namespace rcfd {

namespace {

// The work is K^2/2 frame pairs times nLocal cells (2.5e9 pair-cells for
// K = 300 and the paper's 56,000 cells), so the loops are blocked:
//  - cells are taken in panels of kPanelCells; a panel is copied once,
//    transposed (cell-major, frames contiguous) and pre-scaled by the cell
//    weight, so the innermost loop runs over contiguous frames and needs no
//    multiplication by the volume;
//  - within a panel, a kTileI x kTileJ tile of frame pairs keeps its
//    accumulators in registers while it sweeps the panel's cells: per cell it
//    loads kTileI + kTileJ values for kTileI * kTileJ pairs.  The lanes run over
//    frames j, not over cells, so no floating-point reduction has to be
//    reordered and the compiler vectorises the tile at plain -O2;
//  - tiles are visited by blocks of kBlockTiles tiles j (about 256 frames), so
//    that the block's part of the panel stays in L2 while all tiles i stream
//    past it;
//  - only tiles that hold a pair i < j are computed (symmetry).
// K = 300 takes about 0.7 s on one core at -O2, K = 3,000 about 80 s
// (docs/paths.md).

// Lanes of the tile: GCC and Clang vector extensions (SSE2 at plain -O2, AVX
// when the build enables it); other compilers, or -DRCFD_SCALAR_LANES, get
// scalar lanes of width 1.
#if defined(__GNUC__) && !defined(RCFD_SCALAR_LANES)
#if defined(__AVX__)
constexpr int kLanes = 4;
#else
constexpr int kLanes = 2;
#endif
typedef double Lanes __attribute__((vector_size(kLanes * sizeof(double))));
typedef std::uint64_t Bits __attribute__((vector_size(kLanes * sizeof(double))));
inline Lanes loadLanes(const double *p) {
  Lanes v;
  std::memcpy(&v, p, sizeof v); // unaligned load
  return v;
}
// Clearing the sign bit is one instruction; max(d, -d) would be two.
inline Lanes absLanes(Lanes d) {
  return reinterpret_cast<Lanes>(reinterpret_cast<Bits>(d) & ~(std::uint64_t(1) << 63));
}
inline Lanes maxLanes(Lanes x, Lanes y) { return x > y ? x : y; }
#else
constexpr int kLanes = 1;
using Lanes = double;
inline Lanes loadLanes(const double *p) { return *p; }
inline Lanes absLanes(Lanes d) { return std::fabs(d); }
inline Lanes maxLanes(Lanes x, Lanes y) { return x > y ? x : y; }
#endif

// Tile shape: 4 frames i times 3 lane groups of frames j keeps 12 accumulators
// plus two temporaries within the 16 vector registers of x86-64.
constexpr int kTileI = 4;
constexpr int kGroupsJ = 3;
constexpr int kTileJ = kGroupsJ * kLanes;
constexpr int kBlockTiles = 256 / kTileJ; // j tiles per block (about 256 frames)
constexpr std::size_t kPanelCells = 256;

// Pre-scaling the values by a per-cell weight w turns the volume factor into
// a plain difference: V (a - b)^2 = (sqrt(V) a - sqrt(V) b)^2 and
// V |a - b| = |V a - V b| because V > 0.
struct SquareSum {
  static double weight(double volume) { return std::sqrt(volume); }
  static Lanes add(Lanes acc, Lanes d) { return acc + d * d; }
  static double combine(double x, double y) { return x + y; }
};
struct AbsSum {
  static double weight(double volume) { return volume; }
  static Lanes add(Lanes acc, Lanes d) { return acc + absLanes(d); }
  static double combine(double x, double y) { return x + y; }
};
struct AbsMax {
  static double weight(double) { return 1.0; }
  static Lanes add(Lanes acc, Lanes d) { return maxLanes(absLanes(d), acc); }
  static double combine(double x, double y) { return x > y ? x : y; }
};

// One tile over the nb cells of a panel (row stride `stride` doubles), folded
// into the K x K result; entries of padded frames (>= K) and pairs i >= j are
// dropped.
template <class Op>
void tile(const double *panel, int stride, std::size_t nb, int i0, int j0, int K, double *out) {
  Lanes acc[kTileI][kGroupsJ];
  for (auto &r : acc)
    for (auto &a : r) a = Lanes{};
  for (std::size_t c = 0; c < nb; ++c) {
    const double *row = panel + c * static_cast<std::size_t>(stride);
#pragma GCC unroll 8
    for (int ii = 0; ii < kTileI; ++ii) {
      const double a = row[i0 + ii];
#pragma GCC unroll 8
      for (int g = 0; g < kGroupsJ; ++g)
        acc[ii][g] = Op::add(acc[ii][g], loadLanes(row + j0 + g * kLanes) - a);
    }
  }
  double res[kTileI][kTileJ];
  std::memcpy(res, acc, sizeof res);
  for (int ii = 0; ii < kTileI; ++ii) {
    const int i = i0 + ii;
    if (i >= K) break;
    for (int jj = 0; jj < kTileJ; ++jj) {
      const int j = j0 + jj;
      if (j <= i || j >= K) continue;
      double &o = out[static_cast<std::size_t>(i) * K + j];
      o = Op::combine(o, res[ii][jj]);
    }
  }
}

template <class Op>
void partialUpper(const std::vector<const double *> &frames, const double *volume, std::size_t n,
                  double *out) {
  const int K = static_cast<int>(frames.size());
  // Pad the frame count to whole tiles in both directions; padded frames are
  // zero and their entries are dropped.
  const int unit = std::lcm(kTileI, kTileJ);
  const int Kp = (K + unit - 1) / unit * unit;
  const int blockJ = kBlockTiles * kTileJ;
  const std::size_t panelCells = std::min(kPanelCells, n);
  std::vector<double> panel(panelCells * Kp, 0.0);
  std::vector<double> w(panelCells);

  for (std::size_t c0 = 0; c0 < n; c0 += kPanelCells) {
    const std::size_t nb = std::min(kPanelCells, n - c0);
    for (std::size_t c = 0; c < nb; ++c) w[c] = volume ? Op::weight(volume[c0 + c]) : 1.0;
    for (int k = 0; k < K; ++k) {
      const double *f = frames[k] + c0;
      // x - x is 0 for finite x and NaN for NaN or Inf: a cheap guard, needed
      // because the max norm would silently skip NaN.
      double probe = 0.0;
      for (std::size_t c = 0; c < nb; ++c) {
        panel[c * Kp + k] = w[c] * f[c];
        probe += f[c] - f[c];
      }
      if (probe != 0.0)
        throw std::invalid_argument("recurrencePartial: frame " + std::to_string(k) +
                                    " holds NaN or Inf values near local cell " +
                                    std::to_string(c0));
    }
    for (int jb = 0; jb < Kp; jb += blockJ) {
      const int jEnd = std::min(jb + blockJ, Kp);
      for (int i0 = 0; i0 < jEnd; i0 += kTileI) {
        // First tile that holds a j > i0.
        const int jFirst = std::max(jb, (i0 + 1) / kTileJ * kTileJ);
        for (int j0 = jFirst; j0 < jEnd; j0 += kTileJ)
          tile<Op>(panel.data(), Kp, nb, i0, j0, K, out);
      }
    }
  }
}

} // namespace

const char *recurrenceNormName(RecurrenceNorm norm) {
  switch (norm) {
  case RecurrenceNorm::SqrDiff: return "sqrDiff";
  case RecurrenceNorm::Euclidean: return "euclidean";
  case RecurrenceNorm::AbsDiff: return "absDiff";
  case RecurrenceNorm::Max: return "max";
  }
  return "unknown";
}

RecurrenceNorm parseRecurrenceNorm(const std::string &name) {
  for (RecurrenceNorm n : {RecurrenceNorm::SqrDiff, RecurrenceNorm::Euclidean,
                           RecurrenceNorm::AbsDiff, RecurrenceNorm::Max})
    if (name == recurrenceNormName(n)) return n;
  throw std::invalid_argument("unknown recurrence norm \"" + name +
                              "\": expected sqrDiff, euclidean, absDiff or max");
}

bool recurrenceNeedsMaxReduction(RecurrenceNorm norm) { return norm == RecurrenceNorm::Max; }

void recurrencePartial(RecurrenceNorm norm, const std::vector<const double *> &frames,
                       const double *cellVolume, std::size_t nLocal,
                       std::vector<double> &partial) {
  const int K = static_cast<int>(frames.size());
  partial.assign(static_cast<std::size_t>(K) * K, 0.0);
  if (K == 0 || nLocal == 0) return;
  for (int k = 0; k < K; ++k)
    if (!frames[k])
      throw std::invalid_argument("recurrencePartial: frame " + std::to_string(k) +
                                  " is a null pointer");
  if (norm != RecurrenceNorm::Max) {
    if (!cellVolume)
      throw std::invalid_argument(std::string("recurrencePartial: the ") +
                                  recurrenceNormName(norm) + " norm needs the cell volumes");
    for (std::size_t c = 0; c < nLocal; ++c)
      if (!(cellVolume[c] > 0.0))
        throw std::invalid_argument("recurrencePartial: cell " + std::to_string(c) +
                                    " has a non-positive volume");
  }

  double *out = partial.data();
  switch (norm) {
  case RecurrenceNorm::SqrDiff:
  case RecurrenceNorm::Euclidean: partialUpper<SquareSum>(frames, cellVolume, nLocal, out); break;
  case RecurrenceNorm::AbsDiff: partialUpper<AbsSum>(frames, cellVolume, nLocal, out); break;
  case RecurrenceNorm::Max: partialUpper<AbsMax>(frames, nullptr, nLocal, out); break;
  }
  // Mirror, so that the partial is a valid symmetric matrix on its own.
  for (int i = 0; i < K; ++i)
    for (int j = i + 1; j < K; ++j)
      partial[static_cast<std::size_t>(j) * K + i] = partial[static_cast<std::size_t>(i) * K + j];
}

void recurrenceFinish(RecurrenceNorm norm, int K, std::vector<double> &m) {
  if (K < 0 || m.size() != static_cast<std::size_t>(K) * static_cast<std::size_t>(K))
    throw std::invalid_argument("recurrenceFinish: the matrix holds " + std::to_string(m.size()) +
                                " values, not K * K for K = " + std::to_string(K));
  const auto at = [&](int i, int j) -> double & { return m[static_cast<std::size_t>(i) * K + j]; };
  double largest = 0.0;
  for (int i = 0; i < K; ++i) {
    at(i, i) = 0.0;
    for (int j = i + 1; j < K; ++j) {
      double v = at(i, j);
      if (!std::isfinite(v) || v < 0.0)
        throw std::invalid_argument("recurrenceFinish: entry (" + std::to_string(i) + ", " +
                                    std::to_string(j) + ") is " + std::to_string(v) +
                                    "; a frame holds NaN or Inf values");
      if (norm == RecurrenceNorm::Euclidean) v = std::sqrt(v);
      at(i, j) = v;
      largest = std::max(largest, v);
    }
  }
  for (int i = 0; i < K; ++i)
    for (int j = i + 1; j < K; ++j) {
      const double v = largest > 0.0 ? at(i, j) / largest : 0.0;
      at(i, j) = v;
      at(j, i) = v;
    }
}

std::vector<double> recurrenceMatrix(RecurrenceNorm norm, const std::vector<const double *> &frames,
                                     const double *cellVolume, std::size_t nLocal) {
  std::vector<double> m;
  recurrencePartial(norm, frames, cellVolume, nLocal, m);
  recurrenceFinish(norm, static_cast<int>(frames.size()), m);
  return m;
}

} // namespace rcfd
