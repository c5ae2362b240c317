// Face swaps on a distributed mesh: the helper behind the drift, dispersion
// and carry operators, for authors of new operators that move mass between
// neighbouring cells.
//
// A face-swap operator visits faces, reads the masses of the two cells of
// each face and accumulates a change on both sides (what one side loses the
// other gains, so the exchange conserves every fraction by construction).
// FaceExchange hides where the cells live: this rank's own cells are read in
// place from the state, and the cells of other ranks that touch this rank's
// faces ("ghosts") arrive by one PETSc scatter.  A face between two ranks is
// on both, each computes it from the same masses and keeps the change of its
// own cell (a ghost's change is written and dropped), so partition
// boundaries need no special case in a kernel and a sweep meets the
// neighbouring ranks once.
//
//   FaceExchange exchange;
//   PetscCall(exchange.setUp(db, nf, {0, 0, 0}, 0.0)); // all internal faces
//   PetscCall(exchange.sweep(state.masses(), [&] {
//     for (const SwapFace &f : exchange.faces()) {
//       const PetscScalar *mL = exchange.massAt(f.lower), *mU = exchange.massAt(f.upper);
//       PetscScalar *dL = exchange.changeAt(f.lower), *dU = exchange.changeAt(f.upper);
//       for (int i = 0; i < nf; ++i) { const double x = ...; dL[i] -= x; dU[i] += x; }
//     }
//   }));
//
// Every change is computed from the masses at the start of the sweep (an
// explicit step); choosing a small enough sub-step is the operator's job
// (maxAreaOverVolume() and maxFacesPerCell() help to bound it).
// See src/operator/swap/ for three operators written this way.
#pragma once

#include "rcfd/database.hpp"
#include "rcfd/fractions.hpp"

#include <algorithm>
#include <memory>
#include <vector>

namespace rcfd {

/// One face between two cells, as a kernel sees it.  Cell indices are local
/// to the exchange (give them to massAt()/changeAt()), not mesh cell numbers.
struct SwapFace {
  PetscInt lower, upper; // the cell the chosen direction points away from, and the other
  double area;           // area projected on the chosen direction (whole area without one), > 0 [m^2]
  double volumeLower, volumeUpper; // [m^3]
  double distance; // between the two cell centres, along the face normal [m]
  double areaOverVolumeLower, areaOverVolumeUpper; // area / volume of each side [1/m]
};

class FaceExchange {
public:
  FaceExchange();
  ~FaceExchange();
  FaceExchange(const FaceExchange &) = delete;
  FaceExchange &operator=(const FaceExchange &) = delete;

  /// Collective.  Chooses the faces whose area vector has a component along
  /// `direction` above `minShare` of its area (all internal faces when the
  /// direction is zero) and builds the ghost scatter for states of
  /// `numFractions` masses per cell.  Cost: one pass over the mesh's faces
  /// and two reductions; memory per rank one SwapFace (56 bytes with 32-bit
  /// PetscInt) per face, nf numbers per own cell and 2 nf per ghost cell.
  PetscErrorCode setUp(const Database &db, int numFractions, const Vec3 &direction, double minShare);

  /// This rank's faces: every chosen face of an own cell (not collective).
  const std::vector<SwapFace> &faces() const;
  /// Most faces any cell has, over all ranks (for per-face limits).
  int maxFacesPerCell() const;
  /// Largest sum over a cell's faces of area / volume, over all ranks and
  /// both senses of the direction [1/m]: a velocity u gives a Courant number
  /// at most u dt maxAreaOverVolume().
  double maxAreaOverVolume() const;
  /// Cells a kernel may index: this rank's own cells, then its ghosts.
  PetscInt numGathered() const;
  /// This rank's own cells (the first numOwn() gathered cells).
  PetscInt numOwn() const { return open.nlocal; }

  /// Collective.  One sweep: gatherBegin(masses), gatherEnd(), kernel(),
  /// endKernel(), then addChanges(into), where `into` defaults to `masses`.
  /// Cost: one scatter of nf numbers per ghost cell (messages to
  /// neighbouring ranks only) and one pass over the own cells that changed;
  /// nothing is copied.
  template <typename Kernel> PetscErrorCode sweep(Vec masses, Kernel &&kernel, Vec into = nullptr) {
    PetscFunctionBeginUser;
    PetscCall(gatherBegin(masses));
    PetscCall(gatherEnd());
    kernel();
    PetscCall(endKernel());
    PetscCall(addChanges(into ? into : masses));
    PetscFunctionReturn(0);
  }

  /// Collective.  Starts bringing the ghost cells' masses and opens
  /// `masses`: massAt() of an own cell may be read from here on (a kernel
  /// may work on its own cells while the ghosts travel).  The changes start
  /// at zero.
  PetscErrorCode gatherBegin(Vec masses);
  /// Collective.  The ghost cells' masses have arrived: massAt() of any
  /// gathered cell until endKernel().
  PetscErrorCode gatherEnd();
  /// Not collective.  Closes what gatherBegin() opened (before addChanges()).
  PetscErrorCode endKernel();
  /// Not collective.  Adds the own cells' accumulated changes to `masses`
  /// and zeroes them.
  PetscErrorCode addChanges(Vec masses);

  /// The nf masses of gathered cell i (between gatherEnd() and endKernel();
  /// an own cell's from gatherBegin()).
  const PetscScalar *massAt(PetscInt i) const {
    return i < open.nlocal ? open.own + i * open.nf : open.ghost + (i - open.nlocal) * open.nf;
  }
  /// The nf accumulated changes of gathered cell i (same window).
  PetscScalar *changeAt(PetscInt i) {
    if (i < open.nlocal) markChanged(i, i + 1);
    return changeInMarked(i);
  }
  /// For a kernel that knows which own cells it may change: mark them once
  /// (own cells from..to-1; addChanges() visits only the marked range) and
  /// then reach their changes through changeInMarked(), which marks nothing.
  /// (Marking a ghost is not needed: its changes are dropped.)
  void markChanged(PetscInt from, PetscInt to) {
    open.changedFrom = std::min(open.changedFrom, from);
    open.changedTo = std::max(open.changedTo, to);
  }
  PetscScalar *changeInMarked(PetscInt i) {
    return i < open.nlocal ? open.ownChange + i * open.nf : open.ghostChange + (i - open.nlocal) * open.nf;
  }

  /// Collective.  The values of a cell Vec (block size 1, PETSc order, e.g.
  /// a database frame's alpha_s) at the gathered cells.  Copies numGathered() numbers.
  PetscErrorCode gatherScalar(Vec cellValues, std::vector<double> *out);

private:
  struct Impl; // faces, scatters, ghost vectors (face_exchange.cpp)
  std::unique_ptr<Impl> impl;
  // The arrays gatherBegin() opens, held here only so that massAt() and
  // changeAt() inline into the kernels' loops.
  struct Window {
    const PetscScalar *own = nullptr, *ghost = nullptr;
    PetscScalar *ownChange = nullptr, *ghostChange = nullptr;
    PetscInt nlocal = 0, changedFrom = PETSC_MAX_INT, changedTo = 0; // own cells with changes
    int nf = 0;
  } open;
};

} // namespace rcfd
