#include "rcfd/measured_drift_field.hpp"
#include "base/petsc_compat.hpp"

#include "rcfd/face_exchange.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace rcfd {

namespace {

int blockCount(int cells, int per) { return (cells + per - 1) / per; }

std::string millimetres(const std::vector<double> &d) {
  std::string out;
  char text[32];
  for (std::size_t i = 0; i < d.size(); ++i) {
    std::snprintf(text, sizeof text, "%s%.4g", i ? ", " : "", d[i] * 1e3);
    out += text;
  }
  return out + " mm";
}

} // namespace

int DriftRegions::count(const BoxSpec &box) const {
  return blockCount(box.nx, rx) * blockCount(box.ny, ry) * blockCount(box.nz, rz);
}

int DriftRegions::regionOf(const BoxSpec &box, int cell) const {
  const int i = cell % box.nx, j = (cell / box.nx) % box.ny, k = cell / (box.nx * box.ny);
  return i / rx + blockCount(box.nx, rx) * (j / ry + blockCount(box.ny, ry) * (k / rz));
}

PetscErrorCode MeasuredDriftField::setUp(const Database &db, const std::vector<double> &diameters,
                                         FaceExchange &exchange) {
  const MPI_Comm comm = db.layout().comm();
  const char *path = db.path().c_str();
  std::vector<double> layout, field;
  int layoutCols = 0, fieldCols = 0;
  PetscFunctionBeginUser;
  PetscCheck(db.formatVersion() > 0, comm, PETSC_ERR_USER_INPUT,
             "-drift_model measured needs a database file with a measured drift field, not one made in memory "
             "(a blend of databases)");
  PetscCall(db.readMatrix(kMeasuredDriftLayoutName, &layout, &layoutCols));
  PetscCall(db.readMatrix(kMeasuredDriftFieldName, &field, &fieldCols));
  PetscCheck(!layout.empty() && !field.empty(), comm, PETSC_ERR_USER_INPUT,
             "Database '%s' has no measured drift field (/extra/%s): -drift_model measured needs a database "
             "built from particles by an rcfd that stores it (rebuild it with rcfd build)",
             path, kMeasuredDriftFieldName);
  PetscCheck(db.mesh().onBoxLattice(), comm, PETSC_ERR_USER_INPUT,
             "Database '%s': the measured drift field needs a box mesh", path);
  const BoxSpec &box = db.mesh().boxSpec();
  const int classes = layoutCols - 3;
  PetscCheck(layout.size() == static_cast<std::size_t>(layoutCols) && classes >= 1 && layout[0] >= 1 &&
                 layout[1] >= 1 && layout[2] >= 1 && fieldCols == kMeasuredDriftValuesPerClass * classes,
             comm, PETSC_ERR_FILE_UNEXPECTED,
             "Database '%s': /extra/%s should be one row of the region size (3 cell counts) and the class "
             "diameters, and /extra/%s have %d columns per class",
             path, kMeasuredDriftLayoutName, kMeasuredDriftFieldName, kMeasuredDriftValuesPerClass);
  blocks = {static_cast<int>(layout[0]), static_cast<int>(layout[1]), static_cast<int>(layout[2])};
  stored.assign(layout.begin() + 3, layout.end());
  numRegions = blocks.count(box);
  const std::size_t rows = field.size() / fieldCols;
  PetscCheck(rows == static_cast<std::size_t>(db.numFrames()) * numRegions, comm, PETSC_ERR_USER_INPUT,
             "Database '%s': the measured drift field has %zu rows, not %d frames x %d regions of %d x %d x %d "
             "cells (a -db_frames window is not supported with -drift_model measured)",
             path, rows, db.numFrames(), numRegions, blocks.rx, blocks.ry, blocks.rz);
  // Each fraction drifts with the stored class of its diameter (within 1 %).
  nf = static_cast<int>(diameters.size());
  std::vector<int> classOf(nf, -1);
  for (int i = 0; i < nf; ++i) {
    for (int c = 0; c < classes; ++c)
      if (std::fabs(stored[c] - diameters[i]) <= 0.01 * diameters[i] &&
          (classOf[i] < 0 || std::fabs(stored[c] - diameters[i]) < std::fabs(stored[classOf[i]] - diameters[i])))
        classOf[i] = c;
    PetscCheck(classOf[i] >= 0, comm, PETSC_ERR_USER_INPUT,
               "-drift_model measured: fraction %d (%.4g mm) matches no class of the measured drift field of "
               "'%s' (%s) within 1 %%",
               i, diameters[i] * 1e3, path, millimetres(stored).c_str());
  }
  frames = db.numFrames();
  velocity.assign(static_cast<std::size_t>(frames) * numRegions * nf, 0.0);
  largest.assign(frames, 0.0);
  for (std::size_t row = 0; row < rows; ++row)
    for (int i = 0; i < nf; ++i) {
      const double *v = field.data() + row * fieldCols + kMeasuredDriftValuesPerClass * classOf[i];
      PetscCheck(std::isfinite(v[0]) && std::isfinite(v[1]) && v[1] >= 0, comm, PETSC_ERR_FILE_UNEXPECTED,
                 "Database '%s': the measured drift field has a velocity or count that is not a finite number "
                 "(frame %zu, region %zu)",
                 path, row / numRegions, row % numRegions);
      const double u = v[1] > 0 ? v[0] : 0.0; // no particle of the class there: no drift of its own
      velocity[row * nf + i] = u;
      largest[row / numRegions] = std::max(largest[row / numRegions], std::fabs(u));
    }
  // The natural cell of every gathered cell (own cells, then ghosts).
  OwnedVec natural;
  std::vector<double> gathered;
  PetscCall(VecDuplicate(db.alphaS(0), natural.put()));
  PetscScalar *n;
  PetscCall(VecGetArrayWrite(natural, &n));
  for (PetscInt r = 0; r < db.layout().numLocal(); ++r)
    n[r] = static_cast<double>(db.layout().naturalCell(db.layout().rowStart() + r));
  PetscCall(VecRestoreArrayWrite(natural, &n));
  PetscCall(exchange.gatherScalar(natural, &gathered));
  regionOfGathered.resize(gathered.size());
  for (std::size_t c = 0; c < gathered.size(); ++c)
    regionOfGathered[c] = blocks.regionOf(box, db.mesh().boxCell(static_cast<int>(gathered[c]))); // a vessel: its box cell
  madeFrom = db.identity();
  PetscFunctionReturn(PETSC_SUCCESS);
}

void MeasuredDriftField::speeds(int k, double *up, double *down) const {
  const double *frame = velocity.data() + static_cast<std::size_t>(k) * numRegions * nf;
  for (std::size_t c = 0; c < regionOfGathered.size(); ++c) {
    const double *u = frame + static_cast<std::size_t>(regionOfGathered[c]) * nf;
    for (int i = 0; i < nf; ++i) {
      up[c * nf + i] = std::max(u[i], 0.0);
      down[c * nf + i] = std::max(-u[i], 0.0);
    }
  }
}

} // namespace rcfd
