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
  std::vector<OwnedMat> full;
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
    full.push_back(std::move(T));
    share_.push_back(std::move(m));
  }
  // The chain's cells, then each frame's transfer over them (its full matrix
  // freed as soon as its part is taken, so the peak is one frame above the
  // full matrices').
  PetscCall(findChainCells(full));
  OwnedIS rows;
  {
    std::vector<PetscInt> global(cells_.size());
    for (size_t c = 0; c < cells_.size(); ++c) global[c] = db.layout().rowStart() + cells_[c];
    PetscCall(ISCreateGeneral(comm, static_cast<PetscInt>(global.size()), global.data(), PETSC_COPY_VALUES, rows.put()));
  }
  for (OwnedMat &T : full) {
    OwnedMat part;
    PetscCall(MatCreateSubMatrix(T, rows, rows, MAT_INITIAL_MATRIX, part.put()));
    T.reset();
    transfer_.push_back(std::move(part));
  }
  PetscCall(VecDuplicate(share_[0], meanShare_.put()));
  PetscCall(VecSet(meanShare_, 0.0));
  for (const OwnedVec &m : share_) PetscCall(VecAXPY(meanShare_, 1.0 / numFrames(), m));
  PetscCall(VecDuplicate(share_[0], meanAlpha_.put()));
  PetscCall(VecSet(meanAlpha_, 0.0));
  for (int k = 0; k < numFrames(); ++k) PetscCall(VecAXPY(meanAlpha_, 1.0 / numFrames(), db.alphaS(k)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FrameChain::findChainCells(const std::vector<OwnedMat> &full) {
  const Layout &layout = db_->layout();
  const MPI_Comm comm = layout.comm();
  const PetscInt start = layout.rowStart(), n = layout.numLocal();
  PetscInt N;
  PetscFunctionBeginUser;
  PetscCall(MatGetSize(full[0], &N, nullptr));
  // A cell is the chain's when it holds solid in a frame, when its row of a
  // frame is not the single entry 1 on the diagonal, or when a frame moves
  // its solid elsewhere (an off-diagonal entry of its column, which may be
  // another rank's row: marked over all cells and reduced).
  std::vector<unsigned char> marked(static_cast<size_t>(N), 0);
  for (size_t k = 0; k < full.size(); ++k) { // (the transfers are not made yet)
    const PetscScalar *pa;
    PetscCall(VecGetArrayRead(db_->alphaS(static_cast<int>(k)), &pa));
    for (PetscInt i = 0; i < n; ++i)
      if (pa[i] != 0.0) marked[static_cast<size_t>(start + i)] = 1;
    PetscCall(VecRestoreArrayRead(db_->alphaS(static_cast<int>(k)), &pa));
    for (PetscInt r = start; r < start + n; ++r) {
      PetscInt nc;
      const PetscInt *cols;
      const PetscScalar *vals;
      PetscCall(MatGetRow(full[k], r, &nc, &cols, &vals));
      if (nc != 1 || cols[0] != r || vals[0] != 1.0) marked[static_cast<size_t>(r)] = 1;
      for (PetscInt b = 0; b < nc; ++b)
        if (cols[b] != r) marked[static_cast<size_t>(cols[b])] = 1;
      PetscCall(MatRestoreRow(full[k], r, &nc, &cols, &vals));
    }
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, marked.data(), static_cast<int>(N), MPI_UNSIGNED_CHAR, MPI_MAX, comm));
  cells_.clear();
  for (PetscInt i = 0; i < n; ++i)
    if (marked[static_cast<size_t>(start + i)]) cells_.push_back(i);
  // Every rank's chain cells in chain order: the ranks own ascending PETSc
  // rows, so the marked rows in ascending order are that order.
  rowsAll_.clear();
  for (PetscInt r = 0; r < N; ++r)
    if (marked[static_cast<size_t>(r)]) rowsAll_.push_back(r);
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::vector<char> FrameChain::chainMask(const std::vector<PetscInt> &localCells) const {
  std::vector<char> local(static_cast<size_t>(db_->layout().numLocal()), 0), mask(cells_.size(), 0);
  for (PetscInt i : localCells) local[static_cast<size_t>(i)] = 1;
  for (size_t k = 0; k < cells_.size(); ++k) mask[k] = local[static_cast<size_t>(cells_[k])];
  return mask;
}

PetscErrorCode FrameChain::chainVector(Vec *x) const {
  PetscFunctionBeginUser;
  PetscCall(VecCreateMPI(db_->layout().comm(), numChainCells(), PETSC_DETERMINE, x));
  PetscCall(VecSet(*x, 0.0));
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
  PetscCall(VecCreateMPI(db_->layout().comm(), numChainCells() * columns, PETSC_DETERMINE, x));
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
  // The transfers hold the chain cells only; the other cells' rows are the
  // single entry 1 on the diagonal in every frame, summed here as they were
  // when the full matrices were averaged (the same additions).
  const Layout &layout = db_->layout();
  const PetscInt rowStart = layout.rowStart(), rowEnd = rowStart + layout.numLocal();
  const PetscInt colStart = rowStart, colEnd = rowEnd, n = rowEnd - rowStart;
  PetscInt N, chainStart;
  PetscCall(VecGetSize(share_[0], &N));
  PetscCall(MatGetOwnershipRange(transfer_[0], &chainStart, nullptr));
  std::vector<char> inChain(static_cast<size_t>(n), 0);
  for (PetscInt i : cells_) inChain[static_cast<size_t>(i)] = 1;
  // Per local row, its entries summed so far (column, value), sorted by
  // column; with Average::Mass, frame k's column j weighs its mass share,
  // gathered on every rank (N values, as the columns are global).
  std::vector<std::vector<std::pair<PetscInt, PetscScalar>>> rows(static_cast<size_t>(n));
  std::vector<std::pair<PetscInt, PetscScalar>> merged;
  std::vector<double> total;
  std::vector<PetscInt> globalCols;
  OwnedVec all;
  OwnedScatter toAll;
  if (average == Average::Mass) {
    PetscCall(VecScatterCreateToAll(share_[0], toAll.put(), all.put()));
    total.assign(static_cast<size_t>(N), 0.0);
  }
  const PetscScalar one = 1.0;
  for (int k = 0; k < numFrames(); ++k) {
    const PetscScalar *w = nullptr;
    if (average == Average::Mass) {
      PetscCall(VecScatterBegin(toAll, share_[k], all, INSERT_VALUES, SCATTER_FORWARD));
      PetscCall(VecScatterEnd(toAll, share_[k], all, INSERT_VALUES, SCATTER_FORWARD));
      PetscCall(VecGetArrayRead(all, &w));
      for (PetscInt j = 0; j < N; ++j) total[static_cast<size_t>(j)] += w[j];
    }
    PetscInt chainRow = chainStart;
    for (PetscInt r = 0; r < n; ++r) {
      PetscInt nc = 1;
      const PetscInt *chainCols = nullptr;
      const PetscScalar *vals = &one;
      const PetscInt diagonal = rowStart + r;
      const PetscInt *cols = &diagonal;
      if (inChain[static_cast<size_t>(r)]) {
        PetscCall(MatGetRow(transfer_[k], chainRow, &nc, &chainCols, &vals));
        globalCols.resize(static_cast<size_t>(nc));
        for (PetscInt b = 0; b < nc; ++b) globalCols[static_cast<size_t>(b)] = rowsAll_[static_cast<size_t>(chainCols[b])];
        cols = globalCols.data();
      }
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
      if (inChain[static_cast<size_t>(r)]) PetscCall(MatRestoreRow(transfer_[k], chainRow++, &nc, &chainCols, &vals));
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
