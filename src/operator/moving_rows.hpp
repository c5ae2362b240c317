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

class MovingRows {
public:
  /// Collective.  Extracts the non-identity rows of every frame of db.
  PetscErrorCode setUp(const Database &db, int nf);
  /// Collective.  masses <- T_k masses for all nf fractions, in place.
  PetscErrorCode apply(int k, Vec masses);
  /// Bytes held for all frames (this rank).
  size_t bytes() const;
  /// All frames' moving entries on this rank.
  size_t numEntries() const;
  PetscInt numGhosts() const { return static_cast<PetscInt>(ghostRows.size()); }

private:
  // Rows that move, in local numbering; their entries' columns index the
  // local cells (< nlocal) or the ghost buffer (nlocal + g).
  // Rows are grouped by their number of entries: 0, 1, 2, 3, 4, more.
  static constexpr int kGroups = 6;
  struct Frame {
    std::vector<int32_t> rows, ptr, col;
    std::vector<double> val;
    std::array<int32_t, kGroups + 1> group{}; // first row of each group, then the end
  };
  template <int NF> void move(const Frame &f, double *x, const double *ghost, double *out) const;
  std::vector<Frame> frames;
  std::vector<PetscInt> ghostRows; // PETSc rows of the off-rank source cells, all frames
  std::vector<double> buffer;      // new masses of the moving rows
  OwnedVec ghosts;
  OwnedScatter toGhosts;
  PetscInt nlocal = 0;
  int nf = 0;
};

} // namespace rcfd
