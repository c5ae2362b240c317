// Database frames from Eulerian CFD-DEM frames: the per-cell ASCII files
// rCFD users already have.  Serial and PETSc-free; every fault throws
// std::runtime_error with one sentence naming the file (and line).
//
// The files: eulerian_reader.cpp (frame files read and placed on the mesh),
// eulerian_writer.cpp (frames written, the velocity a shift implies),
// eulerian_tracing.cpp (tracers through the solid velocity field),
// eulerian_balancing.cpp (the traced shift made mass-consistent),
// eulerian_frame_builder.cpp (options, the builder and its report);
// eulerian_cells.hpp holds what they share about the mesh's cells.
//
// File format (one file per frame, one line per cell, any cell order):
//   x y z alpha Ux Uy Uz Usx Usy Usz
// x y z: cell centre [m]; alpha: VOID fraction (alpha_s = 1 - alpha);
// U: gas velocity; Us: mass-averaged solid velocity [m/s].  Numbers are
// separated by blanks; blank lines and lines starting with '#' are skipped.
//
// Shift by tracing (docs/database-format.md, "Building from Eulerian frames"):
// each occupied cell c0 of frame k starts n tracers on a jittered stratified
// pattern (a seeded xoshiro stream per frame and cell), each of weight
// w0 / n with w0 = V alpha_s(c0).  A tracer moves for dt_rec through the
// frozen solid velocity field of frame k in sub-steps of at most `courant`
// cells; walls reflect it.  The velocity at a tracer is that of the cell it
// is in (default; an empty cell keeps the tracer's last velocity) or
// trilinear between cell centres, weighted by alpha_s so that empty cells do
// not drag it to zero.  Slow cells (t_cross = V^(1/3)/|Us(c0)| >
// slowCellFactor * dt_rec) keep (1 - 1/r) of each tracer's weight at home,
// r = t_cross / (slowCellFactor dt_rec), and move the rest straight with
// r Us(c0).  A tracer ending in a cell that is empty at t_{k+1} goes to the
// nearest cell that is not.  A cell that holds solid at t_{k+1} but that no
// tracer reached borrows the sources of its nearest reached neighbours.
//
// Mass consistency: every occupied column gets small seeds (supportSeed of
// its solid) at home and at its face neighbours that hold solid at t_{k+1};
// then iterative proportional scaling (scale rows to the target
// V alpha_{k+1}, renormalise columns to 1) makes T_k (V alpha_k) =
// V alpha_{k+1}: plain sweeps first, Newton steps on the row log-factors when
// sweeps stall (scaleToTarget, src/database/csr.hpp); rows that still miss their target by
// more than 5 % get seeds from 2, then 3 cells away and scaling resumes.
#pragma once

#include "rcfd/frames.hpp"
#include "rcfd/mesh.hpp"
#include "rcfd/vessel.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace rcfd {

/// The rows of one Eulerian frame file in file order, before any mesh.
struct EulerianRows {
  std::string source;            // the file, for messages
  std::vector<int> line;         // 1-based line number of each row
  std::vector<Vec3> centre;      // x y z
  std::vector<double> voidFraction;
  std::vector<Vec3> gasVelocity, solidVelocity;
  std::size_t size() const { return centre.size(); }
};

/// One Eulerian frame on a box mesh, natural cell order.
struct EulerianFrame {
  std::string source;               // the file it was read from, for messages (may be empty)
  std::vector<double> alphaS;       // 1 - void fraction
  std::vector<Vec3> gasVelocity;    // U
  std::vector<Vec3> solidVelocity;  // Us
};

/// Parses a frame file.  Throws naming the file and line for a wrong number
/// of columns, a value that is not a finite number, or a void fraction
/// outside [0, 1]; and for a file that cannot be read or holds no cell.
EulerianRows readEulerianRows(const std::string &path);

/// How to lay the box mesh over the cell centres.  Unset parts come from
/// the centres: per axis, the distinct coordinates must be equally spaced
/// (spacing h, count n); the box is then [min - h/2, max + h/2] with n cells.
struct EulerianMeshRequest {
  std::optional<std::array<int, 3>> cells;
  std::optional<Vec3> lo, hi;
};
BoxSpec resolveEulerianMesh(const EulerianMeshRequest &request, const EulerianRows &rows);

/// Places every row in the mesh cell holding its centre.  Throws naming the
/// file and line for a centre outside the mesh or away from the centre of
/// its mesh cell (more than a quarter cell along an axis), for two lines
/// giving the same cell, and naming the file and the first missing cell
/// when the file does not cover every cell.
EulerianFrame mapOntoMesh(const EulerianRows &rows, const BoxSpec &mesh);

inline EulerianFrame readEulerianFrame(const std::string &path, const BoxSpec &mesh) {
  return mapOntoMesh(readEulerianRows(path), mesh);
}

/// Writes a frame in the same format, natural cell order, numbers in their
/// shortest exact form (reading the file back gives the same doubles, and
/// alpha_s = 1 - (1 - alpha_s) to one rounding).  Throws on a write error.
void writeEulerianFrame(const std::string &path, const Mesh &mesh, const EulerianFrame &frame);

/// Displacement per dt_rec implied by a shift matrix, mass-averaged over
/// each source cell: Us_c = sum_j T(j, c) (x_j - x_c) / dt_rec.  A cell with
/// an identity column (empty, or all its solid stays) gets zero.
std::vector<Vec3> impliedSolidVelocity(const Mesh &mesh, const CsrMatrix &shift, double dtRec);

