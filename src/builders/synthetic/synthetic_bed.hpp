// Embedded default database: a deterministic *kinematic stand-in* for a
// bubbling fluidized bed.  It is not a physical model (no gas, no momentum
// balance); it moves Lagrangian parcels with a prescribed velocity field so
// that the frames look like a bubbling bed (rising voids, a free surface, an
// empty freeboard, solids circulation) and the shift matrices are exact.
// See docs/synthetic-bed.md for the construction and its limits, and
// docs/synthetic.md for other gas velocities and how stationary the bed is.
#pragma once

#include "rcfd/frames.hpp"
#include "rcfd/mesh.hpp"
#include "rcfd/vessel.hpp"
#include "base/constants.hpp"

#include <cstdint>
#include <vector>

namespace rcfd {

/// Options of the synthetic bed.  Lengths in m, times in s, z up, gravity -z;
/// positions are measured from the box origin.  Defaults: the paper's bed.
struct SyntheticBedOptions {
  BoxSpec box;              ///< 0.2 x 0.05 x 0.7 m, 40 x 10 x 140 cells
  /// The whole box, or one vertical cylinder (no caps) inside the box's
  /// cross-section: the bed then runs in a square of the cylinder's area and
  /// its parcels are mapped into the cylinder by an equal-area map; or any
  /// other vessel (a conical bottom, a box minus tubes): the bed runs in a host
  /// box of the vessel's volume, mapped into it by a volume-preserving map
  /// (builders/synthetic/vessel_map.hpp, docs/vessels.md).  The frames are on
  /// vesselMesh(vessel, box)'s cells.
  Vessel vessel;
  int numFrames = 300;      ///< K frames are written
  double dtRec = 5e-3;      ///< time between frames
  std::uint64_t seed = 1;   ///< the whole run is a function of the options and this seed
  double warmUpTime = 1.0;  ///< simulated time before frame 0 (developed bubbling)
  double maxSubstep = 5e-3; ///< kinematic time step is dtRec / ceil(dtRec / maxSubstep)

  // Dense phase.
  double bedHeight = 0.25;  ///< settled height of the dense phase (without voids)
  double packing = 0.55;    ///< alpha_s of the dense phase; also the largest alpha_s written
  int parcelsPerCell = 8;   ///< parcels in a full dense cell; alpha_s comes in steps of packing / this
  double dispersion = 1e-4; ///< emulsion dispersion (sideways swaps, vertical walk) [m^2/s]
  double surfaceDiffusivity = 1e-3; ///< levelling of the bed surface, dh/dt = D lap(h) [m^2/s]

  // Bubbles: nucleation at the distributor, growth with height, rise, eruption.
  double nucleationRate = 2500.0; ///< new bubbles per second and m^2 of distributor
  /// steady: one bubble every 1 / (rate x area), into nucleationStrips strips of the
  /// distributor along x in shuffled rounds (a steadier bed, docs/synthetic.md);
  /// poisson: a Poisson process at random places (earlier versions' bed, bit for bit).
  enum class Nucleation { steady, poisson } nucleation = Nucleation::poisson;
  int nucleationStrips = 8;       ///< strips of the distributor along x for steady nucleation,
                                  ///< about as wide as a bubble (2.5 cm here)
  double initialDiameter = 0.015; ///< D0: size a new bubble opens to at the distributor
  double maxDiameter = 0.05;      ///< asymptote of the growth law D(h) = D0 + (Dmax - D0) h / (h + L);
                                  ///< coalescence may exceed it, up to half the wider bed side
  double growthLength = 0.1;      ///< L in the growth law
  double riseCoefficient = 0.711; ///< rise velocity U = c sqrt(g D)
  double wakeFraction = 0.25;     ///< share of a new bubble's sphere that is wake, in [0, 0.5]
  double bubbleWander = 0.05;     ///< rms lateral wander velocity of bubbles
  double centreDrift = 0.1;       ///< lateral drift to the bed's mid-plane, as a share of U
  double dipoleCutoff = 2.0;      ///< the flow around a bubble is ignored beyond this many radii
  double eruptionRoof = 0.25;     ///< a bubble erupts when its roof is thinner than this many radii
  double ejectionSpeed = 1.2;     ///< roof parcels leave at this multiple of U
  double gravity = kGravity;
};

/// What a generation produced.  Counts and means cover the recorded frames
/// (not the warm-up).
struct SyntheticBedReport {
  long parcels = 0;           ///< number of parcels
  double parcelVolume = 0.0;  ///< solid volume of one parcel [m^3]
  double solidVolume = 0.0;   ///< total solid volume [m^3]
  int substepsPerFrame = 0;
  double maxAlpha = 0.0;      ///< largest alpha_s over all cells and states t_0 .. t_K
  double meanBedHeight = 0.0; ///< time mean of the column-averaged surface height (voids included)
  long bubblesNucleated = 0;
  long bubblesErupted = 0;
  int maxCellJump = 0;        ///< largest per-axis cell distance travelled by a parcel in one dtRec
  double wrapMismatchL1 = 0.0;       ///< sum_c |alpha_K - alpha_0| V_c [m^3]
  double wrapMismatchRelative = 0.0; ///< wrapMismatchL1 / solidVolume
  /// Per recorded frame k (state t_k): the column-averaged surface height and
  /// the solid's centre of gravity height [m], for stationarity checks.
  std::vector<double> surfaceHeight, centreOfGravity;
};

/// Throws std::invalid_argument with a sentence naming the first bad option.
/// `vesselMesh`, when given, is vesselMesh(options.vessel, options.box), not cut
/// again (a vessel with many cut cells takes seconds to cut); the same below.
void validateSyntheticBedOptions(const SyntheticBedOptions &options, const Mesh *vesselMesh = nullptr);

/// Run the kinematic bed and hand frames k = 0 .. numFrames-1 to `sink`, one
/// at a time: frame k holds alpha_s at t_k and the exact shift t_k -> t_{k+1}
/// built from parcel identities (so T_k alpha_k = alpha_{k+1} to round-off).
/// Serial; deterministic for given options.  Throws std::invalid_argument for
/// bad options.
SyntheticBedReport generateSyntheticBed(const SyntheticBedOptions &options, const FrameSink &sink,
                                        const Mesh *vesselMesh = nullptr);

/// The same run without frames: only the report, whose per-frame series
/// (surface height, centre of gravity) are those generateSyntheticBed gives for
/// the same options.  For long spans (stationarity, docs/synthetic.md): it skips
/// the shifts, most of a frame's cost.  Throws std::invalid_argument for bad options.
SyntheticBedReport generateSyntheticBedSeries(const SyntheticBedOptions &options, const Mesh *vesselMesh = nullptr);

} // namespace rcfd
