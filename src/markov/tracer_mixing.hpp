// How long a tracer started in one cell takes to spread over the bed, from the
// frames themselves (docs/markov.md, "Mixing time").  Each tracer and the bulk
// step together with the frames in order, cycling from frame 0; the tracer's
// concentration in a cell is its share of the tracer over the bulk's share of
// the solid (both propagated, so a perfectly mixed tracer reads 1 everywhere).
#pragma once

#include "markov/frame_chain.hpp"
#include "markov/operator_step.hpp"

#include <vector>

namespace rcfd {

struct MixingSettings {
  double tolerance = 0.05;  ///< mixed: every counted cell within this of 1
  double alphaMin = 0.1;    ///< counted cells: the propagated bulk holds alpha_s at least this
  double horizon = 120.0;   ///< give up after this time [s]
  std::vector<int> starts;  ///< natural cells the tracers start in (at frame 0)
  /// One more tracer after those of `starts` when not empty: the solid in
  /// these own cells (local indices, a zone's localCells()) at frame 0, as a
  /// run's tracer given in a zone (-scalar_NAME_zones).
  std::vector<PetscInt> startZone;
  bool zoneStart = false; ///< whether that tracer is followed (its zone may hold no cell on a rank)
  /// Per own cell (local index; empty: none): cells left out of the deviation,
  /// the averaged chain's absorbing cells (ChainSpectrum::absorbingLocal),
  /// whose solid never moves and so never takes up a tracer.
  std::vector<char> excluded;
};

struct MixingResult {
  /// Per start (the cells', then the zone's): the mixing time [s], or NaN when
  /// not mixed within the horizon.
  std::vector<double> time;
  /// Per step n = 1, 2, ...: the mean and the largest over the starts of the
  /// deviation max_i |c_i - 1| at t = n dt_rec (of the cells' tracers).
  std::vector<double> meanDeviation, worstDeviation;
  /// Per step: the zone's tracer's deviation (MixingSettings::zoneStart).
  std::vector<double> zoneDeviation;
  int confirm = 0; ///< steps the deviation had to stay within the tolerance
};

/// Collective.  The mixing time of a start is t_n = n dt_rec for the first
/// step n from which the deviation stays within the tolerance for K steps (K
/// frames: one pass through the database).  Stops when every start is mixed or
/// at the horizon.  The tracers and the bulk step with the frame's shift and
/// then `steps` (with a size class's drift: the class's chain, the bulk then
/// the class's solid from the mean composition at frame 0).
PetscErrorCode tracerMixing(const FrameChain &chain, const MixingSettings &settings, MixingResult *out,
                            const std::vector<ChainStep *> &steps = {});

/// The natural cell at the horizontal centre of every stride-th layer (along
/// gravity, from the bottom) of a box mesh whose alpha_s at frame 0 is at least
/// alphaMin; all cells holding at least alphaMin at frame 0 when `all` or when
/// the mesh is not a box.
std::vector<int> mixingStarts(const Mesh &mesh, const Vec3 &gravity, const std::vector<double> &alpha0,
                              double alphaMin, bool all, int stride = 1);

} // namespace rcfd