enum class TracerInterpolation { trilinear, cell };

struct EulerianBuildOptions {
  BoxSpec mesh;
  /// In a vessel (docs/vessels.md): each box cell's inside volume [m^3], 0 outside; the
  /// solid of a cell is V_inside alpha_s, and a frame with solid outside is refused.
  /// Empty: every box cell whole.
  std::vector<double> cellVolume;
  /// The vessel (with cellVolume): tracers that cross its wall are mirrored back in, as at
  /// the box's walls.  The whole box: only the box's walls.
  Vessel vessel;
  double dtRec = 0.0;           // time between frames [s], > 0
  int tracersPerCell = 8;       // per occupied cell and frame
  std::uint64_t seed = 1;       // tracer positions are a function of seed, frame and cell
  TracerInterpolation interpolation = TracerInterpolation::cell;
  double courant = 0.25;        // largest tracer move per sub-step, in cell widths
  double slowCellFactor = 2.0;  // slow cell: t_cross > factor * dt_rec (0: no slow-cell split)
  double emptyAlphaS = 0.0;     // a cell with alpha_s <= this is empty
  double supportSeed = 1e-2;    // before scaling, every occupied cell sends this share of its solid
                                // to itself and to each face neighbour that holds solid at t_{k+1}
  int maxSupportRadius = 3;     // rows scaling cannot serve get seeds from up to this many cells
  int scalingIterations = 50;   // cap of the scaling iterations (0: no scaling)
  double scalingTolerance = 1e-6;  // stop when ||T m_k - t||_1 / ||m_k||_1 <= this
};

/// Throws std::invalid_argument naming the first bad option.
void validateEulerianBuildOptions(const EulerianBuildOptions &options);

/// Each box cell's volume inside `vessel` (a mesh cut from the box, vesselMesh), 0
/// outside: EulerianBuildOptions::cellVolume.  Throws for a mesh not cut from a box.
std::vector<double> insideVolumes(const Mesh &vessel);
/// A frame built on the box (solid only in the vessel's cells) as the vessel's
/// frame: the inside cells' alpha_s and the shift among them.  Throws when the
/// shift moves solid between a cell inside and one outside.
FrameRecord onVesselCells(const FrameRecord &boxFrame, const Mesh &vessel);

/// What tracing and scaling did to one frame.
struct EulerianFrameStats {
  std::size_t tracers = 0;     // tracers started
  std::size_t slowCells = 0;   // occupied cells with the slow-cell split
  std::size_t redirected = 0;  // tracers that ended in a cell empty at t_{k+1}
  std::size_t filledCells = 0; // non-empty at t_{k+1}, reached by no tracer, filled from neighbours
  std::size_t unreachedCells = 0; // the same, with no reached cell nearby (left empty)
  int maxSubsteps = 0;
  double residualBefore = 0.0; // ||T m_k - m_{k+1}||_1 / ||m_k||_1, traced matrix
  double residualAfter = 0.0;  // the same after scaling (what rcfd info reports)
  double massChange = 0.0;     // |sum m_{k+1} - sum m_k| / sum m_k: the floor of residualAfter
  int iterations = 0;          // scaling iterations used
  int supportRadius = 1;       // widest seed support scaling needed (cells)
};

/// The traced shift of frame `now` (frame index `frameIndex`, which seeds
/// the tracers) towards alpha_s `alphaNext` at t_{k+1}, mass-consistent
/// after scaling.  Column-stochastic; empty cells have identity columns.
CsrMatrix traceShift(const EulerianFrame &now, const std::vector<double> &alphaNext,
                     const EulerianBuildOptions &options, std::uint64_t frameIndex,
                     EulerianFrameStats *stats);

struct EulerianBuildReport {
  std::size_t files = 0, frames = 0;
  int cells = 0, tracersPerCell = 0;
  std::string interpolation;
  double scalingTolerance = 0.0, supportSeed = 0.0;
  int scalingIterations = 0;
  std::size_t framesWidened[2] = {0, 0}; // frames whose support scaling widened to 2 and to 3 cells
  std::size_t tracers = 0, slowCells = 0, redirected = 0, filledCells = 0, unreachedCells = 0;
  int maxSubsteps = 0, maxIterations = 0;
  double meanNnzPerColumn = 0.0, meanNnzPerOccupiedColumn = 0.0;
  int maxNnzPerColumn = 0;
  double maxAlphaS = 0.0;
  std::vector<EulerianFrameStats> frame; // per frame
  std::size_t framesAboveTolerance = 0;  // residualAfter - massChange above the tolerance

  double maxResidualBefore() const;
  double meanResidualBefore() const;
  double maxResidualAfter() const;
  double meanResidualAfter() const;
  double maxMassChange() const;
  /// Multi-line, human-readable.
  std::string summary() const;
};

/// Incremental builder: feed frames in time order; from the second one on,
/// each call emits one database frame (alpha_s and the traced shift of the
/// previous frame) through the sink.  Holds two frames at most.
class EulerianFrameBuilder {
public:
  EulerianFrameBuilder(const EulerianBuildOptions &options, FrameSink sink);
  void add(EulerianFrame frame);
  const EulerianBuildReport &report() const { return rep; }

private:
  EulerianBuildOptions opt;
  FrameSink sink;
  EulerianBuildReport rep;
  std::optional<EulerianFrame> prev;
  std::size_t nnzTotal = 0, nnzOccupied = 0, occupiedColumns = 0;
};

} // namespace rcfd
