#include "state/initial_state.hpp"
#include "base/petsc_compat.hpp"

#include "base/collective.hpp"
#include "base/h5.hpp"

#include <petscviewerhdf5.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace rcfd {

namespace {

// Mass shares of the inventory in every cell of frame 0's solid.
void mixedMasses(const FractionSet &set, double rho, const PetscScalar *alpha,
                 const std::vector<double> &volume, PetscScalar *m) {
  const int nf = set.size();
  for (size_t c = 0; c < volume.size(); ++c)
    for (int i = 0; i < nf; ++i) m[c * nf + i] = set.massShare(i) * rho * alpha[c] * volume[c];
}

// Largest diameter at the bottom, each fraction a layer of its share of the
// bed's mass, cells ordered by height along -gravity.  `alphaAll` is frame
// 0's alpha_s of every cell (natural order).
void layeredMasses(const FractionSet &set, double rho, const Mesh &mesh, const Vec3 &g,
                   const std::vector<double> &alphaAll, const std::vector<PetscInt> &owned,
                   PetscScalar *m) {
  const int nf = set.size();
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
    total += rho * alphaAll[c] * mesh.cellVolume[c];
  }
  std::vector<int> byDiameter(nf);
  std::iota(byDiameter.begin(), byDiameter.end(), 0);
  std::stable_sort(byDiameter.begin(), byDiameter.end(),
                   [&](int p, int q) { return set.diameter(p) > set.diameter(q); });
  for (size_t r = 0; r < owned.size(); ++r) {
    const PetscInt c = owned[r];
    const double lo = below[c], hi = lo + rho * alphaAll[c] * mesh.cellVolume[c];
    double layerStart = 0.0;
    for (int i : byDiameter) {
      const double layerEnd = layerStart + set.massShare(i) * total;
      m[r * nf + i] = std::max(0.0, std::min(hi, layerEnd) - std::max(lo, layerStart));
      layerStart = layerEnd;
    }
  }
}

} // namespace

namespace {

PetscErrorCode loadInitialMasses(const std::string &initFile, const Database &db, const FractionSet &set,
                                 FractionState &fstate);

} // namespace

