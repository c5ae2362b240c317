#include "operator/moving_rows.hpp"

#include <algorithm>

namespace rcfd {
namespace {

// New masses of the moving rows, summed in column order like PETSc's MAIJ
// product (so one rank gives the same bits), then written back once every
// old mass has been read.  NF > 0 fixes the number of fractions at compile
// time; NF = 0 reads it at run time.
template <int NF>
void moveRows(const std::vector<int32_t> &rowsMoving, const std::vector<int32_t> &ptr,
              const std::vector<int32_t> &col, const std::vector<double> &val, double *x,
              const double *ghost, PetscInt nlocal, int nfRuntime, double *out) {
  const int nf = NF > 0 ? NF : nfRuntime;
  const size_t rows = rowsMoving.size();
  double sum[NF > 0 ? NF : kMaxFractions];
  for (size_t r = 0; r < rows; ++r) {
    for (int i = 0; i < nf; ++i) sum[i] = 0.0;
    for (int32_t e = ptr[r]; e < ptr[r + 1]; ++e) {
      const int32_t c = col[e];
      const double *src = c < nlocal ? x + static_cast<size_t>(c) * nf
                                     : ghost + static_cast<size_t>(c - nlocal) * nf;
      const double v = val[e];
      for (int i = 0; i < nf; ++i) sum[i] += v * src[i];
    }
    for (int i = 0; i < nf; ++i) out[r * nf + i] = sum[i];
  }
  for (size_t r = 0; r < rows; ++r) {
    double *dst = x + static_cast<size_t>(rowsMoving[r]) * nf;
    for (int i = 0; i < nf; ++i) dst[i] = out[r * nf + i];
  }
}

// This rank's rows of a frame straight from PETSc's storage: the diagonal
// block (columns of own cells, numbered locally) and the off-diagonal block
// (columns of other ranks' cells, numbered through colmap).  Faster than a
// MatGetRow per row, which merges and sorts the two.
class LocalBlocks {
public:
  PetscErrorCode open(Mat T) {
    PetscBool mpi;
    PetscFunctionBeginUser;
    PetscCall(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(T), MATMPIAIJ, &mpi));
    if (mpi) PetscCall(MatMPIAIJGetSeqAIJ(T, &diag, &off, &colmap));
    else diag = T;
    PetscCall(openBlock(diag, &d));
    if (off) {
      PetscCall(openBlock(off, &o));
      PetscCall(MatGetSize(off, nullptr, &offColumns));
    }
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscErrorCode close() {
    PetscFunctionBeginUser;
    PetscCall(closeBlock(diag, &d));
    if (off) PetscCall(closeBlock(off, &o));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  struct Block {
    PetscInt n = 0;
    const PetscInt *i = nullptr, *j = nullptr;
    const PetscScalar *v = nullptr;
  } d, o;
  const PetscInt *colmap = nullptr; // global column of each off-diagonal column
  PetscInt offColumns = 0;

private:
  static PetscErrorCode openBlock(Mat A, Block *b) {
    PetscBool done;
    PetscFunctionBeginUser;
    PetscCall(MatGetRowIJ(A, 0, PETSC_FALSE, PETSC_FALSE, &b->n, &b->i, &b->j, &done));
    PetscCheck(done, PETSC_COMM_SELF, PETSC_ERR_SUP, "The shift matrix does not give its CSR arrays");
    PetscCall(MatSeqAIJGetArrayRead(A, &b->v));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  static PetscErrorCode closeBlock(Mat A, Block *b) {
    PetscBool done;
    PetscFunctionBeginUser;
    PetscCall(MatSeqAIJRestoreArrayRead(A, &b->v));
    PetscCall(MatRestoreRowIJ(A, 0, PETSC_FALSE, PETSC_FALSE, &b->n, &b->i, &b->j, &done));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  Mat diag = nullptr, off = nullptr;
};

} // namespace

PetscErrorCode MovingRows::setUp(const Database &db, int numFractions) {
  PetscFunctionBeginUser;
  const Layout &L = db.layout();
  nf = numFractions;
  PetscCheck(nf >= 1 && nf <= kMaxFractions, L.comm(), PETSC_ERR_ARG_OUTOFRANGE,
             "The shift handles 1 to %d fractions, got %d", kMaxFractions, nf);
  nlocal = L.numLocal();

  // The off-rank source cells of all frames.
  ghostRows.clear();
  for (int k = 0; k < db.numFrames(); ++k) {
    LocalBlocks T;
    PetscCall(T.open(db.shift(k)));
    ghostRows.insert(ghostRows.end(), T.colmap, T.colmap + T.offColumns);
    PetscCall(T.close());
  }
  std::sort(ghostRows.begin(), ghostRows.end());
  ghostRows.erase(std::unique(ghostRows.begin(), ghostRows.end()), ghostRows.end());

  // The moving rows of each frame in local numbering: own cells' entries
  // first, then the ghosts' (the order of PETSc's MPIAIJ product).
  frames.assign(db.numFrames(), Frame{});
  size_t mostRows = 0;
  std::vector<int32_t> ghostOf; // local index of each off-diagonal column
  for (int k = 0; k < db.numFrames(); ++k) {
    LocalBlocks T;
    PetscCall(T.open(db.shift(k)));
    ghostOf.resize(T.offColumns);
    for (PetscInt c = 0; c < T.offColumns; ++c)
      ghostOf[c] = static_cast<int32_t>(
          nlocal + (std::lower_bound(ghostRows.begin(), ghostRows.end(), T.colmap[c]) - ghostRows.begin()));
    Frame &f = frames[k];
    f.ptr.push_back(0);
    for (PetscInt r = 0; r < nlocal; ++r) {
      const PetscInt d0 = T.d.i[r], d1 = T.d.i[r + 1];
      const PetscInt o0 = T.o.n ? T.o.i[r] : 0, o1 = T.o.n ? T.o.i[r + 1] : 0;
      // An identity row (T(j, j) = 1 alone) leaves its cell as it is.
      if (d1 - d0 == 1 && o1 == o0 && T.d.j[d0] == r && T.d.v[d0] == 1.0) continue;
      f.rows.push_back(static_cast<int32_t>(r));
      for (PetscInt e = d0; e < d1; ++e) {
        f.col.push_back(static_cast<int32_t>(T.d.j[e]));
        f.val.push_back(T.d.v[e]);
      }
      for (PetscInt e = o0; e < o1; ++e) {
        f.col.push_back(ghostOf[T.o.j[e]]);
        f.val.push_back(T.o.v[e]);
      }
      f.ptr.push_back(static_cast<int32_t>(f.col.size()));
    }
    PetscCall(T.close());
    PetscCheck(f.col.size() < static_cast<size_t>(INT32_MAX), PETSC_COMM_SELF, PETSC_ERR_SUP,
               "Frame %d has %zu moving entries on one rank, more than 32-bit offsets hold: use more ranks",
               k, f.col.size());
    f.rows.shrink_to_fit();
    f.ptr.shrink_to_fit();
    f.col.shrink_to_fit();
    f.val.shrink_to_fit();
    mostRows = std::max(mostRows, f.rows.size());
  }
  buffer.assign(mostRows * nf, 0.0);

  // Ghost values arrive through one scatter of the union of all frames'
  // off-rank sources (about a thousand cells on two ranks of the default bed).
  PetscMPIInt size;
  PetscCallMPI(MPI_Comm_size(L.comm(), &size));
  if (size > 1) {
    FractionState layoutOfState;
    PetscCall(layoutOfState.create(L, nf));
    OwnedIS from, to;
    const PetscInt ng = numGhosts();
    PetscCall(ISCreateBlock(PETSC_COMM_SELF, nf, ng, ghostRows.data(), PETSC_COPY_VALUES, from.put()));
    PetscCall(ISCreateStride(PETSC_COMM_SELF, ng * nf, 0, 1, to.put()));
    PetscCall(VecCreateSeq(PETSC_COMM_SELF, ng * nf, ghosts.put()));
    PetscCall(VecScatterCreate(layoutOfState.masses(), from, ghosts, to, toGhosts.put()));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode MovingRows::apply(int k, Vec masses) {
  PetscFunctionBeginUser;
  const Frame &f = frames[k];
  const PetscScalar *g = nullptr;
  if (toGhosts) {
    PetscCall(VecScatterBegin(toGhosts, masses, ghosts, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(toGhosts, masses, ghosts, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecGetArrayRead(ghosts, &g));
  }
  PetscScalar *x;
  PetscCall(VecGetArray(masses, &x));
  double *out = buffer.data();
  switch (nf) {
  case 1: moveRows<1>(f.rows, f.ptr, f.col, f.val, x, g, nlocal, nf, out); break;
  case 2: moveRows<2>(f.rows, f.ptr, f.col, f.val, x, g, nlocal, nf, out); break;
  case 3: moveRows<3>(f.rows, f.ptr, f.col, f.val, x, g, nlocal, nf, out); break;
  case 4: moveRows<4>(f.rows, f.ptr, f.col, f.val, x, g, nlocal, nf, out); break;
  case 5: moveRows<5>(f.rows, f.ptr, f.col, f.val, x, g, nlocal, nf, out); break;
  case 6: moveRows<6>(f.rows, f.ptr, f.col, f.val, x, g, nlocal, nf, out); break;
  case 8: moveRows<8>(f.rows, f.ptr, f.col, f.val, x, g, nlocal, nf, out); break;
  default: moveRows<0>(f.rows, f.ptr, f.col, f.val, x, g, nlocal, nf, out); break;
  }
  PetscCall(VecRestoreArray(masses, &x));
  if (g) PetscCall(VecRestoreArrayRead(ghosts, &g));
  PetscCall(PetscLogFlops(2.0 * nf * static_cast<double>(f.col.size())));
  PetscFunctionReturn(PETSC_SUCCESS);
}

size_t MovingRows::numEntries() const {
  size_t n = 0;
  for (const Frame &f : frames) n += f.col.size();
  return n;
}

size_t MovingRows::bytes() const {
  size_t b = buffer.size() * sizeof(double) + ghostRows.size() * sizeof(PetscInt);
  for (const Frame &f : frames)
    b += (f.rows.size() + f.ptr.size() + f.col.size()) * sizeof(int32_t) + f.val.size() * sizeof(double);
  return b;
}

} // namespace rcfd
