#include "rcfd/agitation.hpp"
#include "base/petsc_compat.hpp"

#include <algorithm>

namespace rcfd {

PetscErrorCode parseAgitationMeasure(const std::string &name, AgitationMeasure *measure) {
  PetscFunctionBeginUser;
  const bool leaving = name == "leaving";
  PetscCheck(leaving || name == "dispersion", PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
             "the agitation measure '%s' is not known; use leaving or dispersion", name.c_str());
  *measure = leaving ? AgitationMeasure::LeavingShare : AgitationMeasure::Dispersion;
  PetscFunctionReturn(PETSC_SUCCESS);
}

const char *agitationMeasureName(AgitationMeasure m) {
  return m == AgitationMeasure::LeavingShare ? "leaving" : "dispersion";
}

PetscErrorCode AgitationField::setUp(const Database &db, AgitationMeasure measure) {
  PetscFunctionBeginUser;
  const Layout &layout = db.layout();
  const MPI_Comm comm = layout.comm();
  PetscCheck(db.hasShifts(), comm, PETSC_ERR_ARG_WRONGSTATE,
             "Database '%s' was loaded without its shifts; the agitation field needs them", db.path().c_str());
  kind = measure;
  madeFrom = db.identity();
  const int K = db.numFrames();
  const PetscInt n = layout.numLocal(), start = layout.rowStart();
  const Mesh &mesh = db.mesh();
  const double dt = db.metadata().dtRec;
  values.assign(K, std::vector<double>(n, 0.0));
  OwnedVec column;
  PetscCall(VecCreateMPI(comm, n, layout.numCells(), column.put()));
  for (int k = 0; k < K; ++k) {
    OwnedMat T;
    PetscCall(db.shiftMatrix(k, &T));
    if (measure == AgitationMeasure::LeavingShare) {
      PetscCall(MatGetDiagonal(T, column));
    } else {
      // Entry (j, i) moves solid of cell i to cell j: add its weighted squared
      // distance to cell i, which may live on another rank.
      PetscCall(VecZeroEntries(column));
      for (PetscInt j = start; j < start + n; ++j) {
        PetscInt ncols;
        const PetscInt *cols;
        const PetscScalar *vals;
        PetscCall(MatGetRow(T, j, &ncols, &cols, &vals));
        const Vec3 &xj = mesh.cellCentre[layout.naturalCell(j)];
        for (PetscInt e = 0; e < ncols; ++e) {
          const Vec3 &xi = mesh.cellCentre[layout.naturalCell(cols[e])];
          const double d2 = (xj[0] - xi[0]) * (xj[0] - xi[0]) + (xj[1] - xi[1]) * (xj[1] - xi[1]) +
                            (xj[2] - xi[2]) * (xj[2] - xi[2]);
          if (d2 > 0.0) PetscCall(VecSetValue(column, cols[e], vals[e] * d2 / dt, ADD_VALUES));
        }
        PetscCall(MatRestoreRow(T, j, &ncols, &cols, &vals));
      }
      PetscCall(VecAssemblyBegin(column));
      PetscCall(VecAssemblyEnd(column));
    }
    const PetscScalar *c, *alpha;
    PetscCall(VecGetArrayRead(column, &c));
    PetscCall(VecGetArrayRead(db.alphaS(k), &alpha));
    for (PetscInt i = 0; i < n; ++i) {
      const double a = measure == AgitationMeasure::LeavingShare ? 1.0 - c[i] : c[i];
      values[k][i] = alpha[i] > 0.0 ? std::max(0.0, a) : 0.0; // round-off never makes it negative
    }
    PetscCall(VecRestoreArrayRead(db.alphaS(k), &alpha));
    PetscCall(VecRestoreArrayRead(column, &c));
  }
  PetscCall(normalise(db));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode AgitationField::setValues(const Database &db, AgitationMeasure measure,
                                         std::vector<std::vector<double>> perFrame) {
  PetscFunctionBeginUser;
  const MPI_Comm comm = db.layout().comm();
  PetscCheck((int)perFrame.size() == db.numFrames(), comm, PETSC_ERR_ARG_SIZ,
             "An agitation field needs one set of values per frame of '%s' (%d), got %zu",
             db.path().c_str(), db.numFrames(), perFrame.size());
  for (const auto &f : perFrame)
    PetscCheck((PetscInt)f.size() == db.layout().numLocal(), comm, PETSC_ERR_ARG_SIZ,
               "An agitation field needs one value per local cell (%d), got %zu",
               (int)db.layout().numLocal(), f.size());
  kind = measure;
  madeFrom = db.identity();
  values = std::move(perFrame);
  PetscCall(normalise(db));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode AgitationField::normalise(const Database &db) {
  PetscFunctionBeginUser;
  const MPI_Comm comm = db.layout().comm();
  double sums[2] = {0.0, 0.0}; // sum alpha V a, sum alpha V
  largest = 0.0;
  for (int k = 0; k < (int)values.size(); ++k) {
    const PetscScalar *alpha;
    PetscCall(VecGetArrayRead(db.alphaS(k), &alpha));
    for (std::size_t i = 0; i < values[k].size(); ++i) {
      const double solid = alpha[i] * db.localVolumes()[i];
      sums[0] += solid * values[k][i];
      sums[1] += solid;
      largest = std::max(largest, values[k][i]);
    }
    PetscCall(VecRestoreArrayRead(db.alphaS(k), &alpha));
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_DOUBLE, MPI_SUM, comm));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &largest, 1, MPI_DOUBLE, MPI_MAX, comm));
  mean = sums[1] > 0.0 ? sums[0] / sums[1] : 0.0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