PetscErrorCode setInitialState(const InitialState &spec, const Database &db, const FractionSet &set,
                               double solidDensity, FractionState &fstate) {
  const Layout &L = db.layout();
  PetscFunctionBeginUser;
  if (spec.kind == "file") {
    PetscCall(loadInitialMasses(spec.file, db, set, fstate));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCheck(spec.kind == "mixed" || spec.kind == "layered", L.comm(), PETSC_ERR_USER_INPUT,
             "-init %s is not known; use mixed, layered or file", spec.kind.c_str());
  std::vector<double> alphaAll;
  if (spec.kind == "layered") PetscCall(L.gatherToAll(1, db.alphaS(0), &alphaAll));
  const PetscScalar *alpha;
  PetscScalar *m;
  PetscCall(VecGetArrayRead(db.alphaS(0), &alpha));
  PetscCall(VecGetArrayWrite(fstate.masses(), &m));
  if (spec.kind == "mixed") mixedMasses(set, solidDensity, alpha, db.localVolumes(), m);
  else layeredMasses(set, solidDensity, db.mesh(), db.metadata().gravity, alphaAll, L.ownedNatural(), m);
  PetscCall(VecRestoreArrayWrite(fstate.masses(), &m));
  PetscCall(VecRestoreArrayRead(db.alphaS(0), &alpha));
  PetscFunctionReturn(PETSC_SUCCESS);
}

namespace {

PetscErrorCode loadInitialMasses(const std::string &initFile, const Database &db, const FractionSet &set,
                                 FractionState &fstate) {
  const int nf = set.size();
  const Layout &L = db.layout();
  const MPI_Comm comm = L.comm();
  PetscFunctionBeginUser;
  // Dimensions and diameters first, so that a mismatch gets a sentence
  // rather than a PETSc size error.
  PetscCall(collectively(comm, [&] {
    auto f = h5::File::openRead(initFile, MPI_COMM_NULL); // only the header, on every rank
    const auto dims = f.extents("/masses");
    if (dims.size() != 2 || dims[0] != (hsize_t)L.numCells() || dims[1] != (hsize_t)nf)
      throw std::runtime_error("-init_file '" + initFile + "': /masses should be " +
                               std::to_string(L.numCells()) + " cells x " + std::to_string(nf) +
                               " fractions to match the database and -fractions_diameters");
    if (f.hasAttribute("/masses", "diameters")) {
      const auto d = f.readAttrDoubles("/masses", "diameters");
      for (int i = 0; i < nf && i < (int)d.size(); ++i)
        if (std::fabs(d[i] - set.diameter(i)) > 1e-3 * set.diameter(i))
          throw std::runtime_error("-init_file '" + initFile + "': fraction " + std::to_string(i + 1) +
                                   " has diameter " + std::to_string(d[i] * 1e3) +
                                   " mm in the file but " + std::to_string(set.diameter(i) * 1e3) +
                                   " mm in -fractions_diameters");
    }
    // A file with checksums is read once here, where a damaged chunk gets
    // rcfd's sentence naming the file (PETSc's VecLoad below would report
    // HDF5's failure without it).
    if (f.checksums() == h5::Checksums::fletcher32) f.read<double>("/masses");
  }, PETSC_ERR_USER_INPUT));
  OwnedVec natural;
  OwnedScatter scatter;
  OwnedViewer v;
  PetscCall(L.naturalScatter(nf, fstate.masses(), natural.put(), scatter.put()));
  PetscCall(PetscObjectSetName((PetscObject)natural.get(), "masses"));
  PetscCall(PetscViewerHDF5Open(comm, initFile.c_str(), FILE_MODE_READ, v.put()));
  PetscCall(VecLoad(natural, v));
  PetscCall(VecScatterBegin(scatter, natural, fstate.masses(), INSERT_VALUES, SCATTER_REVERSE));
  PetscCall(VecScatterEnd(scatter, natural, fstate.masses(), INSERT_VALUES, SCATTER_REVERSE));
  // Every entry checked: VecMin passes over NaN.  Counts: [not finite or negative,
  // mass in cells frame 0 says are empty, total mass, that stray mass].
  double counts[4] = {0.0, 0.0, 0.0, 0.0};
  const PetscScalar *m, *alpha;
  PetscCall(VecGetArrayRead(fstate.masses(), &m));
  PetscCall(VecGetArrayRead(db.alphaS(0), &alpha));
  for (PetscInt c = 0; c < L.numLocal(); ++c) {
    double cell = 0.0;
    for (int i = 0; i < nf; ++i) {
      const double v = m[c * nf + i];
      if (!(v >= 0.0) || !std::isfinite(v)) ++counts[0];
      else cell += v;
    }
    counts[2] += cell;
    if (cell > 0.0 && !(alpha[c] > 0.0)) {
      ++counts[1];
      counts[3] += cell;
    }
  }
  PetscCall(VecRestoreArrayRead(db.alphaS(0), &alpha));
  PetscCall(VecRestoreArrayRead(fstate.masses(), &m));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, counts, 4, MPI_DOUBLE, MPI_SUM, comm));
  PetscCheck(counts[0] == 0.0, comm, PETSC_ERR_USER_INPUT,
             "-init_file '%s': /masses holds %.0f negative or non-finite (NaN, inf) masses; expected masses >= 0 kg",
             initFile.c_str(), counts[0]);
  PetscCheck(counts[2] > 0.0, comm, PETSC_ERR_USER_INPUT,
             "-init_file '%s': /masses holds no mass at all; expected the kg of each fraction per cell",
             initFile.c_str());
  if (counts[1] > 0.0)
    PetscCall(PetscPrintf(comm,
                          "Warning: -init_file '%s' puts %.4g kg (%.2g %% of its mass) in %.0f cells that frame 0 "
                          "of the database says are empty; the first steps will move it with the bulk\n",
                          initFile.c_str(), counts[3], 100.0 * counts[3] / counts[2], counts[1]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace
} // namespace rcfd
