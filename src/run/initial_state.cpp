#include "rcfd/run.hpp"

#include "util/collective.hpp"
#include "util/h5.hpp"

#include <petscviewerhdf5.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace rcfd {

// Initial masses per cell and fraction: "mixed" (the inventory's shares in
// every cell of frame 0's solid), "layered" (largest diameter at the bottom,
// each fraction a layer of its share of the mass), or "file".
PetscErrorCode Run::initialState() {
  const int nf = set.size();
  const Layout &L = db->layout();
  const auto &vol = db->localVolumes();
  PetscFunctionBeginUser;
  if (initKind == "file") {
    // Dimensions first, so that a mismatch gets a sentence rather than a
    // PETSc size error.
    PetscCall(collectively(comm, [&] {
      // Opened on every rank without MPI-IO: only its header is read here.
      auto f = h5::File::openRead(initFile, MPI_COMM_NULL);
      const auto dims = f.extents("/masses");
      if (dims.size() != 2 || dims[0] != (hsize_t)L.numCells() || dims[1] != (hsize_t)nf)
        throw std::runtime_error("-init_file '" + initFile + "': /masses should be " +
                                 std::to_string(L.numCells()) + " cells x " + std::to_string(nf) +
                                 " fractions to match the database and -fractions_diameters");
    }));
    OwnedVec natural;
    OwnedScatter scatter;
    OwnedViewer v;
    PetscCall(L.naturalScatter(nf, fstate.masses(), natural.put(), scatter.put()));
    PetscCall(PetscObjectSetName((PetscObject)natural.get(), "masses"));
    PetscCall(PetscViewerHDF5Open(comm, initFile.c_str(), FILE_MODE_READ, v.put()));
    PetscCall(VecLoad(natural, v));
    PetscCall(VecScatterBegin(scatter, natural, fstate.masses(), INSERT_VALUES, SCATTER_REVERSE));
    PetscCall(VecScatterEnd(scatter, natural, fstate.masses(), INSERT_VALUES, SCATTER_REVERSE));
    PetscReal low;
    PetscCall(VecMin(fstate.masses(), nullptr, &low));
    PetscCheck(low >= 0 && std::isfinite(low), comm, PETSC_ERR_USER_INPUT,
               "-init_file '%s': /masses has a negative or non-finite mass (%g kg)", initFile.c_str(),
               (double)low);
    PetscFunctionReturn(PETSC_SUCCESS);
  }

  const PetscScalar *alpha;
  PetscScalar *m;
  PetscCall(VecGetArrayRead(db->alphaS(0), &alpha));
  PetscCall(VecGetArrayWrite(fstate.masses(), &m));
  if (initKind == "mixed") {
    for (PetscInt c = 0; c < L.numLocal(); ++c)
      for (int i = 0; i < nf; ++i) m[c * nf + i] = set.massShare(i) * solidDensity * alpha[c] * vol[c];
  } else { // layered: largest at the bottom, each fraction a layer of its mass share
    // Every rank needs the bulk mass of all cells below its own: gather the
    // first frame's alpha_s in natural order on every rank (one vector).
    PetscCall(VecRestoreArrayRead(db->alphaS(0), &alpha));
    OwnedVec all;
    OwnedScatter toAll, nat;
    OwnedVec naturalAlpha;
    PetscCall(L.naturalScatter(1, db->alphaS(0), naturalAlpha.put(), nat.put()));
    PetscCall(VecScatterBegin(nat, db->alphaS(0), naturalAlpha, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(nat, db->alphaS(0), naturalAlpha, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterCreateToAll(naturalAlpha, toAll.put(), all.put()));
    PetscCall(VecScatterBegin(toAll, naturalAlpha, all, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(toAll, naturalAlpha, all, INSERT_VALUES, SCATTER_FORWARD));
    const PetscScalar *a;
    PetscCall(VecGetArrayRead(all, &a));
    const Mesh &mesh = db->mesh();
    const Vec3 g = db->metadata().gravity;
    auto height = [&](int c) {
      const Vec3 &x = mesh.cellCentre[c];
      return -(g[0] * x[0] + g[1] * x[1] + g[2] * x[2]);
    };
    std::vector<int> order(mesh.numCells());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int p, int q) { return height(p) < height(q); });
    std::vector<double> below(mesh.numCells());
    double total = 0.0;
    for (int c : order) {
      below[c] = total;
      total += solidDensity * a[c] * mesh.cellVolume[c];
    }
    std::vector<int> byDiameter(nf);
    std::iota(byDiameter.begin(), byDiameter.end(), 0);
    std::stable_sort(byDiameter.begin(), byDiameter.end(),
                     [&](int p, int q) { return set.diameter(p) > set.diameter(q); });
    for (PetscInt r = 0; r < L.numLocal(); ++r) {
      const int c = static_cast<int>(L.ownedNatural()[r]);
      const double lo = below[c], hi = lo + solidDensity * a[c] * mesh.cellVolume[c];
      double layerStart = 0.0;
      for (int i : byDiameter) {
        const double layerEnd = layerStart + set.massShare(i) * total;
        m[r * nf + i] = std::max(0.0, std::min(hi, layerEnd) - std::max(lo, layerStart));
        layerStart = layerEnd;
      }
    }
    PetscCall(VecRestoreArrayRead(all, &a));
    PetscCall(VecRestoreArrayWrite(fstate.masses(), &m));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(VecRestoreArrayRead(db->alphaS(0), &alpha));
  PetscCall(VecRestoreArrayWrite(fstate.masses(), &m));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
