#include "database/compact_frames.hpp"
#include "base/petsc_compat.hpp"

#include "base/collective.hpp"
#include "base/h5.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <memory>

namespace rcfd {

namespace {

// An implied identity row r whose column did not sum to exactly 1 holds
// 1 / sum after rescaling, as a stored row would: it is stored from now on
// (rare: a column that also holds round-off from other rows).
void materialiseRescaledIdentities(const PetscScalar *inv, PetscInt rstart, PetscInt n, LocalShiftRows *rows) {
  size_t i = 0;
  std::vector<PetscInt> changed;
  for (PetscInt r = 0; r < n; ++r) {
    if (i < rows->row.size() && rows->row[i] == r) ++i;
    else if (inv[r] != 1.0) changed.push_back(r);
  }
  if (changed.empty()) return;
  LocalShiftRows all;
  all.impliedIdentity = true;
  all.rowPtr.assign(1, 0);
  size_t c = 0;
  i = 0;
  while (i < rows->row.size() || c < changed.size()) {
    if (c == changed.size() || (i < rows->row.size() && rows->row[i] < changed[c])) {
      all.row.push_back(rows->row[i]);
      all.col.insert(all.col.end(), rows->col.begin() + rows->rowPtr[i], rows->col.begin() + rows->rowPtr[i + 1]);
      all.val.insert(all.val.end(), rows->val.begin() + rows->rowPtr[i], rows->val.begin() + rows->rowPtr[i + 1]);
      ++i;
    } else {
      all.row.push_back(changed[c]);
      all.col.push_back(rstart + changed[c]);
      all.val.push_back(1.0 * inv[changed[c]]); // as MatDiagonalScale scales the stored 1
      ++c;
    }
    all.rowPtr.push_back(static_cast<PetscInt>(all.col.size()));
  }
  *rows = std::move(all);
}

// Other ranks' columns read by a batch, ascending.
std::vector<PetscInt> ghostColumns(const std::vector<LocalShiftRows> &batch, PetscInt rstart, PetscInt rend) {
  std::vector<PetscInt> ghosts;
  for (const LocalShiftRows &rows : batch)
    for (PetscInt c : rows.col)
      if (c < rstart || c >= rend) ghosts.push_back(c);
  std::sort(ghosts.begin(), ghosts.end());
  ghosts.erase(std::unique(ghosts.begin(), ghosts.end()), ghosts.end());
  return ghosts;
}

// Collective.  Makes check->toGhosts reach every column of `needed`: kept if
// it does on every rank, else built again over the union (a column summed
// through the scatter that no row of a frame reads gets 0 added, exactly).
// The sums are held frame by frame (frame j of the batch at j * n + r on the
// rank owning r, j * ghosts + g in `partial`), so that each frame's passes
// run over contiguous memory as a single frame's did.
PetscErrorCode reachGhosts(const Layout &L, const std::vector<PetscInt> &needed, ColumnCheck *check) {
  const PetscInt B = check->batch;
  PetscMPIInt size;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(L.comm(), &size));
  int missing = !std::includes(check->ghosts.begin(), check->ghosts.end(), needed.begin(), needed.end());
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &missing, 1, MPI_INT, MPI_MAX, L.comm()));
  if (!missing && check->toGhosts) PetscFunctionReturn(PETSC_SUCCESS);
  std::vector<PetscInt> all;
  std::set_union(check->ghosts.begin(), check->ghosts.end(), needed.begin(), needed.end(), std::back_inserter(all));
  check->ghosts = std::move(all);
  const PetscInt *ranges; // of cells, from a vector of one value per cell
  OwnedVec cells;
  PetscCall(VecCreateMPI(L.comm(), L.numLocal(), L.numCells(), cells.put()));
  PetscCall(VecGetOwnershipRanges(cells, &ranges));
  const auto G = static_cast<PetscInt>(check->ghosts.size());
  std::vector<PetscInt> from(static_cast<size_t>(G * B));
  for (PetscInt g = 0; g < G; ++g) {
    const PetscInt c = check->ghosts[g];
    const PetscInt *up = std::upper_bound(ranges, ranges + size + 1, c); // past c's owner's range
    const PetscInt start = *(up - 1), count = *up - start;
    for (PetscInt j = 0; j < B; ++j) from[j * G + g] = B * start + j * count + (c - start);
  }
  OwnedIS fromIS, toIS;
  PetscCall(ISCreateGeneral(PETSC_COMM_SELF, G * B, from.data(), PETSC_COPY_VALUES, fromIS.put()));
  PetscCall(ISCreateStride(PETSC_COMM_SELF, G * B, 0, 1, toIS.put()));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, G * B, check->partial.put()));
  PetscCall(VecScatterCreate(check->sums, fromIS, check->partial, toIS, check->toGhosts.put()));
  ++check->scattersBuilt;
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The sentence refusing column r of a frame, whose sum s is not accepted.
std::string refusal(const Layout &L, const ColumnCheck &check, const std::string &where, PetscInt r, double s) {
  char text[512];
  if (check.weightBits > 0)
    std::snprintf(text, sizeof text,
                  "%s: shift column of cell %d sums to %.17g, but the database says its weights are quantised "
                  "to multiples of 2^-%d (/metadata weight_bits) with every column summing to exactly 1",
                  where.c_str(), (int)L.ownedNatural()[r], s, check.weightBits);
  else
    std::snprintf(text, sizeof text,
                  "%s: shift column of cell %d sums to %.12g, expected 1 within %g (-db_column_tolerance)",
                  where.c_str(), (int)L.ownedNatural()[r], s, check.tolerance);
  return text;
}

} // namespace

