// A loaded Database (include/rcfd/database.hpp): its shift matrices, size,
// mass consistency, extra matrices and -db_view.  Loading is in
// database_loader.cpp, writing in database_writer.cpp.
#include "rcfd/database.hpp"
#include "base/petsc_compat.hpp"

#include "base/collective.hpp"
#include "base/h5.hpp"
#include "database/compact_frames.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace rcfd {

Database::Database() = default;
Database::~Database() = default;

PetscErrorCode Database::shiftMatrix(int k, OwnedMat *T) const {
  PetscFunctionBeginUser;
  PetscCheck(hasShifts(), layout_.comm(), PETSC_ERR_ARG_WRONGSTATE,
             "Database '%s' was loaded without its shifts", path_.c_str());
  PetscCheck(k >= 0 && k < numFrames(), layout_.comm(), PETSC_ERR_ARG_OUTOFRANGE,
             "Frame %d of database '%s', which has %d", k, path_.c_str(), numFrames());
  PetscCall(shiftMatrixOf(frames_[k], layout_, ghostRows_, meta.weightBits, T));
  PetscFunctionReturn(PETSC_SUCCESS);
}

size_t Database::frameBytes() const {
  size_t bytes = ghostRows_.size() * sizeof(PetscInt);
  for (const CompactFrame &f : frames_) bytes += f.bytes();
  return bytes;
}

