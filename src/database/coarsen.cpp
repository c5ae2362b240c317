#include "database/coarsen.hpp"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

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

Mesh coarsenVesselMesh(const Mesh &fine, const std::array<int, 3> &factor, CoarseBox *coarse) {
  const CoarseBox boxes = coarsenBox(fine.boxSpec(), factor); // checks the factors
  std::vector<int> cells; // coarse box cells holding a fine cell, ascending
  for (int c = 0; c < fine.numCells(); ++c) cells.push_back(boxes.coarseOf[fine.boxCell(c)]);
  std::vector<int> ofFine = cells;
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  Mesh m = Mesh::masked(boxes.box, cells, fine.vessel());
  for (int &C : ofFine) C = m.cellOfBoxCell(C);
  const int nc = static_cast<int>(cells.size()); // m.numCells() counts volumes, still to fill
  m.cellVolume.assign(nc, 0.0);
  m.cellCentre.assign(nc, Vec3{0.0, 0.0, 0.0});
  for (int c = 0; c < fine.numCells(); ++c) {
    const double v = fine.cellVolume[c];
    m.cellVolume[ofFine[c]] += v;
    for (int a = 0; a < 3; ++a) m.cellCentre[ofFine[c]][a] += v * fine.cellCentre[c][a];
  }
  for (int C = 0; C < nc; ++C)
    for (double &x : m.cellCentre[C]) x /= m.cellVolume[C];
  // Keyed by (owner, axis) and (patch, owner): the box mesh's orders.
  auto axisOf = [](const Vec3 &s) { return s[0] != 0.0 ? 0 : s[1] != 0.0 ? 1 : 2; };
  std::map<std::pair<int, int>, std::pair<int, Vec3>> faces, walls;
  for (int f = 0; f < fine.numFaces(); ++f) {
    const int o = ofFine[fine.faceOwner[f]], n = ofFine[fine.faceNeighbour[f]];
    if (o == n) continue;
    auto &face = faces.try_emplace({o, axisOf(fine.faceArea[f])}, n, Vec3{0.0, 0.0, 0.0}).first->second;
    for (int a = 0; a < 3; ++a) face.second[a] += fine.faceArea[f][a];
  }
  for (int f = 0; f < fine.numBoundaryFaces(); ++f) {
    auto &wall = walls.try_emplace({fine.boundaryPatch[f], ofFine[fine.boundaryOwner[f]]}, 0, Vec3{0.0, 0.0, 0.0})
                     .first->second;
    for (int a = 0; a < 3; ++a) wall.second[a] += fine.boundaryArea[f][a];
  }
  for (const auto &[key, face] : faces) {
    m.faceOwner.push_back(key.first);
    m.faceNeighbour.push_back(face.first);
    m.faceArea.push_back(face.second);
  }
  for (const auto &[key, wall] : walls) {
    m.boundaryOwner.push_back(key.second);
    m.boundaryPatch.push_back(key.first);
    m.boundaryArea.push_back(wall.second);
  }
  *coarse = boxes;
  coarse->coarseOf = std::move(ofFine);
  coarse->cells = nc;
  return m;
}

FrameRecord coarsenFrame(const FrameRecord &fine, const std::vector<double> &fineVolume, const CoarseBox &coarse) {
  const int nf = static_cast<int>(fine.alphaS.size()), nc = coarse.numCells();
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
