// Database frames from DEM particle snapshots.
//
// Counting rule (ParticleBuildOptions::volume, cell_shares.hpp): a particle
// p has shares w_c(p) >= 0 of its volume in the cells c, summing to 1 --
// overlap: the part of the sphere each cell holds; centre: all of it in the
// cell of its centre (BoxSpec::locate after the AxisMap).  So
//   alpha_s(c) = (sum over p of w_c(p) pi/6 d_p^3) / V_c.
// Under the centre rule alpha_s can exceed the packing limit, even 1, in
// cells not much larger than a particle; the report counts such cells, the
// values are not clipped (clipping would break the exact shift identity
// below).  A particle whose centre lies outside the mesh is in no cell; it
// is counted in the report.
//
// Shift: particles are matched by id between t_k and t_{k+1}, and
//   T_k(j, i) = (mass in cell i at t_k found in cell j at t_{k+1})
//               / (mass in cell i at t_k),
// assembled by shiftFromTransfers from each particle's transfers pi_p(j, i)
// m_p, where pi_p is a split of the particle between its cells at t_k
// (shares w_i(p, t_k)) and at t_{k+1} (shares w_j(p, t_{k+1})): sum_j pi_p(j, i)
// = w_i(p, t_k), sum_i pi_p(j, i) = w_j(p, t_{k+1}).  Any such split keeps a
// column summing the mass cell i holds at t_k and row j of T_k m_k the mass
// cell j holds at t_{k+1}.  The split used: the share a cell holds at both
// times stays (pi(i, i) = min(w_i(t_k), w_i(t_{k+1}))), the rest moves in
// proportion to what the cells lose and gain.  The plain product w_i w_j
// would move half of a particle resting on a cell face across that face
// every frame: numerical mixing where the bed does not move.
// T_k moves *mass*: T_k m_k = m_{k+1} holds to round-off for the cell
// masses m whenever no particle appears, vanishes, crosses the mesh boundary
// or changes mass.  With a single particle density the cell mass is
// rho * V_c * alpha_s, so T_k alpha_k = alpha_{k+1} holds as well.  With
// several densities the two differ: a column of T then shares the cell's
// mass, not its volume, and T alpha_k != alpha_{k+1} in general.  Shifting
// mass is the consistent choice for rcfd, which propagates fraction masses;
// the report gives both residuals.
//
// Particles that vanish between t_k and t_{k+1} (id gone), or whose centre
// leaves the mesh, are treated as staying in their cells at t_k: their mass
// is a self-transfer i -> i, so the column still shares all of cell i's mass
// and the other particles' shares are unchanged.  The propagated state then
// keeps that mass where alpha_{k+1} no longer has it; the residual shows it
// in that cell.  Particles that appear (new id) or enter the mesh are in no
// column of T_k; they are part of alpha_{k+1} and of T_{k+1}.  Counts and
// masses of all four kinds are in the report.
#pragma once

