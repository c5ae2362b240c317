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
  double sum[NF > 0 ? NF : 64];
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

} // namespace

PetscErrorCode MovingRows::setUp(const Database &db, int numFractions) {
  PetscFunctionBeginUser;
  const Layout &L = db.layout();
  nf = numFractions;
  PetscCheck(nf >= 1 && nf <= 64, L.comm(), PETSC_ERR_ARG_OUTOFRANGE,
             "The shift handles 1 to 64 fractions, got %d", nf);
  nlocal = L.numLocal();
  const PetscInt rstart = L.rowStart(), rend = L.rowEnd();
  const auto isIdentityRow = [](PetscInt row, PetscInt n, const PetscInt *c, const PetscScalar *v) {
    return n == 1 && c[0] == row && v[0] == 1.0;
  };

  // Pass 1: the off-rank source cells of all frames.
  ghostRows.clear();
  for (int k = 0; k < db.numFrames(); ++k)
    for (PetscInt row = rstart; row < rend; ++row) {
      PetscInt n;
      const PetscInt *c;
      const PetscScalar *v;
      PetscCall(MatGetRow(db.shift(k), row, &n, &c, &v));
      if (!isIdentityRow(row, n, c, v))
        for (PetscInt e = 0; e < n; ++e)
          if (c[e] < rstart || c[e] >= rend) ghostRows.push_back(c[e]);
      PetscCall(MatRestoreRow(db.shift(k), row, &n, &c, &v));
    }
  std::sort(ghostRows.begin(), ghostRows.end());
  ghostRows.erase(std::unique(ghostRows.begin(), ghostRows.end()), ghostRows.end());
  const auto localColumn = [&](PetscInt c) -> int32_t {
    if (c >= rstart && c < rend) return static_cast<int32_t>(c - rstart);
    const auto g = std::lower_bound(ghostRows.begin(), ghostRows.end(), c) - ghostRows.begin();
    return static_cast<int32_t>(nlocal + g);
  };

  // Pass 2: the moving rows in local numbering.
  frames.assign(db.numFrames(), Frame{});
  size_t mostRows = 0;
  for (int k = 0; k < db.numFrames(); ++k) {
    Frame &f = frames[k];
    f.ptr.push_back(0);
    for (PetscInt row = rstart; row < rend; ++row) {
      PetscInt n;
      const PetscInt *c;
      const PetscScalar *v;
      PetscCall(MatGetRow(db.shift(k), row, &n, &c, &v));
      if (!isIdentityRow(row, n, c, v)) {
        f.rows.push_back(static_cast<int32_t>(row - rstart));
        for (PetscInt e = 0; e < n; ++e) {
          f.col.push_back(localColumn(c[e]));
          f.val.push_back(v[e]);
        }
        f.ptr.push_back(static_cast<int32_t>(f.col.size()));
      }
      PetscCall(MatRestoreRow(db.shift(k), row, &n, &c, &v));
    }
    f.rows.shrink_to_fit();
    f.ptr.shrink_to_fit();
    f.col.shrink_to_fit();
    f.val.shrink_to_fit();
    mostRows = std::max(mostRows, f.rows.size());
  }
  buffer.assign(mostRows * nf, 0.0);

  // Ghost values arrive through one scatter of the union of all frames'
  // off-rank sources: a few hundred cells along the partition boundary.
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
