// Distribution of the mesh's cells over MPI ranks.  METIS partitions the cell
// graph; cells are renumbered so that each rank owns a contiguous block of
// PETSc rows.  Files always use the natural (mesh) numbering, so they do not
// depend on the number of ranks.
#pragma once

#include "rcfd/handle.hpp"
#include "rcfd/mesh.hpp"

#include <utility>
#include <vector>

namespace rcfd {

class Layout {
public:
  /// Partition the mesh over the ranks of comm (collective).  On one rank the
  /// numbering is the natural one.  `work` (natural order, >= 0, optional)
  /// is the work per cell, e.g. the number of frames in which it holds solid:
  /// METIS then balances the work instead of the cells.  Reads -partition_view.
  static PetscErrorCode create(MPI_Comm comm, const Mesh &mesh, Layout *layout,
                               const std::vector<int> *work = nullptr);

  MPI_Comm comm() const { return comm_; }
  PetscInt numCells() const { return static_cast<PetscInt>(toNatural_.size()); }
  PetscInt rowStart() const { return rstart; }
  PetscInt rowEnd() const { return rend; }
  PetscInt numLocal() const { return rend - rstart; }
  /// PETSc row of a natural cell index, and back.
  PetscInt petscRow(PetscInt natural) const { return toPetsc_[natural]; }
  PetscInt naturalCell(PetscInt row) const { return toNatural_[row]; }
  /// Natural indices of this rank's cells, ascending (= PETSc row order).
  const std::vector<PetscInt> &ownedNatural() const { return owned; }
  /// Every rank's first PETSc row, and the number of cells last; the same on every rank.
  const std::vector<PetscInt> &rowStarts() const { return starts_; }
  /// The PETSc row of every natural cell; the same on every rank.
  const std::vector<PetscInt> &petscRows() const { return toPetsc_; }
  /// Maximal runs [begin, end) of consecutive natural indices among the owned cells.
  std::vector<std::pair<PetscInt, PetscInt>> ownedNaturalRuns() const;
  /// Number of cells whose faces cross to another rank, summed over ranks.
  PetscInt numCutFaces() const { return cutFaces; }

  /// Scatter between a PETSc-ordered Vec with block size bs and a
  /// natural-ordered Vec (contiguous PETSC_DECIDE ownership); the natural Vec
  /// is created here.  Forward: PETSc -> natural.
  PetscErrorCode naturalScatter(PetscInt bs, Vec petscOrdered, Vec *natural,
                                VecScatter *scatter) const;

  /// Collective.  A scatter from a PETSc-ordered Vec with block size bs to a
  /// sequential Vec holding the blocks of the given PETSc rows, in that order
  /// (created here, zeroed); SCATTER_REVERSE with ADD_VALUES adds them back to
  /// their owners.  Used for ghost cells.
  PetscErrorCode rowsScatter(PetscInt bs, PetscInt n, const PetscInt *rows, Vec *local,
                             VecScatter *scatter) const;

  /// Collective: the values of a PETSc-ordered Vec with block size bs, in
  /// natural order, on every rank (for small global needs: tests, layers).
  PetscErrorCode gatherToAll(PetscInt bs, Vec petscOrdered, std::vector<double> *natural) const;

private:
  MPI_Comm comm_ = MPI_COMM_NULL;
  PetscInt rstart = 0, rend = 0, cutFaces = 0;
  std::vector<PetscInt> toPetsc_, toNatural_, owned, starts_;
};

/// Layout::gatherToAll of a Vec whose rows at and above a bound on each rank
/// are zero (a state's occupied cells, FractionState::occupiedEnd), for a
/// caller that gathers again and again (the column carry at every jump): only
/// the rows below the bounds travel (one MPI_Allgatherv straight from the
/// Vec's array), and only the natural cells below end() are written.  The
/// values are those of gatherToAll, bit for bit.
class OccupiedGather {
public:
  /// Collective.  `localEnd`: every own row (local index) at or above it
  /// holds zeros.  Afterwards values() holds every cell's bs values in
  /// natural order, zero for every cell at or above end().
  PetscErrorCode gather(const Layout &layout, PetscInt bs, Vec petscOrdered, PetscInt localEnd);
  const std::vector<double> &values() const { return natural; }
  /// One past the last natural cell that may hold a nonzero value.
  PetscInt end() const { return naturalEnd; }

private:
  // The layout the tables below were made for, by content rather than by address: a layout
  // made after a database switch may reuse a freed one's address on some ranks only, and the
  // ranks must agree on whether to remake them (content is the same on every rank).
  PetscInt blockSize = 0, naturalEnd = 0;
  std::vector<PetscInt> starts, petscRowOf; // Layout::rowStarts, Layout::petscRows
  std::vector<int> owner;               // the rank of each natural cell
  std::vector<double> rows, natural;    // PETSc row order as received; natural order
  std::vector<PetscMPIInt> counts, displs;
};

} // namespace rcfd