#include "particles/cell_shares.hpp"
#include "particles/particle_dump.hpp"
#include "rcfd/frames.hpp"
#include "rcfd/mesh.hpp"
#include "rcfd/vessel.hpp"

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace rcfd {

struct ParticleBuildOptions {
  BoxSpec mesh;                                               // in rcfd coordinates (after `axes`)
  AxisMap axes;                                               // file -> rcfd coordinates, z up
  int stride = 1;                                             // dt_rec = stride * snapshot interval
  std::size_t first = 0;                                      // window of snapshot indices,
  std::size_t last = std::numeric_limits<std::size_t>::max(); // both ends included
  SnapshotReadOptions read; // default density for files without density/mass
  ParticleVolume volume = ParticleVolume::Centre; // cells a particle's volume is counted in
  /// A vessel cut out of `mesh` (vesselMesh; not owned, outlives the builder), or
  /// none: the frames are then on its cells, alpha_s over their inside volumes.
  /// A particle whose centre is outside it (its shapes) is outside the mesh; under
  /// the overlap rule the parts of a sphere in outside cells go to its centre's cell.
  const Mesh *vessel = nullptr;
};

struct ParticleBuildReport {
  ParticleVolume volume = ParticleVolume::Centre; // the counting rule used
  std::size_t snapshots = 0; // snapshots used
  std::size_t frames = 0;    // = snapshots - 1
  int cells = 0;
  std::size_t particles = 0; // in the first snapshot used
  double totalMass = 0.0;    // kg, first snapshot, inside and outside the mesh

  double meanNnzPerColumn = 0.0;         // all columns of all frames (empty cells: 1)
  double meanNnzPerOccupiedColumn = 0.0; // columns of cells holding solid at t_k
  int maxNnzPerColumn = 0;

  std::size_t appeared = 0, vanished = 0;        // ids new at t_{k+1} / gone at t_{k+1}
  double appearedMass = 0.0, vanishedMass = 0.0; // kg, summed over frames
  std::size_t enteredMesh = 0, leftMesh = 0;     // same id, centre crossed the mesh boundary
  double enteredMeshMass = 0.0, leftMeshMass = 0.0;
  std::size_t outside = 0; // particles outside the mesh, summed over snapshots
  std::size_t maxOutsidePerSnapshot = 0;

  double maxAlphaS = 0.0;
  std::size_t cellsAlphaAtLeastOne = 0; // (cell, snapshot) pairs with alpha_s >= 1

  double maxAlphaResidual = 0.0; // max over k, j of |(T_k alpha_k)_j - alpha_{k+1, j}|
  double maxMassResidual = 0.0;  // max over k, j of |(T_k m_k)_j - m_{k+1, j}|, kg

  /// Multi-line, human-readable.
  std::string summary() const;
};

/// The snapshot indices a build uses: first, first + stride, ... up to
/// min(last, available - 1).  Throws std::invalid_argument on a bad window
/// or stride.
std::vector<std::size_t> selectSnapshots(std::size_t available, const ParticleBuildOptions &opt);

/// Incremental builder: feed the selected snapshots in time order; from the
/// second one on, each call emits one frame (alpha_s at the previous
/// snapshot and the shift to this one) through the sink.  It keeps only the
/// previous snapshot's (id, cell, mass) list and alpha_s, never a snapshot.
class ParticleFrameBuilder {
public:
  ParticleFrameBuilder(const ParticleBuildOptions &opt, FrameSink sink);

  /// Throws std::runtime_error on a duplicate id or a timestep that does not
  /// increase.
  void add(const ParticleSnapshot &snap);
  const ParticleBuildReport &report() const { return rep; }

private:
  struct Placement {
    int64_t id;
    double mass;
    std::size_t first, count; // its cells in the snapshot's share list; none: outside the mesh
  };
  struct Snapshot {
    std::vector<Placement> particles; // sorted by id
    std::vector<CellShare> shares;
  };

  void place(const ParticleSnapshot &snap);
  void toVesselCells(int centreBoxCell);
  CsrMatrix shiftTo(const Snapshot &next);
  void account(const CsrMatrix &T, const std::vector<double> &alphaK,
               const std::vector<double> &massK);

  ParticleBuildOptions opt;
  FrameSink sink;
  double cellVolume = 0.0;
  int numCells = 0;
  Vessel vesselShape; // of opt.vessel, for which particles are inside it
  bool cellsVessel = false; // opt.vessel is of the cells particles reached (VisitedCells)
  ParticleBuildReport rep;
  int64_t prevTimestep = -1;
  std::size_t nnzTotal = 0, nnzOccupied = 0, occupiedColumns = 0;
  // Previous and current snapshot, reduced to what the shift needs.
  Snapshot prev, cur;
  std::vector<CellShare> scratch;
  std::vector<double> alphaPrev, alphaCur, massPrev, massCur;
  FrameRecord frame;
};

/// Reads the selected files one at a time (plain or gzip dump, or CSV) and
/// streams the frames to `sink`.  `files` is the whole time-ordered list;
/// only the files picked by selectSnapshots are read.  Needs at least two.
ParticleBuildReport buildFramesFromSnapshots(const std::vector<std::string> &files,
                                             const ParticleBuildOptions &opt,
                                             const FrameSink &sink);

} // namespace rcfd
