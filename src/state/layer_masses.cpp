#include "state/layer_masses.hpp"
#include "base/petsc_compat.hpp"

#include "rcfd/zone.hpp"
#include "state/cell_passes.hpp"

#include <cmath>
#include <limits>

namespace rcfd {

PetscErrorCode HorizontalLayers::setUp(const Database &db) {
  PetscFunctionBeginUser;
  comm = db.layout().comm();
  const Mesh &mesh = db.mesh();
  // A vessel cut from a box has the box's layers; each holds its cells' real
  // (inside) volumes, so a cone's narrow layers weigh what they hold.
  PetscCheck(mesh.onBoxLattice(), comm, PETSC_ERR_SUP,
             "Database '%s': profiles, halves and the bottom layer need a box mesh (horizontal cell layers)",
             db.path().c_str());
  int axis = 2;
  bool upward = true;
  verticalAxis(db.metadata().gravity, &axis, &upward);
  const BoxSpec &b = mesh.boxSpec();
  const int n = axis == 0 ? b.nx : axis == 1 ? b.ny : b.nz;
  const double h = b.length[axis] / n;
  layerThickness = h;
  centre.resize(n);
  for (int l = 0; l < n; ++l) { // layer 0 at the bottom
    const int k = upward ? l : n - 1 - l;
    centre[l] = b.origin[axis] + (k + 0.5) * h;
  }
  layerOfLocal.clear();
  localVolume = db.localVolumes();
  std::vector<double> volume(n, 0.0);
  const auto &owned = db.layout().ownedNatural();
  for (std::size_t c = 0; c < owned.size(); ++c) {
    int k = static_cast<int>(std::floor((mesh.cellCentre[owned[c]][axis] - b.origin[axis]) / h));
    k = k < 0 ? 0 : k >= n ? n - 1 : k;
    const int l = upward ? k : n - 1 - k;
    layerOfLocal.push_back(l);
    volume[l] += localVolume[c];
  }
  layerVolume.assign(n, 0.0);
  PetscCallMPI(MPI_Allreduce(volume.data(), layerVolume.data(), n, MPI_DOUBLE, MPI_SUM, comm));
  // A vessel may leave box layers without a cell (a cone that starts above the
  // box's floor): they are no layers of the bed, and the bottom layer is the
  // vessel's lowest.  A box keeps every layer.
  std::vector<int> kept(n, -1);
  int count = 0;
  for (int l = 0; l < n; ++l)
    if (layerVolume[l] > 0.0) {
      kept[l] = count;
      centre[count] = centre[l];
      layerVolume[count++] = layerVolume[l];
    }
  if (count < n) {
    centre.resize(count);
    layerVolume.resize(count);
    for (int &l : layerOfLocal) l = kept[l];
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode HorizontalLayers::fractionMasses(Vec masses, int nf, std::vector<double> *perLayer) const {
  return sumLayers(masses, nf, static_cast<PetscInt>(layerOfLocal.size()), perLayer);
}

PetscErrorCode HorizontalLayers::fractionMasses(const FractionState &state, std::vector<double> *perLayer) const {
  PetscInt end;
  PetscFunctionBeginUser;
  PetscCall(state.occupiedEnd(&end));
  PetscCall(sumLayers(state.masses(), state.numFractions(), end, perLayer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode HorizontalLayers::layerAmounts(const FractionState &state, int l, std::vector<double> *amounts) const {
  PetscInt end;
  const PetscScalar *a;
  PetscFunctionBeginUser;
  const int w = state.numScalars() * state.numFractions();
  std::vector<double> local(w, 0.0);
  PetscCall(state.occupiedEnd(&end));
  PetscCall(VecGetArrayRead(state.amounts(), &a));
  for (PetscInt c = 0; c < end; ++c)
    if (layerOfLocal[c] == l)
      for (int k = 0; k < w; ++k) local[k] += a[c * w + k];
  PetscCall(VecRestoreArrayRead(state.amounts(), &a));
  amounts->assign(w, 0.0);
  PetscCallMPI(MPI_Allreduce(local.data(), amounts->data(), w, MPI_DOUBLE, MPI_SUM, comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode HorizontalLayers::sumLayers(Vec masses, int nf, PetscInt end, std::vector<double> *perLayer) const {
  PetscFunctionBeginUser;
  std::vector<double> local(centre.size() * nf, 0.0);
  const PetscScalar *m;
  PetscCall(VecGetArrayRead(masses, &m));
  byFractions(nf, [&](auto k) {
    constexpr int N = decltype(k)::value;
    if constexpr (N == 0) {
      for (PetscInt c = 0; c < end; ++c)
        for (int i = 0; i < nf; ++i) local[layerOfLocal[c] * nf + i] += m[c * nf + i];
    } else
      for (PetscInt c = 0; c < end;) { // a run of cells of one layer, its sums in registers (the same order)
        const int l = layerOfLocal[c];
        PetscInt to = c + 1;
        while (to < end && layerOfLocal[to] == l) ++to;
        sumCells<N>(N, m, c, to, &local[static_cast<std::size_t>(l) * N]);
        c = to;
      }
  });
  PetscCall(VecRestoreArrayRead(masses, &m));
  perLayer->assign(local.size(), 0.0);
  PetscCallMPI(MPI_Allreduce(local.data(), perLayer->data(), static_cast<int>(local.size()), MPI_DOUBLE,
                             MPI_SUM, comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode HorizontalLayers::solidVolumes(Vec alpha, std::vector<double> *perLayer) const {
  PetscFunctionBeginUser;
  std::vector<double> local(centre.size(), 0.0);
  const PetscScalar *a;
  PetscCall(VecGetArrayRead(alpha, &a));
  for (std::size_t c = 0; c < layerOfLocal.size(); ++c) local[layerOfLocal[c]] += a[c] * localVolume[c];
  PetscCall(VecRestoreArrayRead(alpha, &a));
  perLayer->assign(local.size(), 0.0);
  PetscCallMPI(MPI_Allreduce(local.data(), perLayer->data(), static_cast<int>(local.size()), MPI_DOUBLE,
                             MPI_SUM, comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

namespace layers {

double sauterDiameter(const std::vector<double> &perLayer, int l, const FractionSet &fractions) {
  const int nf = fractions.size();
  double mass = 0.0, massOverD = 0.0;
  for (int i = 0; i < nf; ++i) {
    mass += perLayer[l * nf + i];
    massOverD += perLayer[l * nf + i] / fractions.diameter(i);
  }
  return mass > 0.0 ? mass / massOverD : std::numeric_limits<double>::quiet_NaN();
}

int medianLayer(const std::vector<double> &perLayer, int nf) {
  const int n = static_cast<int>(perLayer.size()) / nf;
  std::vector<double> layerMass(n, 0.0);
  double total = 0.0;
  for (int l = 0; l < n; ++l) {
    for (int i = 0; i < nf; ++i) layerMass[l] += perLayer[l * nf + i];
    total += layerMass[l];
  }
  if (!(total > 0.0)) return -1;
  double below = 0.0;
  for (int l = 0; l < n; ++l) {
    below += layerMass[l];
    if (below >= 0.5 * total) return l;
  }
  return n - 1; // round-off: the sum fell a hair short of half
}

void halves(const std::vector<double> &perLayer, int nf, int splitLayer, std::vector<double> *bottom,
            std::vector<double> *top) {
  const int n = static_cast<int>(perLayer.size()) / nf;
  bottom->assign(nf, 0.0);
  top->assign(nf, 0.0);
  for (int l = 0; l < n; ++l)
    for (int i = 0; i < nf; ++i) (l <= splitLayer ? *bottom : *top)[i] += perLayer[l * nf + i];
  for (auto *half : {bottom, top}) {
    double sum = 0.0;
    for (double m : *half) sum += m;
    for (double &m : *half) m = sum > 0.0 ? m / sum : std::numeric_limits<double>::quiet_NaN();
  }
}

} // namespace layers
} // namespace rcfd
