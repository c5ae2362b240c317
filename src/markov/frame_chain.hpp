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
  /// The transfer matrix of frame k (k taken modulo the number of frames).
  Mat transfer(long long k) const { return transfer_[static_cast<size_t>(k % numFrames())]; }
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
  /// cells (cell-major: entry i * columns + c), as blockTransfers moves them.
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
  const Database *db_ = nullptr;
  std::vector<OwnedMat> transfer_;
  std::vector<OwnedVec> share_;
  OwnedVec meanShare_, meanAlpha_;
  double columnError_ = 0.0;
};

const char *averageName(FrameChain::Average a);

} // namespace rcfd