int batchFor(const Layout &L) {
  PetscMPIInt size;
  MPI_Comm_size(L.comm(), &size);
  if (size == 1) return 1; // nobody to wait for
  const double cellsPerRank = static_cast<double>(L.numCells()) / size;
  return static_cast<int>(std::clamp(16e6 / 8.0 / cellsPerRank, 1.0, 16.0));
}

PetscErrorCode rescaleColumns(const Layout &L, std::vector<LocalShiftRows> *batch,
                              const std::vector<std::string> &where, ColumnCheck *check) {
  const PetscInt B = check->batch;
  const MPI_Comm comm = L.comm();
  const PetscInt rstart = L.rowStart(), rend = L.rowEnd(), n = L.numLocal();
  PetscMPIInt size;
  PetscFunctionBeginUser;
  PetscCheck(batch->size() <= static_cast<size_t>(B) && where.size() == batch->size(), PETSC_COMM_SELF,
             PETSC_ERR_PLIB, "rescaleColumns takes up to %d frames, each with its name", (int)B);
  PetscCallMPI(MPI_Comm_size(comm, &size));
  OwnedVec &sums = check->sums, &partial = check->partial; // own columns' sums; this rank's share of the ghosts'
  if (!sums) PetscCall(VecCreateMPI(comm, n * B, L.numCells() * B, sums.put()));
  if (size > 1) PetscCall(reachGhosts(L, ghostColumns(*batch, rstart, rend), check));
  const std::vector<PetscInt> &ghosts = check->ghosts; // the scatter's, a superset of this batch's
  const auto G = static_cast<PetscInt>(ghosts.size());
  auto ghostOf = [&](PetscInt c) { return std::lower_bound(ghosts.begin(), ghosts.end(), c) - ghosts.begin(); };

  // Frame j of the batch: own columns' sums at s + j * n, its share of the ghosts' at p + j * G.
  PetscCall(VecSet(sums, 0.0));
  if (partial) PetscCall(VecSet(partial, 0.0));
  PetscScalar *s, *p = nullptr;
  PetscCall(VecGetArray(sums, &s));
  if (partial) PetscCall(VecGetArray(partial, &p));
  for (size_t j = 0; j < batch->size(); ++j) {
    const LocalShiftRows &rows = (*batch)[j];
    PetscScalar *sj = s + j * n, *pj = p ? p + j * G : nullptr;
    auto add = [&](PetscInt first, PetscInt last) {
      for (PetscInt e = first; e < last; ++e) {
        const PetscInt c = rows.col[e];
        if (c >= rstart && c < rend) sj[c - rstart] += rows.val[e];
        else pj[ghostOf(c)] += rows.val[e];
      }
    };
    if (!rows.impliedIdentity) {
      add(0, static_cast<PetscInt>(rows.col.size())); // row by row, like MatMultTranspose
    } else { // the same additions in the same order, identity rows' 1 in its place
      size_t i = 0;
      for (PetscInt r = 0; r < n; ++r) {
        if (i < rows.row.size() && rows.row[i] == r) add(rows.rowPtr[i], rows.rowPtr[i + 1]), ++i;
        else sj[r] += 1.0;
      }
    }
  }
  PetscCall(VecRestoreArray(sums, &s));
  if (partial) PetscCall(VecRestoreArray(partial, &p));
  if (size > 1) { // the other ranks' shares added after this rank's own, as MatMultTranspose adds them
    PetscCall(VecScatterBegin(check->toGhosts, partial, sums, ADD_VALUES, SCATTER_REVERSE));
    PetscCall(VecScatterEnd(check->toGhosts, partial, sums, ADD_VALUES, SCATTER_REVERSE));
  }

  // Check every column of every frame, then rescale so that each sums to 1
  // to round-off.  The refusal is of the batch's first frame with a bad
  // column on this rank (its first bad column).
  PetscCall(VecGetArray(sums, &s));
  std::string why;
  const bool quantised = check->weightBits > 0;
  double largest = check->largestError; // in a register: the loop runs over every cell of every frame
  for (size_t j = 0; j < batch->size() && why.empty(); ++j)
    for (PetscInt r = 0; r < n; ++r) {
      double &sum = s[j * n + r];
      const double err = std::fabs(sum - 1.0);
      largest = std::max(largest, err);
      if (quantised ? sum == 1.0 : err <= check->tolerance) {
        sum = 1.0 / sum;
        continue;
      }
      why = refusal(L, *check, where[j], r, sum);
      break;
    }
  check->largestError = largest;
  PetscCall(VecRestoreArray(sums, &s));
  PetscCall(agreeOnFailure(comm, !why.empty(), why));
  if (size > 1) {
    PetscCall(VecScatterBegin(check->toGhosts, sums, partial, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(check->toGhosts, sums, partial, INSERT_VALUES, SCATTER_FORWARD));
  }
  const PetscScalar *inv, *ginv = nullptr;
  PetscCall(VecGetArrayRead(sums, &inv));
  if (partial) PetscCall(VecGetArrayRead(partial, &ginv));
  for (size_t j = 0; j < batch->size(); ++j) {
    LocalShiftRows &rows = (*batch)[j];
    for (size_t e = 0; e < rows.col.size(); ++e) { // as MatDiagonalScale(T, NULL, 1 / sums)
      const PetscInt c = rows.col[e];
      rows.val[e] *= c >= rstart && c < rend ? inv[j * n + c - rstart] : ginv[j * G + ghostOf(c)];
    }
    if (rows.impliedIdentity) materialiseRescaledIdentities(inv + j * n, rstart, n, &rows);
  }
  PetscCall(VecRestoreArrayRead(sums, &inv));
  if (partial) PetscCall(VecRestoreArrayRead(partial, &ginv));
  PetscFunctionReturn(PETSC_SUCCESS);
}

CompactFrame compactFrame(const LocalShiftRows &rows, PetscInt rowStart, PetscInt nlocal, int weightBits,
                          const std::string &where, std::vector<PetscInt> *ghosts) {
  using F = CompactFrame;
  auto own = [&](PetscInt c) { return c >= rowStart && c < rowStart + nlocal; };
  // The group of each stored row (-1: identity row, left out) and each group's size.
  const size_t stored = rows.numStored();
  std::vector<int8_t> groupOf(stored);
  std::array<size_t, F::kGroups> rowsIn{}, entriesIn{};
  for (size_t i = 0; i < stored; ++i) {
    const PetscInt r = rows.localRow(i), first = rows.rowPtr[i], last = rows.rowPtr[i + 1];
    if (isIdentityRow(rowStart + r, rows.col.data() + first, rows.val.data() + first, last - first)) {
      groupOf[i] = -1;
      continue;
    }
    bool narrow = true;
    for (PetscInt e = first; e < last && narrow; ++e) {
      const PetscInt offset = rows.col[e] - rowStart - r;
      narrow = own(rows.col[e]) && offset >= INT16_MIN && offset <= INT16_MAX;
    }
    const int g = narrow ? static_cast<int>(std::min<PetscInt>(last - first, F::kLong)) : F::kWide;
    groupOf[i] = static_cast<int8_t>(g);
    ++rowsIn[g];
    entriesIn[g] += static_cast<size_t>(last - first);
  }
  F f;
  size_t totalRows = 0, totalEntries = 0;
  for (int g = 0; g < F::kGroups; ++g) {
    f.group[g] = static_cast<int32_t>(totalRows);
    f.firstEntry[g] = static_cast<int32_t>(totalEntries);
    totalRows += rowsIn[g];
    totalEntries += entriesIn[g];
  }
  if (totalEntries >= static_cast<size_t>(INT32_MAX))
    throw h5::Error(where + " has " + std::to_string(totalEntries) +
                    " moving entries on one rank, more than 32-bit offsets hold: use more ranks");
  f.group[F::kGroups] = static_cast<int32_t>(totalRows);
  f.firstEntry[F::kGroups] = static_cast<int32_t>(totalEntries);
  const size_t narrowEntries = f.firstEntry[F::kWide];
  f.rows.resize(totalRows);
  f.ptr.resize(rowsIn[F::kLong] + rowsIn[F::kWide] + 1);
  f.offset.resize(narrowEntries);
  f.col.resize(totalEntries - narrowEntries);
  (weightBits > 0 ? f.quantum.resize(totalEntries) : f.val.resize(totalEntries));

  const double scale = std::ldexp(1.0, weightBits), most = scale;
  std::array<size_t, F::kGroups> nextRow{}, nextEntry{};
  for (int g = 0; g < F::kGroups; ++g) nextRow[g] = f.group[g], nextEntry[g] = f.firstEntry[g];
  for (size_t s = 0; s < stored; ++s) {
    const int g = groupOf[s];
    if (g < 0) continue;
    const PetscInt r = rows.localRow(s);
    const size_t i = nextRow[g]++;
    f.rows[i] = static_cast<int32_t>(r);
    if (g >= F::kLong) f.ptr[i - f.group[F::kLong]] = static_cast<int32_t>(nextEntry[g]);
    for (PetscInt e = rows.rowPtr[s]; e < rows.rowPtr[s + 1]; ++e) {
      const size_t at = nextEntry[g]++;
      const PetscInt c = rows.col[e];
      if (g != F::kWide) {
        f.offset[at] = static_cast<int16_t>(c - rowStart - r);
      } else if (own(c)) {
        f.col[at - narrowEntries] = static_cast<int32_t>(c - rowStart);
      } else {
        if (static_cast<long long>(nlocal) + c >= INT32_MAX)
          throw h5::Error(where + ": too many cells for 32-bit column numbers on one rank");
        f.col[at - narrowEntries] = static_cast<int32_t>(nlocal + c); // numberGhosts() renumbers it
        ghosts->push_back(c);
      }
      const double v = rows.val[e];
      if (weightBits == 0) {
        f.val[at] = v;
        continue;
      }
      const double numerator = v * scale; // exact: a power of two
      if (!(numerator >= 1.0 && numerator <= most && numerator == std::floor(numerator))) {
        char text[160];
        std::snprintf(text, sizeof text, "%.17g", v);
        throw h5::Error(where + ": shift weight " + text + " is not a positive multiple of 2^-" +
                        std::to_string(weightBits) + " up to 1, but the database says its weights are quantised to "
                        "multiples of 2^-" + std::to_string(weightBits) + " (/metadata weight_bits)");
      }
      f.quantum[at] = static_cast<uint16_t>(numerator - 1.0);
    }
  }
  f.ptr.back() = static_cast<int32_t>(totalEntries);
  return f;
}

void numberGhosts(CompactFrame *frame, PetscInt nlocal, const std::vector<PetscInt> &ghostRows) {
  for (int32_t &c : frame->col)
    if (c >= nlocal)
      c = static_cast<int32_t>(nlocal + (std::lower_bound(ghostRows.begin(), ghostRows.end(), c - nlocal) -
                                         ghostRows.begin()));
}

namespace {

// A rank's rows split into PETSc's "diagonal" block (columns of own cells,
// numbered from the first own row) and "off-diagonal" block (global
// columns): the arrays MatCreateMPIAIJWithSplitArrays uses in place, so the
// matrix owns them through a container (freed with it).  Faster than the
// row-by-row insertion of MatCreateMPIAIJWithArrays.  The vectors are never
// empty, so that data() is never null.
struct SplitArrays {
  std::vector<PetscInt> di{0}, dj, oi{0}, oj;
  std::vector<PetscScalar> da, oa;
  static PetscErrorCode destroy(void *self) {
    delete static_cast<SplitArrays *>(self);
    return PETSC_SUCCESS;
  }
};

} // namespace

PetscErrorCode shiftMatrixOf(const CompactFrame &f, const Layout &L, const std::vector<PetscInt> &ghostRows,
                             int weightBits, OwnedMat *T) {
  PetscFunctionBeginUser;
  const PetscInt n = L.numLocal();
  auto arrays = std::make_unique<SplitArrays>();
  SplitArrays &a = *arrays;
  std::vector<int32_t> movingRow(n, -1); // the row's place in the compact frame
  for (size_t i = 0; i < f.rows.size(); ++i) movingRow[f.rows[i]] = static_cast<int32_t>(i);
  const double scale = std::ldexp(1.0, -weightBits);
  a.di.reserve(n + 1);
  a.oi.reserve(n + 1);
  a.dj.reserve(f.numEntries() + n);
  a.da.reserve(f.numEntries() + n);
  for (PetscInt r = 0; r < n; ++r) {
    if (movingRow[r] < 0) {
      a.dj.push_back(r);
      a.da.push_back(1.0);
    } else {
      const size_t i = movingRow[r];
      size_t first, last;
      f.entries(i, &first, &last);
      for (size_t e = first; e < last; ++e) {
        const int32_t c = f.column(i, e);
        const double v = weightBits > 0 ? (f.quantum[e] + 1.0) * scale : f.val[e];
        if (c < n) a.dj.push_back(c), a.da.push_back(v);
        else a.oj.push_back(ghostRows[c - n]), a.oa.push_back(v);
      }
    }
    a.di.push_back(static_cast<PetscInt>(a.dj.size()));
    a.oi.push_back(static_cast<PetscInt>(a.oj.size()));
  }
  for (auto *v : {&a.dj, &a.oj}) if (v->empty()) v->push_back(0);
  for (auto *v : {&a.da, &a.oa}) if (v->empty()) v->push_back(0.0);
  PetscCall(MatCreateMPIAIJWithSplitArrays(L.comm(), n, n, L.numCells(), L.numCells(), a.di.data(), a.dj.data(),
                                           a.da.data(), a.oi.data(), a.oj.data(), a.oa.data(), T->put()));
  PetscContainer owner;
  PetscCall(PetscContainerCreate(PETSC_COMM_SELF, &owner));
  PetscCall(PetscContainerSetPointer(owner, arrays.release()));
  PetscCall(PetscContainerSetUserDestroy(owner, SplitArrays::destroy));
  PetscCall(PetscObjectCompose(reinterpret_cast<PetscObject>(T->get()), "rcfd_split_arrays",
                               reinterpret_cast<PetscObject>(owner)));
  PetscCall(PetscContainerDestroy(&owner));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
