// Distributed bookkeeping shared by the face-swap operators (drift,
// dispersion): this rank's faces, the masses of both cells of each face
// (including cells on other ranks), and the reverse scatter that adds each
// swap's changes to the owning ranks.  Partition boundaries need no special
// case: a face is handled by the rank owning its owner cell, and PETSc's
// scatter moves ghost values both ways.
#pragma once

#include "rcfd/database.hpp"
#include "rcfd/fractions.hpp"
#include "rcfd/handle.hpp"

#include <functional>
#include <vector>

namespace rcfd {

struct SwapFace {
  PetscInt lower, upper; // local indices into the gathered cells
  double area;           // area projected on the chosen direction, > 0
  double volumeLower, volumeUpper;
  double distance; // between the two cell centres, along the face normal
};

class FaceExchange {
public:
  /// Faces whose area vector has a component along `direction` above
  /// `minShare` of its area (all internal faces when direction is zero);
  /// "lower" is the cell the direction points away from.
  PetscErrorCode setUp(const Database &db, int nf, const Vec3 &direction, double minShare);
  const std::vector<SwapFace> &faces() const { return swapFaces; }
  /// Number of swap faces touching each gathered cell at most (for limits).
  int maxFacesPerCell() const { return maxPerCell; }
  PetscInt numGathered() const { return gathered; }
  /// Collective: copy masses of every cell touched by this rank's faces into
  /// gatheredMasses() (nf per cell), and zero the change array.
  PetscErrorCode gather(Vec masses);
  /// Collective: add the accumulated changes to the masses of the owning ranks.
  PetscErrorCode scatterAdd(Vec masses);
  const PetscScalar *gatheredMasses() const { return massArray; }
  PetscScalar *changes() { return changeArray; }
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
  OwnedVec local, delta;
  OwnedScatter scatter, scalarScatter;
  OwnedVec scalarLocal;
  std::vector<PetscInt> rows; // PETSc row of each gathered cell
  PetscScalar *massArray = nullptr, *changeArray = nullptr;
  PetscInt gathered = 0;
  int maxPerCell = 0;
  double maxAoverV = 0.0;
};

} // namespace rcfd
