#include "database/coarsen.hpp"

#include <stdexcept>
#include <string>

namespace rcfd {

CoarseBox coarsenBox(const BoxSpec &fine, const std::array<int, 3> &factor) {
  const int n[3] = {fine.nx, fine.ny, fine.nz};
  for (int a = 0; a < 3; ++a)
    if (factor[a] < 1 || n[a] % factor[a] != 0)
      throw std::invalid_argument(std::string("the coarsening factor along ") + "xyz"[a] + " is " +
                                  std::to_string(factor[a]) + "; it must be at least 1 and divide the " +
                                  std::to_string(n[a]) + " cells along that axis");
  CoarseBox c;
  c.box = fine;
  c.box.nx = fine.nx / factor[0];
  c.box.ny = fine.ny / factor[1];
  c.box.nz = fine.nz / factor[2];
  c.coarseOf.resize(fine.numCells());
  for (int k = 0; k < fine.nz; ++k)
    for (int j = 0; j < fine.ny; ++j)
      for (int i = 0; i < fine.nx; ++i)
        c.coarseOf[fine.cellIndex(i, j, k)] = c.box.cellIndex(i / factor[0], j / factor[1], k / factor[2]);
  return c;
}

FrameRecord coarsenFrame(const FrameRecord &fine, const std::vector<double> &fineVolume, const CoarseBox &coarse) {
  const int nf = static_cast<int>(fine.alphaS.size()), nc = coarse.box.numCells();
  if (nc == nf) return fine; // factor 1: the same frame, bit for bit
  FrameRecord out;
  out.alphaS.assign(nc, 0.0);
  std::vector<double> coarseVolume(nc, 0.0);
  for (int i = 0; i < nf; ++i) {
    out.alphaS[coarse.coarseOf[i]] += fine.alphaS[i] * fineVolume[i];
    coarseVolume[coarse.coarseOf[i]] += fineVolume[i];
  }
  for (int I = 0; I < nc; ++I) out.alphaS[I] /= coarseVolume[I];
  // Entry (j, i) carries T(j, i) m_i of fine cell i's solid to j: from I(i) to
  // J(j).  shiftFromTransfers sums these per coarse column and divides by the
  // column's total, sum over i in I of m_i: that is R T D_k R^T D_c^-1.
  std::vector<int32_t> dest, src;
  std::vector<double> weight;
  dest.reserve(fine.shift.nnz());
  src.reserve(fine.shift.nnz());
  weight.reserve(fine.shift.nnz());
  for (int j = 0; j < nf; ++j)
    for (int64_t e = fine.shift.rowPtr[j]; e < fine.shift.rowPtr[j + 1]; ++e) {
      const int i = fine.shift.col[e];
      const double carried = fine.shift.val[e] * fine.alphaS[i] * fineVolume[i];
      if (carried == 0.0) continue;
      dest.push_back(coarse.coarseOf[j]);
      src.push_back(coarse.coarseOf[i]);
      weight.push_back(carried);
    }
  out.shift = shiftFromTransfers(nc, std::move(dest), std::move(src), std::move(weight));
  return out;
}

FrameRecord composeFrames(const FrameRecord &a, const FrameRecord &b) {
  const int n = static_cast<int>(a.alphaS.size());
  if (static_cast<int>(b.alphaS.size()) != n || a.shift.n != n || b.shift.n != n)
    throw std::invalid_argument("composeFrames: the two frames have different numbers of cells");
  // Row j of T_b T_a is the sum over entries (j, l) of T_b of T_b(j, l) times row l of T_a.
  std::vector<int32_t> dest, src;
  std::vector<double> weight;
  for (int j = 0; j < n; ++j)
    for (int64_t e = b.shift.rowPtr[j]; e < b.shift.rowPtr[j + 1]; ++e) {
      const int l = b.shift.col[e];
      for (int64_t f = a.shift.rowPtr[l]; f < a.shift.rowPtr[l + 1]; ++f) {
        dest.push_back(j);
        src.push_back(a.shift.col[f]);
        weight.push_back(b.shift.val[e] * a.shift.val[f]);
      }
    }
  FrameRecord out;
  out.alphaS = a.alphaS;
  out.shift = shiftFromTransfers(n, std::move(dest), std::move(src), std::move(weight));
  return out;
}

} // namespace rcfd
