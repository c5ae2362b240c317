#include "path/database_recurrence.hpp"
#include "base/petsc_compat.hpp"

#include "base/collective.hpp"

namespace rcfd {

std::string recurrenceDatasetName(RecurrenceNorm norm) {
  return std::string("recurrence_") + recurrenceNormName(norm);
}

PetscErrorCode computeRecurrence(const Database &db, RecurrenceNorm norm, std::vector<double> *R) {
  const int K = db.numFrames();
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(db.layout().comm(), &rank));
  std::vector<const double *> frames(K);
  for (int k = 0; k < K; ++k) PetscCall(VecGetArrayRead(db.alphaS(k), &frames[k]));
  std::vector<double> partial;
  PetscCall(collectively(db.layout().comm(), [&] {
    recurrencePartial(norm, frames, db.localVolumes().data(), db.localVolumes().size(), partial);
  }));
  for (int k = 0; k < K; ++k) PetscCall(VecRestoreArrayRead(db.alphaS(k), &frames[k]));
  R->assign(static_cast<size_t>(K) * K, 0.0);
  PetscCallMPI(MPI_Reduce(partial.data(), R->data(), K * K, MPI_DOUBLE,
                          recurrenceNeedsMaxReduction(norm) ? MPI_MAX : MPI_SUM, 0,
                          db.layout().comm()));
  PetscCall(collectively(db.layout().comm(), [&] {
    if (rank == 0) recurrenceFinish(norm, K, *R);
  }));
  PetscCallMPI(MPI_Bcast(R->data(), K * K, MPI_DOUBLE, 0, db.layout().comm()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode loadOrComputeRecurrence(const Database &db, RecurrenceNorm norm,
                                       std::vector<double> *R, bool *stored) {
  int cols = 0;
  PetscFunctionBeginUser;
  *stored = false;
  PetscCall(db.readMatrix(recurrenceDatasetName(norm), R, &cols));
  if (cols == db.numFrames() && R->size() == static_cast<size_t>(cols) * cols) {
    *stored = true;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(computeRecurrence(db, norm, R));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
