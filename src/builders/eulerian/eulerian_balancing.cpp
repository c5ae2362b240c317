// Balancing of a traced Eulerian shift (eulerian_balancing.hpp).
#include "builders/eulerian/eulerian_balancing.hpp"

#include "builders/eulerian/eulerian_cells.hpp"
#include "database/csr.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

namespace rcfd {

using eulerian::cellIjk;
using eulerian::forEachInRing;

namespace {

// Scaling widens the support of the rows that miss their target by more than
// this share once it has stalled (the others converge with what they have).
constexpr double kStuckShare = 5e-2;

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

CsrMatrix balanceShift(CsrMatrix T, const std::vector<double> &m, const std::vector<double> &mNext,
                       const std::vector<char> &fullNext, const EulerianBuildOptions &opt,
                       EulerianFrameStats *stats) {
  EulerianFrameStats &st = *stats;
  const BoxSpec &box = opt.mesh;
  const int N = box.numCells();
  // Cells holding solid at t_{k+1} that no tracer reached borrow the sources
  // of their nearest reached neighbours (ring 1, else 2), in proportion to
  // their own target; scaling then settles the amounts.
  std::vector<double> y;
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

} // namespace rcfd
