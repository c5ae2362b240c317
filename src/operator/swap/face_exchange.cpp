#include "rcfd/face_exchange.hpp"
#include "base/petsc_compat.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace rcfd {

struct FaceExchange::Impl {
  std::vector<SwapFace> swapFaces;
  OwnedVec ghostMasses; // nf per ghost cell
  OwnedScatter ghostScatter, scalarScatter;
  OwnedVec scalarLocal;
  std::vector<PetscInt> rows; // PETSc row of each gathered cell (own, then ghosts)
  std::vector<PetscScalar> ownChanges, ghostChanges; // a ghost's changes are its own rank's to make
  Vec openMasses = nullptr;
  const Layout *layout = nullptr;
  PetscInt gathered = 0;
  int maxPerCell = 0;
  double maxAoverV = 0.0;
};

FaceExchange::FaceExchange() : impl(std::make_unique<Impl>()) {}
FaceExchange::~FaceExchange() = default;

const std::vector<SwapFace> &FaceExchange::faces() const { return impl->swapFaces; }
int FaceExchange::maxFacesPerCell() const { return impl->maxPerCell; }
double FaceExchange::maxAreaOverVolume() const { return impl->maxAoverV; }
PetscInt FaceExchange::numGathered() const { return impl->gathered; }

PetscErrorCode FaceExchange::setUp(const Database &db, int numFractions, const Vec3 &direction,
                                   double minShare) {
  PetscFunctionBeginUser;
  const Mesh &mesh = db.mesh();
  const Layout &L = db.layout();
  const double dn = std::hypot(direction[0], direction[1], direction[2]);
  impl = std::make_unique<Impl>();
  open = Window{};
  auto &swapFaces = impl->swapFaces;
  auto &rows = impl->rows;
  const int nf = numFractions;
  const PetscInt nlocal = L.numLocal();
  impl->layout = &L;
  rows.resize(nlocal);
  for (PetscInt r = 0; r < nlocal; ++r) rows[r] = L.rowStart() + r;
  auto owned = [&](PetscInt row) { return row >= L.rowStart() && row < L.rowEnd(); };
  std::map<PetscInt, PetscInt> ghostIndex; // PETSc row -> local index of a ghost cell
  auto index = [&](PetscInt row) {
    if (owned(row)) return row - L.rowStart();
    auto [it, inserted] = ghostIndex.emplace(row, static_cast<PetscInt>(rows.size()));
    if (inserted) rows.push_back(row);
    return it->second;
  };
  for (int f = 0; f < mesh.numFaces(); ++f) {
    if (!owned(L.petscRow(mesh.faceOwner[f])) && !owned(L.petscRow(mesh.faceNeighbour[f])))
      continue; // between two other ranks' cells
    const Vec3 &S = mesh.faceArea[f];
    const double area = std::hypot(S[0], S[1], S[2]);
    double along = area; // dispersion: the whole face, owner as "lower"
    if (dn > 0) along = (S[0] * direction[0] + S[1] * direction[1] + S[2] * direction[2]) / dn;
    if (std::fabs(along) <= minShare * area) continue;
    int lo = mesh.faceOwner[f], up = mesh.faceNeighbour[f];
    if (along < 0) std::swap(lo, up); // S points from owner to neighbour
    const Vec3 &a = mesh.cellCentre[lo], &b = mesh.cellCentre[up];
    const double normalDistance =
        std::fabs((b[0] - a[0]) * S[0] + (b[1] - a[1]) * S[1] + (b[2] - a[2]) * S[2]) / area;
    const double projected = std::fabs(along);
    swapFaces.push_back({index(L.petscRow(lo)), index(L.petscRow(up)), projected,
                         mesh.cellVolume[lo], mesh.cellVolume[up], normalDistance,
                         projected / mesh.cellVolume[lo], projected / mesh.cellVolume[up]});
  }
  const PetscInt gathered = impl->gathered = static_cast<PetscInt>(rows.size());

  // Area over volume sent through in each direction, and faces, per own
  // cell: every face of an own cell is on this rank.
  std::vector<double> sendsUp(nlocal, 0.0), sendsDown(nlocal, 0.0);
  std::vector<int> perCell(nlocal, 0);
  for (const auto &f : swapFaces) {
    if (f.lower < nlocal) sendsUp[f.lower] += f.area / f.volumeLower, ++perCell[f.lower];
    if (f.upper < nlocal) sendsDown[f.upper] += f.area / f.volumeUpper, ++perCell[f.upper];
  }
  double localMax = 0.0;
  int localFaces = 0;
  for (PetscInt c = 0; c < nlocal; ++c) {
    localMax = std::max({localMax, sendsUp[c], sendsDown[c]});
    localFaces = std::max(localFaces, perCell[c]);
  }
  PetscCallMPI(MPI_Allreduce(&localMax, &impl->maxAoverV, 1, MPI_DOUBLE, MPI_MAX, L.comm()));
  PetscCallMPI(MPI_Allreduce(&localFaces, &impl->maxPerCell, 1, MPI_INT, MPI_MAX, L.comm()));

  impl->ownChanges.assign(static_cast<size_t>(nlocal) * nf, 0.0);
  impl->ghostChanges.assign(static_cast<size_t>(gathered - nlocal) * nf, 0.0);
  PetscCall(L.rowsScatter(nf, gathered - nlocal, rows.data() + nlocal, impl->ghostMasses.put(),
                          impl->ghostScatter.put()));
  open.nf = nf;
  open.nlocal = nlocal;
  open.ownChange = impl->ownChanges.data();
  open.ghostChange = impl->ghostChanges.data();
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FaceExchange::gatherBegin(Vec masses) {
  PetscFunctionBeginUser;
  Impl &x = *impl;
  PetscCall(VecScatterBegin(x.ghostScatter, masses, x.ghostMasses, INSERT_VALUES, SCATTER_FORWARD));
  std::fill(x.ghostChanges.begin(), x.ghostChanges.end(), 0.0); // as documented, though never read
  x.openMasses = masses;
  PetscCall(VecGetArrayRead(masses, &open.own));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FaceExchange::gatherEnd() {
  PetscFunctionBeginUser;
  Impl &x = *impl;
  PetscCall(VecScatterEnd(x.ghostScatter, x.openMasses, x.ghostMasses, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGetArrayRead(x.ghostMasses, &open.ghost));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FaceExchange::gatherScalar(Vec cellValues, std::vector<double> *out) {
  PetscFunctionBeginUser;
  Impl &x = *impl;
  if (!x.scalarScatter)
    PetscCall(x.layout->rowsScatter(1, x.gathered, x.rows.data(), x.scalarLocal.put(), x.scalarScatter.put()));
  PetscCall(VecScatterBegin(x.scalarScatter, cellValues, x.scalarLocal, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(x.scalarScatter, cellValues, x.scalarLocal, INSERT_VALUES, SCATTER_FORWARD));
  const PetscScalar *a;
  PetscCall(VecGetArrayRead(x.scalarLocal, &a));
  out->assign(a, a + x.gathered);
  PetscCall(VecRestoreArrayRead(x.scalarLocal, &a));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FaceExchange::endKernel() {
  PetscFunctionBeginUser;
  Impl &x = *impl;
  PetscCall(VecRestoreArrayRead(x.openMasses, &open.own));
  PetscCall(VecRestoreArrayRead(x.ghostMasses, &open.ghost));
  x.openMasses = nullptr;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FaceExchange::addChanges(Vec masses) {
  PetscFunctionBeginUser;
  Impl &x = *impl;
  const size_t nf = static_cast<size_t>(open.nf);
  PetscScalar *m;
  PetscCall(VecGetArray(masses, &m));
  // Add and zero in one pass, over the cells that can have changed (the
  // freeboard, typically the upper half of a rank's rows, is left alone).
  for (size_t k = static_cast<size_t>(open.changedFrom) * nf; k < static_cast<size_t>(open.changedTo) * nf; ++k) {
    m[k] += x.ownChanges[k];
    x.ownChanges[k] = 0.0;
  }
  open.changedFrom = PETSC_MAX_INT;
  open.changedTo = 0;
  PetscCall(VecRestoreArray(masses, &m));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
