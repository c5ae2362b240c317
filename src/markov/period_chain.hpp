// The chain over one period of the frames (docs/markov.md, "The period
// chain"): P = S_{K-1} ... S_1 S_0, where S_k is frame k's transfer followed by
// the chain's steps (a size class's drift; the carry at the wrap).  P moves
// a distribution at frame 0 to where it is one pass through the database
// later, so its stationary distribution is the chain's periodic stationary
// distribution at frame 0: for the bulk, frame 0's mass share m_0 when every
// frame moves alpha_k onto alpha_{k+1} and the wrap meets frame 0 (exactly,
// with the carry), where the time-averaged chain only gives the mean share
// approximately; for a size class, where the class lives at frame 0 in the
// linearised chain.  P is never formed (it is dense where the frames are
// sparse): SLEPc sees a shell whose product applies the K steps.
#pragma once

#include "markov/frame_chain.hpp"
#include "markov/operator_step.hpp"
#include "markov/spectrum.hpp"

#include <vector>

namespace rcfd {

/// The period chain's numbers (PeriodSpectrum without its distribution, so
/// that they copy).
struct PeriodNumbers {
  int states = 0;               ///< cells holding solid at frame 0 that the chain does not keep for ever
  int absorbing = 0;            ///< cells holding solid at frame 0 that it keeps for ever (P(i, i) = 1)
  double leftOut = 0.0;         ///< frame 0's mass share of those
  double lambda1 = 0.0;         ///< 1 for a chain that keeps its distributions on the states
  double lambda2Re = 0.0, lambda2Im = 0.0, lambda2 = 0.0; ///< the next-largest eigenvalue, its modulus
  double relaxationTime = 0.0;  ///< -K dt_rec / ln |lambda2| [s] (infinite when |lambda2| >= 1)
  int iterations = 0;           ///< SLEPc's restarts
  long long products = 0;       ///< products with P (each K frames' steps)
  double seconds = 0.0;         ///< wall time of the solve
  double l1 = 0.0, max = 0.0;   ///< |stationary - m_0| (m_0 on the states, summing to 1): sum and largest
  double residual = 0.0;        ///< |P m_0 - m_0|_1 over the chain's cells: the database's check at frame 0
};

struct PeriodSpectrum : PeriodNumbers {
  OwnedVec stationary; ///< over all cells (0 off the states), sums to 1
};

/// The height (against gravity) of a distribution's centre, `share` per cell
/// of `mesh` in natural order (Layout::gatherToAll): where a class's
/// stationary distribution lies against the bulk's is its segregation.
double centreHeight(const Mesh &mesh, const Vec3 &gravity, const std::vector<double> &share);

class PeriodChain {
public:
  PeriodChain() = default;
  PeriodChain(const PeriodChain &) = delete;
  PeriodChain &operator=(const PeriodChain &) = delete;
  /// Collective.  The states are the chain's cells holding solid at frame 0
  /// but those a chain keeps for ever: a cell whose solid a period returns to
  /// it whole (P(i, i) = 1) is an eigenvector of P of its own, and with several
  /// the eigenvalue 1 is not simple.  The candidates are `absorbing` (per own
  /// cell, local index; ChainSpectrum's absorbingLocal: solid that never moves
  /// in the frames), each followed through one period by solve() with the
  /// chain's steps (a class's drift may move what the frames leave).  Cells
  /// empty at frame 0 are passed through within the period but are no
  /// states: a distribution at frame 0 holds nothing there.  chain must
  /// outlive this.
  PetscErrorCode setUp(const FrameChain &chain, const std::vector<char> &absorbing);
  /// Collective.  P's two largest eigenvalues and its stationary distribution
  /// with `steps` after each frame's transfer (none: the frames alone), by
  /// `solver` (-markov_eps_*); `what` names the chain in a refusal.  P
  /// restricted to the states loses what a period takes elsewhere (the
  /// periodic wrap's solid landing in cells frame 0 holds empty): lambda1 is
  /// then below 1 and its eigenvector the quasi-stationary distribution.
  PetscErrorCode solve(ChainEigensolver &solver, const std::vector<ChainStep *> &steps, const char *what,
                       PeriodSpectrum *out);
  int numStates() const { return numStates_; }

private:
  static PetscErrorCode mult(Mat P, Vec in, Vec out);
  PetscErrorCode applyPeriod(); // x_ <- P x_ over all chain cells
  PetscErrorCode chooseStates(const std::vector<ChainStep *> &steps);

  const FrameChain *chain_ = nullptr;
  // Positions among this rank's chain cells: the cells holding solid at frame
  // 0, candidates to be kept for ever apart, and the chain's states.
  std::vector<PetscInt> held_, candidates_, states_;
  PetscInt numCandidates_ = 0, firstCandidate_ = 0; // all ranks'; this rank's first as a block column
  int numStates_ = 0, absorbing_ = 0;
  double leftOut_ = 0.0;
  std::vector<ChainStep *> steps_;
  OwnedVec x_, y_; // over the chain's cells (one column)
  long long products_ = 0;
};

} // namespace rcfd
