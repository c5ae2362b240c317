// Eulerian frames in a vessel (docs/vessels.md): the frames are given on the
// box; tracing and scaling run there with each cell's inside volume, and the
// frames written are the vessel's cells only (eulerian_frames.hpp).
#include "builders/eulerian/eulerian_frames.hpp"

#include <stdexcept>

namespace rcfd {

std::vector<double> insideVolumes(const Mesh &vessel) {
  if (!vessel.onBoxLattice()) throw std::invalid_argument("insideVolumes: the vessel's mesh is not cut from a box");
  std::vector<double> v(static_cast<std::size_t>(vessel.boxSpec().numCells()), 0.0);
  for (int c = 0; c < vessel.numCells(); ++c) v[vessel.boxCell(c)] = vessel.cellVolume[c];
  return v;
}

FrameRecord onVesselCells(const FrameRecord &boxFrame, const Mesh &vessel) {
  const CsrMatrix &T = boxFrame.shift;
  if (T.n != vessel.boxSpec().numCells() || boxFrame.alphaS.size() != static_cast<std::size_t>(T.n))
    throw std::invalid_argument("onVesselCells: the frame is not of the vessel's box");
  FrameRecord out;
  const int n = vessel.numCells();
  out.alphaS.resize(n);
  out.shift.n = n;
  out.shift.rowPtr.assign(1, 0);
  for (int b = 0; b < T.n; ++b) { // rows in box order: the vessel's cells are numbered in it
    const int r = vessel.cellOfBoxCell(b);
    for (int64_t e = T.rowPtr[b]; e < T.rowPtr[b + 1]; ++e) {
      const int c = vessel.cellOfBoxCell(T.col[e]);
      if ((r < 0) != (c < 0) && T.val[e] != 0.0)
        throw std::runtime_error("the traced shift moves solid between a cell inside the vessel and one outside");
      if (r < 0 || c < 0) continue;
      out.shift.col.push_back(c);
      out.shift.val.push_back(T.val[e]);
    }
    if (r < 0) continue;
    out.alphaS[r] = boxFrame.alphaS[b];
    out.shift.rowPtr.push_back(static_cast<int64_t>(out.shift.col.size()));
  }
  return out;
}

} // namespace rcfd
