#include "path/database_recurrence.hpp"
#include "base/petsc_compat.hpp"

#include "base/collective.hpp"

namespace rcfd {

std::string recurrenceDatasetName(RecurrenceNorm norm) {
  return std::string("recurrence_") + recurrenceNormName(norm);
}

// Rank 0 computes the matrix from the frames in natural cell order, exactly as
// one rank does, and broadcasts it: partial sums per rank would change its last
// bits with the number of ranks, and a stitching path, which ranks candidates
// by these values, would then differ between 1 and 2 ranks.  The price is
// K x cells doubles on rank 0 while the matrix is computed.
PetscErrorCode computeRecurrence(const Database &db, RecurrenceNorm norm, std::vector<double> *R) {
  const int K = db.numFrames();
  const MPI_Comm comm = db.layout().comm();
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  std::vector<std::vector<double>> natural(K);
  for (int k = 0; k < K; ++k) {
    PetscCall(db.layout().gatherToAll(1, db.alphaS(k), &natural[k]));
    if (rank != 0) std::vector<double>().swap(natural[k]);
  }
  R->assign(static_cast<size_t>(K) * K, 0.0);
  PetscCall(collectively(comm, [&] {
    if (rank != 0) return;
    std::vector<const double *> frames(K);
    for (int k = 0; k < K; ++k) frames[k] = natural[k].data();
    const auto &volume = db.mesh().cellVolume;
    std::vector<double> partial;
    recurrencePartial(norm, frames, volume.data(), volume.size(), partial);
    *R = std::move(partial);
    recurrenceFinish(norm, K, *R);
  }));
  PetscCallMPI(MPI_Bcast(R->data(), K * K, MPI_DOUBLE, 0, comm));
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
