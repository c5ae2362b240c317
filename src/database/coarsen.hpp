// Exact coarsening of a database (issue 14), in space and in time, on the
// CSR frames of the file format (natural cell order, serial, PETSc-free).
//
// Space: coarse cells are blocks of fx x fy x fz fine cells.  A coarse frame is
// the Galerkin product T_c = R T_k P, with R summing fine cells into coarse ones
// and P = D_k R^T D_c^-1 spreading a coarse cell's solid over its fine cells in
// proportion to their solid in frame k (D_k = diag(alpha_k V), D_c = R D_k).
// T_c is column-stochastic, and T_c m_c,k = m_c,k+1 whenever T_k m_k = m_k+1:
// the coarse database is as mass-consistent as the fine one.  A coarse cell's
// alpha_s is the volume-weighted mean of its fine cells'.
//
// Time: two consecutive frames become one of 2 dt_rec, T = T_k+1 T_k with frame
// k's alpha_s; the product of column-stochastic matrices is column-stochastic.
#pragma once

#include "rcfd/frames.hpp"
#include "rcfd/mesh.hpp"

#include <array>
#include <vector>

namespace rcfd {

/// The coarse box of `fine` with `factor` fine cells per coarse cell along x, y, z,
/// and the coarse cell of every fine cell.  Throws std::invalid_argument naming the
/// axis when a factor is below 1 or does not divide the cell count.
struct CoarseBox {
  BoxSpec box;
  std::vector<int> coarseOf; ///< natural fine cell -> natural coarse cell
  int cells = 0;             ///< coarse cells when not the whole box (a vessel's), else 0
  int numCells() const { return cells > 0 ? cells : box.numCells(); }
};
CoarseBox coarsenBox(const BoxSpec &fine, const std::array<int, 3> &factor);

/// A vessel's mesh (Mesh::isMasked, docs/vessels.md) coarsened: the coarse box's
/// cells that hold a fine cell, in the box's order, each with its fine cells'
/// volume and their volume-weighted centre; faces between two coarse cells
/// with the fine faces' open areas summed (boundary faces likewise); the same
/// vessel.  `coarse` maps the fine mesh's cells to the coarse mesh's.
Mesh coarsenVesselMesh(const Mesh &fine, const std::array<int, 3> &factor, CoarseBox *coarse);

/// The frame on the coarse cells (see above).  `fineVolume` per fine cell.
FrameRecord coarsenFrame(const FrameRecord &fine, const std::vector<double> &fineVolume, const CoarseBox &coarse);

/// The frame of two steps: first `a`, then `b`; alpha_s of `a`.
FrameRecord composeFrames(const FrameRecord &a, const FrameRecord &b);

} // namespace rcfd
