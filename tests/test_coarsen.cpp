// Exact coarsening: coarse frames are column-stochastic and carry the coarse
// solid masses of frame k onto those of frame k+1 when the fine frames do;
// factor 1 gives the same frame bit for bit; two composed frames equal the two
// applied one after the other; quantised weights quantised again to the same
// bits come back bit for bit, and a coarsened quantised frame quantised again
// sums to exactly 1 in every column; bad factors are refused naming the axis.
#include "check.hpp"

#include "database/coarsen.hpp"
#include "database/quantise.hpp"

#include <cmath>
#include <stdexcept>

using namespace rcfd;

namespace {

std::vector<double> multiply(const CsrMatrix &T, const std::vector<double> &m) {
  std::vector<double> out(T.n, 0.0);
  for (int j = 0; j < T.n; ++j)
    for (int64_t e = T.rowPtr[j]; e < T.rowPtr[j + 1]; ++e) out[j] += T.val[e] * m[T.col[e]];
  return out;
}

std::vector<double> columnSums(const CsrMatrix &T) {
  std::vector<double> s(T.n, 0.0);
  for (int64_t e = 0; e < T.nnz(); ++e) s[T.col[e]] += T.val[e];
  return s;
}

} // namespace

int main() {
  // A 4 x 1 x 2 box of 0.1 m cells.  Frame a moves solid around the loop
  // 0 -> 1 -> 5 -> 4 -> 0 (half of each cell's solid moves on), frame b is its
  // reverse, and both are mass-consistent with the alphas below.
  BoxSpec fine;
  fine.nx = 4;
  fine.ny = 1;
  fine.nz = 2;
  fine.length = {0.4, 0.1, 0.2};
  const std::vector<double> volume(8, 1e-3);
  FrameRecord a;
  a.alphaS = {0.4, 0.2, 0.0, 0.1, 0.3, 0.1, 0.0, 0.0};
  a.shift = shiftFromTransfers(8, {0, 1, 1, 5, 5, 4, 4, 0, 3}, {0, 0, 1, 1, 5, 5, 4, 4, 3},
                               {0.2, 0.2, 0.1, 0.1, 0.05, 0.05, 0.15, 0.15, 0.1});
  const std::vector<double> m0 = {0.4e-3, 0.2e-3, 0, 0.1e-3, 0.3e-3, 0.1e-3, 0, 0};
  const std::vector<double> m1 = multiply(a.shift, m0);
  // Space: factor 2 along x: coarse cells {0,1}, {2,3} below, {4,5}, {6,7} above.
  const CoarseBox coarse = coarsenBox(fine, {2, 1, 1});
  RCFD_CHECK(coarse.box.nx == 2 && coarse.box.nz == 2 && coarse.coarseOf[5] == 2 && coarse.coarseOf[3] == 1);
  const FrameRecord c = coarsenFrame(a, volume, coarse);
  RCFD_CHECK_CLOSE(c.alphaS[0], 0.3, 1e-15);  // (0.4 + 0.2) / 2
  RCFD_CHECK_CLOSE(c.alphaS[2], 0.2, 1e-15);  // (0.3 + 0.1) / 2
  for (double s : columnSums(c.shift)) RCFD_CHECK_CLOSE(s, 1.0, 1e-15);
  // T_c m_c,k = m_c,k+1, with m_c the sums of the fine masses.
  auto sumUp = [&](const std::vector<double> &m) {
    std::vector<double> mc(4, 0.0);
    for (int i = 0; i < 8; ++i) mc[coarse.coarseOf[i]] += m[i];
    return mc;
  };
  const std::vector<double> moved = multiply(c.shift, sumUp(m0)), expected = sumUp(m1);
  for (int I = 0; I < 4; ++I) RCFD_CHECK_CLOSE(moved[I], expected[I], 1e-18);
  // Coarse cell 0 (fine 0, 1: 0.6 g) sends to coarse 2 what fine 1 sends to 5: 0.1 g of 0.6 g.
  double t20 = -1;
  for (int64_t e = c.shift.rowPtr[2]; e < c.shift.rowPtr[3]; ++e)
    if (c.shift.col[e] == 0) t20 = c.shift.val[e];
  RCFD_CHECK_CLOSE(t20, 0.1 / 0.6, 1e-15);
  // An empty coarse cell keeps an identity column.
  RCFD_CHECK(columnSums(c.shift)[3] == 1.0);
  // Factor 1: the same frame, bit for bit.
  const FrameRecord same = coarsenFrame(a, volume, coarsenBox(fine, {1, 1, 1}));
  RCFD_CHECK(same.alphaS == a.alphaS && same.shift.val == a.shift.val && same.shift.col == a.shift.col);
  // Time: (T_b T_a) m = T_b (T_a m), column-stochastic, alpha of the first frame.
  FrameRecord b;
  b.alphaS = std::vector<double>(8, 0.0);
  for (int i = 0; i < 8; ++i) b.alphaS[i] = m1[i] / 1e-3;
  b.shift = shiftFromTransfers(8, {0, 4, 4, 5, 5, 1, 1, 0}, {0, 0, 4, 4, 5, 5, 1, 1}, {1, 1, 1, 1, 1, 1, 1, 1});
  const FrameRecord two = composeFrames(a, b);
  const std::vector<double> once = multiply(two.shift, m0), twice = multiply(b.shift, m1);
  for (int i = 0; i < 8; ++i) RCFD_CHECK_CLOSE(once[i], twice[i], 1e-18);
  for (double s : columnSums(two.shift)) RCFD_CHECK_CLOSE(s, 1.0, 1e-15);
  RCFD_CHECK(two.alphaS == a.alphaS);
  // A quantised frame (as a database with weight_bits holds it; shares of 1/7
  // and 1/3 are no multiples of 2^-16) quantised again to its bits is the same
  // frame bit for bit: what rcfd coarsen -factor 1,1,1 does to it by default.
  FrameRecord q = a;
  q.shift = shiftFromTransfers(8, {0, 1, 5, 1, 2, 5, 4, 6, 3}, {0, 0, 0, 1, 1, 5, 5, 5, 3},
                               {0.1, 0.2, 0.4, 0.3, 0.6, 1, 1, 1, 1});
  quantiseWeights(&q.shift, 16);
  const CsrMatrix quantisedOnce = q.shift;
  RCFD_CHECK(quantisedOnce.val[0] != 1.0 / 7.0);
  quantiseWeights(&q.shift, 16);
  RCFD_CHECK(q.shift.rowPtr == quantisedOnce.rowPtr && q.shift.col == quantisedOnce.col &&
             q.shift.val == quantisedOnce.val);
  // Coarsened, its weights are no longer multiples of 2^-16; quantised again,
  // every column sums to exactly 1 and the coarse frame keeps the total mass.
  FrameRecord qc = coarsenFrame(q, volume, coarse);
  bool offTheGrid = false;
  for (double w : qc.shift.val) offTheGrid |= std::ldexp(w, 16) != std::floor(std::ldexp(w, 16));
  RCFD_CHECK(offTheGrid);
  quantiseWeights(&qc.shift, 16);
  for (double s : columnSums(qc.shift)) RCFD_CHECK(s == 1.0);
  double before = 0.0, after = 0.0;
  for (double m : sumUp(m0)) before += m;
  for (double m : multiply(qc.shift, sumUp(m0))) after += m;
  RCFD_CHECK_CLOSE(after, before, 1e-12 * before);
  // Factors that do not divide, or below 1, are refused naming the axis.
  for (const std::array<int, 3> f : {std::array<int, 3>{3, 1, 1}, std::array<int, 3>{1, 0, 1}}) {
    bool refused = false;
    try {
      coarsenBox(fine, f);
    } catch (const std::invalid_argument &e) {
      refused = std::string(e.what()).find("the coarsening factor along") != std::string::npos;
    }
    RCFD_CHECK(refused);
  }
  return RCFD_TEST_RESULT();
}
