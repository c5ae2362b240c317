// Distributed bookkeeping shared by the face-swap operators (drift,
// dispersion, carry): this rank's faces, the masses of both cells of each
// face, and the changes a sweep makes.  Cells are numbered locally: this
// rank's cells first (read in place from the state, no copy), then the ghost
// cells on other ranks, whose masses arrive and whose changes leave through
// one PETSc scatter of the ghosts only.  Partition boundaries need no special
// case: a face is handled by the rank owning its owner cell.
#pragma once

#include "rcfd/database.hpp"
#include "rcfd/fractions.hpp"
#include "rcfd/handle.hpp"

#include <algorithm>
#include <functional>
#include <vector>

namespace rcfd {

struct SwapFace {
  PetscInt lower, upper; // local cell indices: own cells, then ghosts
  double area;           // area projected on the chosen direction, > 0
  double volumeLower, volumeUpper;
  double distance; // between the two cell centres, along the face normal
  double areaOverVolumeLower, areaOverVolumeUpper; // area / volume of each side [1/m]
};

class FaceExchange {
public:
  /// Faces whose area vector has a component along `direction` above
  /// `minShare` of its area (all internal faces when direction is zero);
  /// "lower" is the cell the direction points away from.
  PetscErrorCode setUp(const Database &db, int numFractions, const Vec3 &direction, double minShare);
  const std::vector<SwapFace> &faces() const { return swapFaces; }
  /// Number of swap faces touching each gathered cell at most (for limits).
  int maxFacesPerCell() const { return maxPerCell; }
  PetscInt numGathered() const { return gathered; }
  /// Collective: bring the ghost cells' masses and open the state for
  /// reading through massAt() until endKernel().  The changes are zero.
  PetscErrorCode gather(Vec masses);
  /// Collective: add the accumulated changes to `masses` (own cells in place,
  /// ghost cells on their owning ranks) and zero them again.
  PetscErrorCode scatterAdd(Vec masses);
  /// The nf masses and the nf accumulated changes of local cell i.
  const PetscScalar *massAt(PetscInt i) const {
    return i < nlocal ? ownMasses + i * nf : ghostMassArray + (i - nlocal) * nf;
  }
  PetscScalar *changeAt(PetscInt i) {
    if (i >= nlocal) return ghostChangeArray + (i - nlocal) * nf;
    changedFrom = std::min(changedFrom, i); // scatterAdd() visits only this range
    changedTo = std::max(changedTo, i + 1);
    return ownChanges.data() + i * nf;
  }
  /// Collective: values of a cell Vec (block size 1, PETSc order) at the
  /// gathered cells, e.g. a database frame's alpha_s.
  PetscErrorCode gatherScalar(Vec cellValues, std::vector<double> *out);
  /// Restore arrays (call after the kernel, before scatterAdd).
  PetscErrorCode endKernel();
  /// Largest sum over a cell's faces of area / volume in each direction
  /// (cells sending upward and downward), for sub-step estimates.
  double maxAreaOverVolume() const { return maxAoverV; }

private:
  std::vector<SwapFace> swapFaces;
  OwnedVec ghostMasses, ghostChanges; // nf per ghost cell
  OwnedScatter ghostScatter, scalarScatter;
  OwnedVec scalarLocal;
  std::vector<PetscInt> rows; // PETSc row of each local cell (own, then ghosts)
  std::vector<PetscScalar> ownChanges;
  Vec openMasses = nullptr;
  const PetscScalar *ownMasses = nullptr, *ghostMassArray = nullptr;
  PetscScalar *ghostChangeArray = nullptr;
  const Layout *layout = nullptr;
  PetscInt gathered = 0, nlocal = 0;
  PetscInt changedFrom = PETSC_MAX_INT, changedTo = 0; // own cells with changes
  int nf = 0;
  int maxPerCell = 0;
  double maxAoverV = 0.0;
};

} // namespace rcfd
