// The shift of one frame restricted to the cells whose solid moves.
//
// In a bubbling bed most cells keep their content during a step: the
// freeboard is empty and holds an identity column, and packed regions often
// stay put.  In the default bed 64 % of the rows of a frame are identity rows
// (one entry, T(j, j) = 1), and a row is an identity row exactly when its
// column is one (columns sum to 1, entries are >= 0).  Those cells' masses
// are unchanged by the step, so the propagation only needs the other rows:
// their new masses are computed from the old ones into a small buffer and
// written back in place.  This streams a fifth of the bytes of a product with
// the full matrix and never touches the cells that do not move.
#pragma once

#include "rcfd/database.hpp"
#include "rcfd/fractions.hpp"
#include "rcfd/handle.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace rcfd {

// The propagation reads the database's compact frames (include/rcfd/frames.hpp,
// CompactFrame) in place: it holds only the new masses of a frame's moving
// rows and the ghost cells' masses.
class MovingRows {
public:
  /// Collective.  Prepares the ghost scatter of db's frames for nf fractions;
  /// db must outlive this object.
  PetscErrorCode setUp(const Database &db, int nf);
  /// Collective.  masses <- T_k masses for all nf fractions, in place.
  PetscErrorCode apply(int k, Vec masses);
  /// One past the last own cell (local index) whose masses frame k writes:
  /// an empty cell at or above it stays empty.
  PetscInt writtenEnd(int k) const { return writtenEnds[k]; }
  /// Bytes of the compact frames it reads (this rank), and its own buffers'.
  size_t frameBytes() const;
  size_t bufferBytes() const;
  /// All frames' moving entries on this rank.
  size_t numEntries() const;
  PetscInt numGhosts() const { return db ? static_cast<PetscInt>(db->ghostRows().size()) : 0; }

private:
  template <int NF, class Weights>
  void move(const CompactFrame &f, const Weights &w, double *x, const double *ghost, double *out) const;
  template <int NF> void move(const CompactFrame &f, double *x, const double *ghost, double *out) const;
  const Database *db = nullptr;
  std::vector<double> buffer; // new masses of the moving rows
  std::vector<PetscInt> writtenEnds; // per frame
  OwnedVec ghosts;
  OwnedScatter toGhosts;
  PetscInt nlocal = 0;
  int nf = 0;
};

} // namespace rcfd
