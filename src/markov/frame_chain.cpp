#include "markov/frame_chain.hpp"
#include "base/petsc_compat.hpp"

#include <algorithm>
#include <cmath>

namespace rcfd {

const char *averageName(FrameChain::Average a) { return a == FrameChain::Average::Mass ? "mass" : "plain"; }

PetscErrorCode FrameChain::setUp(const Database &db) {
  const MPI_Comm comm = db.layout().comm();
  PetscFunctionBeginUser;
  db_ = &db;
  transfer_.clear();
  share_.clear();
  PetscCheck(db.hasShifts() && db.numFrames() > 0, comm, PETSC_ERR_ARG_WRONGSTATE,
             "Database '%s' was loaded without its shifts: the chain needs them", db.path().c_str());
  OwnedVec ones, sums, volume;
  PetscCall(VecDuplicate(db.alphaS(0), ones.put()));
  PetscCall(VecDuplicate(db.alphaS(0), sums.put()));
  PetscCall(VecDuplicate(db.alphaS(0), volume.put()));
  PetscCall(VecSet(ones, 1.0));
  PetscScalar *pv;
  PetscCall(VecGetArrayWrite(volume, &pv));
  std::copy(db.localVolumes().begin(), db.localVolumes().end(), pv);
  PetscCall(VecRestoreArrayWrite(volume, &pv));
  // Every frame is checked before any is used: the chain of a database
  // whose frames lose or make mass is not a Markov chain.
  columnError_ = 0.0;
  for (int k = 0; k < db.numFrames(); ++k) {
    OwnedMat T;
    PetscCall(db.shiftMatrix(k, &T));
    PetscCall(MatMultTranspose(T, ones, sums));
    PetscCall(VecShift(sums, -1.0));
    PetscReal err;
    PetscCall(VecNorm(sums, NORM_INFINITY, &err));
    PetscCheck(err <= kColumnTolerance, comm, PETSC_ERR_USER_INPUT,
               "Database '%s' does not conserve mass: a column of frame %d's shift sums to 1 %+.3g, more than "
               "%.0e off, so its frames are no Markov chain of the solid",
               db.path().c_str(), k, static_cast<double>(err), kColumnTolerance);
    columnError_ = std::max(columnError_, static_cast<double>(err));
    OwnedVec m;
    PetscCall(VecDuplicate(db.alphaS(k), m.put()));
    PetscCall(VecPointwiseMult(m, db.alphaS(k), volume));
    PetscReal total;
    PetscCall(VecSum(m, &total));
    PetscCheck(total > 0, comm, PETSC_ERR_USER_INPUT, "Database '%s': frame %d holds no solid", db.path().c_str(), k);
    PetscCall(VecScale(m, 1.0 / total));
    transfer_.push_back(std::move(T));
    share_.push_back(std::move(m));
  }
  PetscCall(VecDuplicate(share_[0], meanShare_.put()));
  PetscCall(VecSet(meanShare_, 0.0));
  for (const OwnedVec &m : share_) PetscCall(VecAXPY(meanShare_, 1.0 / numFrames(), m));
  PetscCall(VecDuplicate(share_[0], meanAlpha_.put()));
  PetscCall(VecSet(meanAlpha_, 0.0));
  for (int k = 0; k < numFrames(); ++k) PetscCall(VecAXPY(meanAlpha_, 1.0 / numFrames(), db.alphaS(k)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FrameChain::blockTransfers(PetscInt columns, std::vector<OwnedMat> *maij) const {
  PetscFunctionBeginUser;
  maij->clear();
  for (const OwnedMat &T : transfer_) {
    OwnedMat m;
    PetscCall(MatCreateMAIJ(T, columns, m.put()));
    maij->push_back(std::move(m));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FrameChain::averageChain(Average average, Mat *Q) const {
  PetscFunctionBeginUser;
  OwnedMat sum;
  OwnedVec weight, total;
  PetscCall(VecDuplicate(meanShare_, weight.put()));
  PetscCall(VecDuplicate(meanShare_, total.put()));
  PetscCall(VecSet(total, 0.0));
  for (int k = 0; k < numFrames(); ++k) {
    OwnedMat scaled;
    PetscCall(MatDuplicate(transfer_[k], MAT_COPY_VALUES, scaled.put()));
    if (average == Average::Mass) {
      PetscCall(VecCopy(share_[k], weight));
      PetscCall(MatDiagonalScale(scaled, nullptr, weight));
      PetscCall(VecAXPY(total, 1.0, weight));
    }
    if (!sum)
      sum = std::move(scaled);
    else
      PetscCall(MatAXPY(sum, 1.0, scaled, DIFFERENT_NONZERO_PATTERN));
  }
  if (average == Average::Mass) {
    PetscCall(VecCopy(total, weight));
    PetscScalar *pw;
    PetscInt n;
    PetscCall(VecGetLocalSize(weight, &n));
    PetscCall(VecGetArray(weight, &pw));
    for (PetscInt i = 0; i < n; ++i) pw[i] = pw[i] > 0 ? 1.0 / pw[i] : 0.0;
    PetscCall(VecRestoreArray(weight, &pw));
    PetscCall(MatDiagonalScale(sum, nullptr, weight));
  } else {
    PetscCall(MatScale(sum, 1.0 / numFrames()));
  }
  *Q = sum.get();
  PetscCall(PetscObjectReference(reinterpret_cast<PetscObject>(*Q)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
