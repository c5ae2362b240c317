// The time-averaged chain's spectrum with SLEPc: its stationary distribution
// (the eigenvector of eigenvalue 1) and the second-largest eigenvalue modulus,
// which sets how fast the averaged chain forgets where it started.
#pragma once

#include "markov/frame_chain.hpp"

// SLEPc's handle, declared as slepceps.h does, so that this header needs no SLEPc.
typedef struct _p_EPS *EPS;

namespace rcfd {

struct ChainSpectrum {
  int cells = 0;                  ///< states of the chain: cells whose mean alpha_s is at least alphaMeanMin
  double leftOut = 0.0;           ///< the mean mass share of the other cells
  int absorbing = 0;              ///< cells holding solid that never moves in a frame it is there (Q(i, i) = 1)
  double absorbingShare = 0.0;    ///< their mean mass share
  std::vector<char> absorbingLocal; ///< per own cell (local index): whether it is absorbing
  double lambda1 = 0.0;           ///< the eigenvalue closest to 1 (1 for a stochastic matrix)
  double lambda2Re = 0.0, lambda2Im = 0.0; ///< the next-largest in modulus
  double lambda2 = 0.0;           ///< its modulus
  double relaxationTime = 0.0;    ///< -dt_rec / ln lambda2 [s] (infinite when lambda2 >= 1)
  int iterations = 0;             ///< SLEPc's restarts
  OwnedVec stationary;            ///< over all cells (0 where no solid), sums to 1
  double l1 = 0.0, max = 0.0;     ///< |stationary - mean mass share|: sum and largest
  double residual = 0.0;          ///< |Q m - m|_1 over all cells, m the mean mass share
};

/// The two largest eigenvalues in modulus of a chain and the eigenvector of
/// the one closest to 1 (the stationary one).
struct LargestEigenpairs {
  double lambda1 = 0.0;                    ///< the eigenvalue closest to 1
  double lambda2Re = 0.0, lambda2Im = 0.0; ///< the next-largest in modulus
  double lambda2 = 0.0;                    ///< its modulus
  int iterations = 0;                      ///< SLEPc's restarts
  OwnedVec first;                          ///< lambda1's eigenvector, scaled to sum 1
};

/// Collective.  |a - b| of two distributions over the same cells: its sum and largest entry.
PetscErrorCode distributionDistance(Vec a, Vec b, double *l1, double *max);

/// SLEPc's EPS for a chain (the averaged chain's matrix, or the period chain's
/// shell): non-Hermitian, largest magnitude, nev 2, tolerance 1e-10; its
/// options take a prefix (e.g. -markov_eps_tol, -markov_eps_view), read by
/// setFromOptions before any database is loaded.
class ChainEigensolver {
public:
  ChainEigensolver() = default;
  ~ChainEigensolver();
  ChainEigensolver(const ChainEigensolver &) = delete;
  ChainEigensolver &operator=(const ChainEigensolver &) = delete;
  /// Collective.
  PetscErrorCode setFromOptions(MPI_Comm comm, const char *prefix);
  /// Collective.  Solves the averaged chain (FrameChain::averageChain) and
  /// compares its stationary distribution with the database's mean mass share.
  /// The chain's states are the cells whose mean alpha_s is at least
  /// alphaMeanMin and that are not absorbing: a cell whose solid never moves in
  /// the frames it holds solid (a dead corner, or a splash into the freeboard
  /// that stays until the last frame) is an absorbing state of the averaged
  /// chain, and with several the eigenvalue 1 is not simple.
  /// The chain restricted to the states loses what leaves them: its largest
  /// eigenvalue is then a little below 1 and its eigenvector the
  /// quasi-stationary distribution.
  PetscErrorCode solve(const FrameChain &chain, FrameChain::Average average, double alphaMeanMin, ChainSpectrum *out);
  /// Collective.  The two largest eigenvalues of the n x n chain A (an
  /// assembled matrix or a shell), `what` naming it in a refusal; the solver's
  /// dimensions from its options are kept for the next call.
  PetscErrorCode largest(Mat A, const char *what, LargestEigenpairs *out);

private:
  EPS eps = nullptr;
  std::string prefix_;
  PetscInt ncv_ = PETSC_DEFAULT, mpd_ = PETSC_DEFAULT; // from the options
};

} // namespace rcfd
