// A database's frames as the solid's Markov chain over the cells
// (docs/markov.md).  Frame k's shift T_k is column-stochastic: T_k(j, i) is the
// probability that solid in cell i at t_k is in cell j at t_k + dt_rec, so a
// particle's cell is a time-dependent Markov chain that steps with T_0, T_1, ...
// (cycling after the last frame).  The mass share of frame k, alpha_k V / sum,
// is the distribution of a particle drawn from the bed's solid at t_k.
#pragma once

#include "rcfd/database.hpp"
#include "rcfd/handle.hpp"

#include <string>
#include <vector>

namespace rcfd {

class FrameChain {
public:
  /// Largest |column sum - 1| of a transfer matrix accepted: the load refuses
  /// columns off by more than -db_column_tolerance and rescales the rest, so a
  /// loaded database's columns sum to 1 to round-off.
  static constexpr double kColumnTolerance = 1e-12;

  /// Collective.  Builds each frame's transfer matrix (Database::shiftMatrix,
  /// the matrices the run's MAIJ kernel holds) and mass share; refuses, with
  /// one sentence, a database without shifts or whose frames do not conserve
  /// mass (a column not summing to 1 within kColumnTolerance, or a frame with
  /// no solid), before anything else is computed.  db must outlive the chain.
  PetscErrorCode setUp(const Database &db);

  const Database &database() const { return *db_; }
  int numFrames() const { return static_cast<int>(transfer_.size()); }
  double dt() const { return db_->metadata().dtRec; }
  /// The chain's cells on this rank (local indices, ascending): those that
  /// hold solid in some frame or whose row or column of some frame's shift is
  /// not the identity's.  Every other cell holds no solid in any frame and
  /// keeps what it has, receiving nothing: a distribution that starts on the
  /// solid is zero there for ever.  The propagations (ChainBlock) hold only
  /// these, which on the default bed are fewer than half of the cells (the
  /// freeboard is never reached), and give the same numbers to the bit: a
  /// row's entries are the same, in the same order (docs/markov.md, "Cost").
  const std::vector<PetscInt> &chainCells() const { return cells_; }
  PetscInt numChainCells() const { return static_cast<PetscInt>(cells_.size()); }
  /// All ranks' chain cells.
  PetscInt numChainCellsGlobal() const { return static_cast<PetscInt>(rowsAll_.size()); }
  /// Every rank's chain cells as PETSc rows (Layout), in chain order: chain
  /// cell c of all ranks is PETSc row chainRowsAll()[c].
  const std::vector<PetscInt> &chainRowsAll() const { return rowsAll_; }
  /// The transfer matrix of frame k (k taken modulo the number of frames)
  /// over the chain cells: row and column c are chain cell c of all ranks
  /// (this rank's in chainCells() order after the lower ranks').
  Mat transfer(long long k) const { return transfer_[static_cast<size_t>(k % numFrames())]; }
  /// Per chain cell of this rank, whether it is among `localCells` (local
  /// indices, e.g. a zone's localCells()).
  std::vector<char> chainMask(const std::vector<PetscInt> &localCells) const;
  /// Collective.  A zeroed vector over the chain cells (as transfer() moves).
  PetscErrorCode chainVector(Vec *x) const;
  /// Mass share of frame k (sums to 1; k modulo the number of frames).
  Vec massShare(long long k) const { return share_[static_cast<size_t>(k % numFrames())]; }
  /// The mean over the frames of the mass shares (sums to 1).
  Vec meanShare() const { return meanShare_; }
  /// The mean over the frames of alpha_s.
  Vec meanAlpha() const { return meanAlpha_; }
  /// Largest |column sum - 1| found over all frames.
  double columnError() const { return columnError_; }

  /// Collective.  Each frame's transfer for `columns` interleaved vectors
  /// (MAIJ, as the run's shift kernel holds them): block vectors of `columns`
  /// distributions over the cells step together.
  PetscErrorCode blockTransfers(PetscInt columns, std::vector<OwnedMat> *maij) const;
  /// Collective.  A zeroed block vector of `columns` distributions over the
  /// chain cells (cell-major: entry k * columns + c for chain cell k), as
  /// blockTransfers moves them.
  PetscErrorCode blockVector(PetscInt columns, Vec *x) const;

  /// How frames are averaged into one chain.
  enum class Average {
    Mass,  ///< sum_k T_k diag(m_k) diag(sum_k m_k)^-1: the mean mass flux over the mean mass
    Plain, ///< (1/K) sum_k T_k
  };
  /// Collective.  The time-averaged chain over all cells (a cell that never
  /// holds solid has an empty column with Average::Mass).  With Average::Mass
  /// the mean mass share is stationary, Q m = m, when each frame's shift moves
  /// alpha_k onto alpha_{k+1} and the last frame's onto the first's.
  PetscErrorCode averageChain(Average average, Mat *Q) const;

private:
  PetscErrorCode findChainCells(const std::vector<OwnedMat> &full);

  const Database *db_ = nullptr;
  std::vector<PetscInt> cells_;  // this rank's chain cells (local indices)
  std::vector<PetscInt> rowsAll_; // every rank's chain cells as PETSc rows, in chain order
  std::vector<OwnedMat> transfer_; // over the chain cells
  std::vector<OwnedVec> share_;
  OwnedVec meanShare_, meanAlpha_;
  double columnError_ = 0.0;
};

const char *averageName(FrameChain::Average a);

} // namespace rcfd
