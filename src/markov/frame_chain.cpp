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

PetscErrorCode FrameChain::blockVector(PetscInt columns, Vec *x) const {
  PetscFunctionBeginUser;
  PetscCall(VecCreateMPI(db_->layout().comm(), db_->layout().numLocal() * columns, PETSC_DETERMINE, x));
  PetscCall(VecSetBlockSize(*x, columns));
  PetscCall(VecSet(*x, 0.0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FrameChain::averageChain(Average average, Mat *Q) const {
  const MPI_Comm comm = db_->layout().comm();
  PetscFunctionBeginUser;
  // Summed row by row (each row's entries merged over the frames in frame
  // order, sorted by column) rather than by MatAXPY with a different nonzero
  // pattern per frame, which rebuilt the whole sum K times (10 s of the 15 s
  // the eigenvalues took on the default bed).  The additions are the same, in
  // the same order, so the result is the same to the bit.
  PetscInt rowStart, rowEnd, colStart, colEnd, n, N;
  PetscCall(MatGetOwnershipRange(transfer_[0], &rowStart, &rowEnd));
  PetscCall(MatGetOwnershipRangeColumn(transfer_[0], &colStart, &colEnd));
  PetscCall(MatGetSize(transfer_[0], &N, nullptr));
  n = rowEnd - rowStart;
  // Per local row, its entries summed so far (column, value), sorted by
  // column; with Average::Mass, frame k's column j weighs its mass share,
  // gathered on every rank (N values, as the columns are global).
  std::vector<std::vector<std::pair<PetscInt, PetscScalar>>> rows(static_cast<size_t>(n));
  std::vector<std::pair<PetscInt, PetscScalar>> merged;
  std::vector<double> total;
  OwnedVec all;
  OwnedScatter toAll;
  if (average == Average::Mass) {
    PetscCall(VecScatterCreateToAll(share_[0], toAll.put(), all.put()));
    total.assign(static_cast<size_t>(N), 0.0);
  }
  for (int k = 0; k < numFrames(); ++k) {
    const PetscScalar *w = nullptr;
    if (average == Average::Mass) {
      PetscCall(VecScatterBegin(toAll, share_[k], all, INSERT_VALUES, SCATTER_FORWARD));
      PetscCall(VecScatterEnd(toAll, share_[k], all, INSERT_VALUES, SCATTER_FORWARD));
      PetscCall(VecGetArrayRead(all, &w));
      for (PetscInt j = 0; j < N; ++j) total[static_cast<size_t>(j)] += w[j];
    }
    for (PetscInt r = 0; r < n; ++r) {
      PetscInt nc;
      const PetscInt *cols;
      const PetscScalar *vals;
      PetscCall(MatGetRow(transfer_[k], rowStart + r, &nc, &cols, &vals));
      std::vector<std::pair<PetscInt, PetscScalar>> &row = rows[static_cast<size_t>(r)];
      merged.clear();
      size_t a = 0;
      for (PetscInt b = 0; b < nc; ++b) {
        const PetscScalar v = w ? vals[b] * w[cols[b]] : vals[b];
        while (a < row.size() && row[a].first < cols[b]) merged.push_back(row[a++]);
        if (a < row.size() && row[a].first == cols[b])
          merged.emplace_back(cols[b], row[a++].second + v);
        else
          merged.emplace_back(cols[b], v);
      }
      merged.insert(merged.end(), row.begin() + static_cast<std::ptrdiff_t>(a), row.end());
      row.swap(merged);
      PetscCall(MatRestoreRow(transfer_[k], rowStart + r, &nc, &cols, &vals));
    }
    if (w) PetscCall(VecRestoreArrayRead(all, &w));
  }
  std::vector<PetscInt> dnz(static_cast<size_t>(n), 0), onz(static_cast<size_t>(n), 0);
  for (PetscInt r = 0; r < n; ++r)
    for (const auto &e : rows[static_cast<size_t>(r)])
      ++(e.first >= colStart && e.first < colEnd ? dnz : onz)[static_cast<size_t>(r)];
  OwnedMat sum;
  PetscCall(MatCreate(comm, sum.put()));
  PetscCall(MatSetSizes(sum, n, colEnd - colStart, N, N));
  PetscCall(MatSetType(sum, MATAIJ));
  PetscCall(MatSeqAIJSetPreallocation(sum, 0, dnz.data()));
  PetscCall(MatMPIAIJSetPreallocation(sum, 0, dnz.data(), 0, onz.data()));
  const double scale = 1.0 / numFrames();
  std::vector<PetscInt> cols;
  std::vector<PetscScalar> vals;
  for (PetscInt r = 0; r < n; ++r) {
    cols.clear();
    vals.clear();
    for (const auto &e : rows[static_cast<size_t>(r)]) {
      cols.push_back(e.first);
      if (average == Average::Mass) {
        const double t = total[static_cast<size_t>(e.first)];
        vals.push_back(e.second * (t > 0 ? 1.0 / t : 0.0));
      } else {
        vals.push_back(e.second * scale);
      }
    }
    const PetscInt row = rowStart + r;
    PetscCall(MatSetValues(sum, 1, &row, static_cast<PetscInt>(cols.size()), cols.data(), vals.data(), INSERT_VALUES));
  }
  PetscCall(MatAssemblyBegin(sum, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(sum, MAT_FINAL_ASSEMBLY));
  *Q = sum.get();
  PetscCall(PetscObjectReference(reinterpret_cast<PetscObject>(*Q)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
