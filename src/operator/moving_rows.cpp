#include "operator/moving_rows.hpp"
#include "base/petsc_compat.hpp"

#include <algorithm>

namespace rcfd {
namespace {

// New masses of `count` rows of LEN entries each (entries of row r at
// r * LEN), summed in column order like PETSc's MAIJ product (so one rank
// gives the same bits).  NF > 0 fixes the number of fractions at compile
// time; NF = 0 reads it at run time.  LEN = 0 reads row lengths from ptr.
template <int NF, int LEN>
void sumRows(size_t count, const int32_t *ptr, const int32_t *col, const double *val,
             const double *x, const double *ghost, PetscInt nlocal, int nfRuntime, double *out) {
  const int nf = NF > 0 ? NF : nfRuntime;
  double sum[NF > 0 ? NF : kMaxFractions];
  for (size_t r = 0; r < count; ++r) {
    for (int i = 0; i < nf; ++i) sum[i] = 0.0;
    const int32_t first = LEN > 0 ? static_cast<int32_t>(r * LEN) : ptr[r];
    const int32_t last = LEN > 0 ? first + LEN : ptr[r + 1];
    for (int32_t e = first; e < last; ++e) {
      const int32_t c = col[e];
      const double *src = c < nlocal ? x + static_cast<size_t>(c) * nf
                                     : ghost + static_cast<size_t>(c - nlocal) * nf;
      const double v = val[e];
      for (int i = 0; i < nf; ++i) sum[i] += v * src[i];
    }
    for (int i = 0; i < nf; ++i) out[r * nf + i] = sum[i];
  }
}

} // namespace

// Rows come grouped by their number of entries (0, 1, ..., 4, more), so
// that the loop over a row's entries has a fixed length the branch
// predictor gets right: mixed lengths of 2 to 4 entries cost a mispredicted
// branch per row, about a third of the step.  Then every old mass has been
// read, and the new ones are written back.
template <int NF>
void MovingRows::move(const Frame &f, double *x, const double *ghost, double *out) const {
  const int32_t *ptr = f.ptr.data(), *col = f.col.data();
  const double *val = f.val.data();
  auto group = [&](int g) { return static_cast<size_t>(f.group[g + 1] - f.group[g]); };
  auto at = [&](int g) { return static_cast<size_t>(f.group[g]); };
  std::fill(out, out + group(0) * nf, 0.0); // all solid left, none came in
  sumRows<NF, 1>(group(1), nullptr, col + ptr[at(1)], val + ptr[at(1)], x, ghost, nlocal, nf, out + at(1) * nf);
  sumRows<NF, 2>(group(2), nullptr, col + ptr[at(2)], val + ptr[at(2)], x, ghost, nlocal, nf, out + at(2) * nf);
  sumRows<NF, 3>(group(3), nullptr, col + ptr[at(3)], val + ptr[at(3)], x, ghost, nlocal, nf, out + at(3) * nf);
  sumRows<NF, 4>(group(4), nullptr, col + ptr[at(4)], val + ptr[at(4)], x, ghost, nlocal, nf, out + at(4) * nf);
  sumRows<NF, 0>(group(5), ptr + at(5), col, val, x, ghost, nlocal, nf, out + at(5) * nf);
  const int n = NF > 0 ? NF : nf;
  for (size_t r = 0; r < f.rows.size(); ++r) {
    double *dst = x + static_cast<size_t>(f.rows[r]) * n;
    for (int i = 0; i < n; ++i) dst[i] = out[r * n + i];
  }
}

namespace {

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
    // Each pass takes the rows of one length group, in row order.
    for (int g = 0; g < kGroups; ++g) {
      f.group[g] = static_cast<int32_t>(f.rows.size());
      for (PetscInt r = 0; r < nlocal; ++r) {
        const PetscInt d0 = T.d.i[r], d1 = T.d.i[r + 1];
        const PetscInt o0 = T.o.n ? T.o.i[r] : 0, o1 = T.o.n ? T.o.i[r + 1] : 0;
        // An identity row (T(j, j) = 1 alone) leaves its cell as it is.
        if (d1 - d0 == 1 && o1 == o0 && T.d.j[d0] == r && T.d.v[d0] == 1.0) continue;
        if (std::min<PetscInt>(d1 - d0 + o1 - o0, kGroups - 1) != g) continue;
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
    }
    f.group[kGroups] = static_cast<int32_t>(f.rows.size());
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
  if (size > 1) PetscCall(L.rowsScatter(nf, numGhosts(), ghostRows.data(), ghosts.put(), toGhosts.put()));
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
  case 1: move<1>(f, x, g, out); break;
  case 2: move<2>(f, x, g, out); break;
  case 3: move<3>(f, x, g, out); break;
  case 4: move<4>(f, x, g, out); break;
  case 5: move<5>(f, x, g, out); break;
  case 6: move<6>(f, x, g, out); break;
  case 8: move<8>(f, x, g, out); break;
  default: move<0>(f, x, g, out); break;
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