PetscErrorCode Database::consistency(std::vector<double> *residual) const {
  PetscFunctionBeginUser;
  residual->clear();
  if (!hasShifts() || numFrames() < 2) PetscFunctionReturn(PETSC_SUCCESS);
  OwnedVec vol, ma, mb, moved;
  PetscCall(VecDuplicate(alpha[0], vol.put()));
  PetscCall(VecDuplicate(alpha[0], ma.put()));
  PetscCall(VecDuplicate(alpha[0], mb.put()));
  PetscCall(VecDuplicate(alpha[0], moved.put()));
  PetscScalar *pv;
  PetscCall(VecGetArrayWrite(vol, &pv));
  std::copy(volumes.begin(), volumes.end(), pv);
  PetscCall(VecRestoreArrayWrite(vol, &pv));
  for (int k = 0; k + 1 < numFrames(); ++k) {
    PetscReal diff, total;
    PetscCall(VecPointwiseMult(ma, vol, alpha[k]));
    PetscCall(VecPointwiseMult(mb, vol, alpha[k + 1]));
    OwnedMat T;
    PetscCall(shiftMatrix(k, &T));
    PetscCall(MatMult(T, ma, moved));
    PetscCall(VecNorm(ma, NORM_1, &total));
    PetscCall(VecAXPY(moved, -1.0, mb));
    PetscCall(VecNorm(moved, NORM_1, &diff));
    residual->push_back(total > 0 ? diff / total : 0.0);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Database::readMatrix(const std::string &name, std::vector<double> *rowMajor,
                                    int *cols) const {
  PetscFunctionBeginUser;
  rowMajor->clear();
  *cols = 0;
  PetscCall(collectively(layout_.comm(), [&] {
    h5::File f = h5::File::openRead(path_, MPI_COMM_NULL);
    const std::string ds = "/extra/" + name;
    if (!f.exists(ds)) return;
    const auto dims = f.extents(ds);
    if (dims.size() != 2) throw h5::Error("database '" + path_ + "': " + ds + " is not a matrix");
    *rowMajor = f.read<double>(ds);
    *cols = static_cast<int>(dims[1]);
  }));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Database::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  const Mesh &m = mesh_;
  PetscCall(PetscViewerASCIIPrintf(viewer, "Database %s\n", path_.c_str()));
  PetscCall(PetscViewerASCIIPushTab(viewer));
  if (m.isBox()) {
    const BoxSpec &b = m.boxSpec();
    PetscCall(PetscViewerASCIIPrintf(
        viewer, "mesh: box %d x %d x %d cells = %d, %.4g x %.4g x %.4g m from (%.4g, %.4g, %.4g)\n",
        b.nx, b.ny, b.nz, m.numCells(), b.length[0], b.length[1], b.length[2], b.origin[0],
        b.origin[1], b.origin[2]));
  } else if (m.isMasked()) {
    const BoxSpec &b = m.boxSpec();
    PetscCall(PetscViewerASCIIPrintf(
        viewer,
        "mesh: vessel %s\n      cut from the box %d x %d x %d cells, %.4g x %.4g x %.4g m from (%.4g, %.4g, %.4g): "
        "%d cells inside (%.1f %% of the box's), %.6g m^3 (%.1f %% of the box's)\n",
        m.vessel().c_str(), b.nx, b.ny, b.nz, b.length[0], b.length[1], b.length[2], b.origin[0], b.origin[1],
        b.origin[2], m.numCells(), 100.0 * m.numCells() / b.numCells(), m.totalVolume(),
        100.0 * m.totalVolume() / (b.length[0] * b.length[1] * b.length[2])));
  }
  PetscCall(PetscViewerASCIIPrintf(viewer, "faces: %d internal, %d boundary\n", m.numFaces(),
                                   m.numBoundaryFaces()));
  PetscCall(PetscViewerASCIIPrintf(viewer, "frames: %d every %.6g s (%.6g s recorded)\n",
                                   numFrames(), meta.dtRec, numFrames() * meta.dtRec));
  PetscCall(PetscViewerASCIIPrintf(viewer, "solid density: %g kg/m^3, gravity (%g, %g, %g) m/s^2\n",
                                   meta.solidDensity, meta.gravity[0], meta.gravity[1],
                                   meta.gravity[2]));
  PetscCall(PetscViewerASCIIPrintf(viewer, "source: %s\n", meta.source.c_str()));
  const OperatingConditions &c = meta.conditions;
  if (std::isfinite(c.superficialVelocity) || std::isfinite(c.gasDensity) || std::isfinite(c.gasKinematicViscosity))
    PetscCall(PetscViewerASCIIPrintf(viewer, "recorded at: u_sup %g m/s, gas density %g kg/m^3, gas kinematic viscosity %g m^2/s (nan: not recorded)\n",
                                     c.superficialVelocity, c.gasDensity, c.gasKinematicViscosity));
  if (hasShifts()) {
    // nonzeros (a row not held is an identity row of one entry), moving entries, narrow ones, bytes
    double counts[4] = {0.0, 0.0, 0.0, static_cast<double>(frameBytes())};
    for (const CompactFrame &f : frames_) {
      counts[0] += static_cast<double>(f.numEntries() + layout_.numLocal() - f.numRows());
      counts[1] += static_cast<double>(f.numEntries());
      counts[2] += static_cast<double>(f.offset.size());
    }
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, counts, 4, MPI_DOUBLE, MPI_SUM, layout_.comm()));
    const double nnz = counts[0], moving = counts[1];
    std::vector<double> res;
    PetscCall(consistency(&res));
    const double worst = res.empty() ? 0.0 : *std::max_element(res.begin(), res.end());
    double colErr = maxColumnError;
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &colErr, 1, MPI_DOUBLE, MPI_MAX, layout_.comm()));
    PetscCall(PetscViewerASCIIPrintf(viewer, "shift nonzeros: %.3g per column on average\n",
                                     nnz / numFrames() / m.numCells()));
    char weights[64] = "full-precision weights";
    if (meta.weightBits > 0) std::snprintf(weights, sizeof weights, "weights quantised to 2^-%d", meta.weightBits);
    PetscCall(PetscViewerASCIIPrintf(
        viewer, "compact frames: %.1f MB on all ranks, %.3g moving entries per cell and frame, %.0f %% of them with 16-bit column offsets, %s\n",
        counts[3] / 1e6, moving / numFrames() / m.numCells(), moving > 0 ? 100.0 * counts[2] / moving : 100.0,
        weights));
    PetscCall(PetscViewerASCIIPrintf(viewer, "largest |column sum - 1| before rescaling: %.3g\n",
                                     colErr));
    PetscCall(PetscViewerASCIIPrintf(
        viewer, "mass consistency |T_k a_k - a_k+1|_1 / |a_k|_1: largest %.3g over %zu pairs\n",
        worst, res.size()));
  }
  PetscCall(PetscViewerASCIIPopTab(viewer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
