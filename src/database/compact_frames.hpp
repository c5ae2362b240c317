// From one rank's rows of a shift as the file stores them to the compact
// frame the database holds (include/rcfd/frames.hpp, CompactFrame), and back
// to a PETSc matrix when one is asked for.  Private to the library.
//
// The loader's arithmetic is that of the PETSc matrices it used to build, so
// that full-precision runs give the same bits: column sums as
// MatMultTranspose(T, 1) forms them (own rows' entries in row order, other
// ranks' partial sums added through a reverse scatter) and the rescaling
// T(j, i) *= 1 / sum_i as MatDiagonalScale(T, NULL, 1 / sums) does it.
#pragma once

#include "rcfd/frames.hpp"
#include "rcfd/handle.hpp"
#include "rcfd/layout.hpp"

#include <string>
#include <vector>

namespace rcfd {

/// This rank's rows of one shift, columns in PETSc numbering, sorted per row:
/// every local row (`row` empty), or, with `impliedIdentity`, the rows
/// listed in `row` (local, ascending), the others identity rows T(r, r) = 1
/// that are not stored (a version 3 file's, which need no work to load).
struct LocalShiftRows {
  std::vector<PetscInt> rowPtr, col;
  std::vector<PetscScalar> val;
  bool impliedIdentity = false;
  std::vector<PetscInt> row; ///< local row of each stored row, with impliedIdentity
  /// Local row of the i-th stored row.
  PetscInt localRow(size_t i) const { return impliedIdentity ? row[i] : static_cast<PetscInt>(i); }
  size_t numStored() const { return rowPtr.size() - 1; }
};

/// What the loader checks the columns against and records, and what it keeps
/// from one batch of frames to the next.
struct ColumnCheck {
  /// Frames whose columns are summed, checked and rescaled together: one
  /// ghost exchange and one agreement on errors per batch, not per frame
  /// (each is a point where one rank waits for the other).  The same on
  /// every rank (batchFor).
  int batch = 1;
  double tolerance = 1e-9; ///< largest |column sum - 1| accepted (full precision)
  int weightBits = 0;      ///< > 0: weights quantised to 2^-weightBits, column sums exactly 1
  double largestError = 0.0; ///< largest |column sum - 1| seen on this rank (updated)
  /// Other ranks' columns of all frames so far (ascending) and the scatter of
  /// `batch` sums per cell to and from them: built again only when a batch
  /// reads a column not in it.  The union grows with the frames (on the
  /// default bed at 2 ranks, in every batch to about 900 columns), so that
  /// is once per batch, not once per frame.
  std::vector<PetscInt> ghosts;
  OwnedVec sums, partial; ///< own columns' sums, `batch` per cell; this rank's share of the ghosts'
  OwnedScatter toGhosts;
  int scattersBuilt = 0; ///< how often (for tests and measurements)
};

/// The frames of a batch on `layout`: 1 on one rank (no one to wait for; a
/// frame's rows then stay in cache from reading to compacting), else 16,
/// fewer on a large mesh so that the batch's column sums (8 bytes per cell
/// and frame) stay within about 16 MB per rank.  The same on every rank.
int batchFor(const Layout &layout);

/// Collective.  Sums the columns of each of `batch` (at most check->batch frames,
/// `where[i]` naming frame i: "database 'x.h5', frame k"), refuses (on every
/// rank, with a sentence naming the frame and the cell) a column off by more
/// than the tolerance, or, for quantised weights, one whose sum is not
/// exactly 1, and divides every entry by its column's sum.  Implied identity
/// rows count in the sums in their place, so the sums are those of all rows
/// to the bit; one whose column does not sum to exactly 1 is stored,
/// rescaled, like any other.  Every rank passes the same frames.
PetscErrorCode rescaleColumns(const Layout &layout, std::vector<LocalShiftRows> *batch,
                              const std::vector<std::string> &where, ColumnCheck *check);

/// The compact form of rescaled rows.  Entries of other ranks' cells go to
/// wide rows with the column nlocal + (their PETSc row) until numberGhosts()
/// renumbers them; their PETSc rows are appended to `ghosts`.  Quantised
/// weights must be multiples of 2^-weightBits in (0, 1] (throws h5::Error
/// naming `where` otherwise).
CompactFrame compactFrame(const LocalShiftRows &rows, PetscInt rowStart, PetscInt nlocal, int weightBits,
                          const std::string &where, std::vector<PetscInt> *ghosts);

/// Columns nlocal + PETSc row become nlocal + place in `ghostRows` (sorted).
void numberGhosts(CompactFrame *frame, PetscInt nlocal, const std::vector<PetscInt> &ghostRows);

/// Collective.  The MPIAIJ matrix of a compact frame: identity rows restored,
/// the same entries in the same order as the matrix the loader once built.
PetscErrorCode shiftMatrixOf(const CompactFrame &frame, const Layout &layout, const std::vector<PetscInt> &ghostRows,
                             int weightBits, OwnedMat *T);

} // namespace rcfd
