#include "operator/moving_rows.hpp"
#include "base/petsc_compat.hpp"

#include <algorithm>
#include <cmath>

namespace rcfd {
namespace {

// A frame's weights as the kernel reads them: doubles, or 16-bit numerators
// over 2^bits (the double (q + 1) 2^-bits is exact, so a quantised database
// gives the same sums as the same weights stored in double).
struct FullWeights {
  const double *v;
  double operator[](size_t e) const { return v[e]; }
};
struct QuantisedWeights {
  const uint16_t *q;
  double scale;
  double operator[](size_t e) const { return (q[e] + 1.0) * scale; }
};

// Where a group's rows find their entries: fixed-length narrow rows at
// first + r LEN, the others through ptr; narrow rows' columns are offsets
// from the row, wide rows' are full (entry e at col[e - wideBase]).
struct GroupEntries {
  const int32_t *rows, *ptr;
  size_t first;
  const int16_t *offset;
  const int32_t *col;
  size_t wideBase;
};

// New masses of `count` rows, summed in entry order like PETSc's MAIJ
// product (so one rank gives the same bits).  NF > 0 fixes the number of
// fractions at compile time; NF = 0 reads it at run time.  LEN > 0: rows of
// LEN entries; LEN = 0 reads row lengths from ptr.
template <int NF, int LEN, bool WIDE, class Weights>
void sumRows(size_t count, const GroupEntries &g, const Weights &w, const double *x, const double *ghost,
             PetscInt nlocal, int nfRuntime, double *out) {
  const int nf = NF > 0 ? NF : nfRuntime;
  double sum[NF > 0 ? NF : kMaxFractions];
  const int16_t *offset = g.offset; // locals: read once, not through g in every entry
  const int32_t *col = g.col, *ptr = g.ptr, *rows = g.rows;
  for (size_t r = 0; r < count; ++r) {
    for (int i = 0; i < nf; ++i) sum[i] = 0.0;
    const size_t first = LEN > 0 ? g.first + r * LEN : static_cast<size_t>(ptr[r]);
    const size_t last = LEN > 0 ? first + LEN : static_cast<size_t>(ptr[r + 1]);
    const int32_t row = WIDE ? 0 : rows[r];
    for (size_t e = first; e < last; ++e) {
      const int32_t c = WIDE ? col[e - g.wideBase] : row + offset[e];
      const double *src = c < nlocal ? x + static_cast<size_t>(c) * nf
                                     : ghost + static_cast<size_t>(c - nlocal) * nf;
      const double v = w[e];
      for (int i = 0; i < nf; ++i) sum[i] += v * src[i];
    }
    for (int i = 0; i < nf; ++i) out[r * nf + i] = sum[i];
  }
}

} // namespace

// Rows come grouped by their number of entries (0, 1, ..., 4, more, then
// the wide ones), so that the loop over a row's entries has a fixed length
// the branch predictor gets right: mixed lengths of 2 to 4 entries cost a
// mispredicted branch per row, about a third of the step.  Then every old
// mass has been read, and the new ones are written back.
template <int NF, class Weights>
void MovingRows::move(const CompactFrame &f, const Weights &w, double *x, const double *ghost, double *out) const {
  using F = CompactFrame;
  auto count = [&](int g) { return static_cast<size_t>(f.group[g + 1] - f.group[g]); };
  auto at = [&](int g) { return static_cast<size_t>(f.group[g]); };
  auto entries = [&](int g) {
    return GroupEntries{f.rows.data() + at(g), f.ptr.data() + (g >= F::kLong ? at(g) - at(F::kLong) : 0),
                        static_cast<size_t>(f.firstEntry[g]), f.offset.data(), f.col.data(), f.offset.size()};
  };
  std::fill(out, out + count(0) * nf, 0.0); // all solid left, none came in
  sumRows<NF, 1, false>(count(1), entries(1), w, x, ghost, nlocal, nf, out + at(1) * nf);
  sumRows<NF, 2, false>(count(2), entries(2), w, x, ghost, nlocal, nf, out + at(2) * nf);
  sumRows<NF, 3, false>(count(3), entries(3), w, x, ghost, nlocal, nf, out + at(3) * nf);
  sumRows<NF, 4, false>(count(4), entries(4), w, x, ghost, nlocal, nf, out + at(4) * nf);
  sumRows<NF, 0, false>(count(F::kLong), entries(F::kLong), w, x, ghost, nlocal, nf, out + at(F::kLong) * nf);
  sumRows<NF, 0, true>(count(F::kWide), entries(F::kWide), w, x, ghost, nlocal, nf, out + at(F::kWide) * nf);
  const int n = NF > 0 ? NF : nf;
  for (size_t r = 0; r < f.rows.size(); ++r) {
    double *dst = x + static_cast<size_t>(f.rows[r]) * n;
    for (int i = 0; i < n; ++i) dst[i] = out[r * n + i];
  }
}

template <int NF>
void MovingRows::move(const CompactFrame &f, double *x, const double *ghost, double *out) const {
  const int bits = db->metadata().weightBits;
  if (bits > 0) move<NF>(f, QuantisedWeights{f.quantum.data(), std::ldexp(1.0, -bits)}, x, ghost, out);
  else move<NF>(f, FullWeights{f.val.data()}, x, ghost, out);
}

PetscErrorCode MovingRows::setUp(const Database &database, int numFractions) {
  PetscFunctionBeginUser;
  const Layout &L = database.layout();
  PetscCheck(database.hasShifts(), L.comm(), PETSC_ERR_ARG_WRONGSTATE,
             "Database '%s' was loaded without its shifts", database.path().c_str());
  nf = numFractions;
  PetscCheck(nf >= 1 && nf <= kMaxFractions, L.comm(), PETSC_ERR_ARG_OUTOFRANGE,
             "The shift handles 1 to %d fractions, got %d", kMaxFractions, nf);
  db = &database;
  nlocal = L.numLocal();
  size_t mostRows = 0;
  writtenEnds.assign(db->numFrames(), 0);
  for (int k = 0; k < db->numFrames(); ++k) {
    const CompactFrame &f = db->frame(k);
    mostRows = std::max(mostRows, f.numRows());
    for (int32_t row : f.rows) writtenEnds[k] = std::max<PetscInt>(writtenEnds[k], row + 1);
  }
  buffer.assign(mostRows * nf, 0.0);
  // Ghost values arrive through one scatter of the union of all frames'
  // off-rank sources (about a thousand cells on two ranks of the default bed).
  PetscMPIInt size;
  PetscCallMPI(MPI_Comm_size(L.comm(), &size));
  if (size > 1)
    PetscCall(L.rowsScatter(nf, numGhosts(), db->ghostRows().data(), ghosts.put(), toGhosts.put()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode MovingRows::apply(int k, Vec masses) {
  PetscFunctionBeginUser;
  const CompactFrame &f = db->frame(k);
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
  PetscCall(PetscLogFlops(2.0 * nf * static_cast<double>(f.numEntries())));
  PetscFunctionReturn(PETSC_SUCCESS);
}

size_t MovingRows::numEntries() const {
  size_t n = 0;
  for (int k = 0; db && k < db->numFrames(); ++k) n += db->frame(k).numEntries();
  return n;
}

size_t MovingRows::frameBytes() const { return db ? db->frameBytes() : 0; }

size_t MovingRows::bufferBytes() const {
  PetscInt ghostValues = 0;
  if (ghosts) (void)VecGetLocalSize(ghosts, &ghostValues);
  return (buffer.size() + static_cast<size_t>(ghostValues)) * sizeof(double);
}

} // namespace rcfd
