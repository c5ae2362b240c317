// This rank's rows of one frame as the loader reads them (local_frame.hpp):
// alpha_s, and the shift's rows stored in full (versions 1, 2) or as moving
// rows (version 3), checked entry by entry.
#include "database/local_frame.hpp"

#include "database/stored_frame.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

namespace rcfd {
namespace {

// Appends natural row `row` of a stored shift to `rows` in PETSc numbering,
// columns sorted; refuses an entry outside the mesh or a weight that is not a
// non-negative number.
void appendRow(const Layout &layout, const std::string &where, hsize_t row, const int32_t *col, const double *val,
               int64_t count, LocalShiftRows *rows) {
  const hsize_t n = layout.numCells();
  const size_t rowBegin = rows->col.size();
  for (int64_t t = 0; t < count; ++t) {
    if (col[t] < 0 || static_cast<hsize_t>(col[t]) >= n)
      throw h5::Error(where + ": shift entry in row " + std::to_string(row) + " names cell " +
                      std::to_string(col[t]) + ", outside the mesh's " + std::to_string(n) + " cells");
    if (!std::isfinite(val[t]) || val[t] < 0.0)
      throw h5::Error(where + ": shift entry (" + std::to_string(row) + ", " + std::to_string(col[t]) + ") is " +
                      std::to_string(val[t]) + ", expected a non-negative share");
    rows->col.push_back(layout.petscRow(col[t]));
    rows->val.push_back(val[t]);
  }
  // PETSc wants sorted columns; renumbering may have reordered them.
  // Rows hold a handful of entries: insertion sort, in place.
  for (size_t a = rowBegin + 1; a < rows->col.size(); ++a)
    for (size_t b = a; b > rowBegin && rows->col[b - 1] > rows->col[b]; --b) {
      std::swap(rows->col[b - 1], rows->col[b]);
      std::swap(rows->val[b - 1], rows->val[b]);
    }
  rows->rowPtr.push_back(static_cast<PetscInt>(rows->col.size()));
}

// Versions 1 and 2: the full CSR's rows of the rank's cells.
void readLocalRowsFull(const h5::File &f, const std::string &g, const std::string &where, const Layout &layout,
                       const std::vector<std::pair<hsize_t, hsize_t>> &cellRuns, LocalShiftRows *rows) {
  const hsize_t n = layout.numCells();
  std::vector<std::pair<hsize_t, hsize_t>> ptrRuns;
  for (auto [b, e] : cellRuns) ptrRuns.emplace_back(b, e + 1);
  const auto ptrDims = f.extents(g + "/shift_row_ptr");
  if (ptrDims.size() != 1 || ptrDims[0] != n + 1)
    throw h5::Error(where + ": shift_row_ptr has " + std::to_string(ptrDims.empty() ? 0 : ptrDims[0]) +
                    " entries, expected " + std::to_string(n + 1) + " (cells + 1)");
  const hsize_t nnz = f.extents(g + "/shift_col").at(0);
  if (f.extents(g + "/shift_val").at(0) != nnz)
    throw h5::Error(where + ": shift_col and shift_val differ in length");
  const auto ptr = f.readRuns<int64_t>(g + "/shift_row_ptr", ptrRuns);
  std::vector<std::pair<hsize_t, hsize_t>> nzRuns;
  size_t p = 0;
  for (auto [b, e] : cellRuns) {
    const int64_t first = ptr[p], last = ptr[p + (e - b)];
    for (hsize_t r = 0; r < e - b; ++r)
      if (ptr[p + r + 1] < ptr[p + r])
        throw h5::Error(where + ": shift_row_ptr decreases at row " + std::to_string(b + r));
    if (first < 0 || last > static_cast<int64_t>(nnz))
      throw h5::Error(where + ": shift_row_ptr points outside shift_col (" + std::to_string(nnz) +
                      " entries)");
    if (last > first) nzRuns.emplace_back(first, last);
    p += e - b + 1;
  }
  const auto col = f.readRuns<int32_t>(g + "/shift_col", nzRuns);
  const auto val = f.readRuns<double>(g + "/shift_val", nzRuns);
  rows->rowPtr.assign(1, 0);
  rows->col.reserve(col.size());
  rows->val.reserve(val.size());
  size_t q = 0;
  p = 0;
  for (auto [b, e] : cellRuns) {
    for (hsize_t r = 0; r < e - b; ++r) {
      const int64_t count = ptr[p + r + 1] - ptr[p + r];
      appendRow(layout, where, b + r, col.data() + q, val.data() + q, count, rows);
      q += static_cast<size_t>(count);
    }
    p += e - b + 1;
  }
}

// Version 3: the rank's moving rows, found by binary search in moving_row
// (read whole); its other cells' rows are identity rows, implied and never
// built (rescaleColumns counts them in their place, compactFrame leaves them
// out), so the frame is the one version 2 gives, to the bit.
void readLocalRowsMoving(const h5::File &f, const std::string &g, const std::string &where, const Layout &layout,
                         const std::vector<std::pair<hsize_t, hsize_t>> &cellRuns, int weightBits,
                         LocalShiftRows *rows) {
  const MovingRowIndex index = readMovingRowIndex(f, g, where, static_cast<int>(layout.numCells()), weightBits);
  const auto &moving = index.movingRow;
  // The positions [lo, hi) in moving_row of each run of own cells, merged where they touch.
  std::vector<std::pair<hsize_t, hsize_t>> rowRuns;
  for (auto [b, e] : cellRuns) {
    const auto lo = static_cast<hsize_t>(std::lower_bound(moving.begin(), moving.end(), b) - moving.begin());
    const auto hi = static_cast<hsize_t>(std::lower_bound(moving.begin(), moving.end(), e) - moving.begin());
    if (lo == hi) continue;
    if (!rowRuns.empty() && rowRuns.back().second == lo) rowRuns.back().second = hi;
    else rowRuns.emplace_back(lo, hi);
  }
  std::vector<std::pair<hsize_t, hsize_t>> entryRuns;
  const auto ptr = readMovingRowPtr(f, g, where, index, rowRuns, &entryRuns);
  const auto col = f.readRuns<int32_t>(g + "/shift_col", entryRuns);
  const auto val = readStoredWeights(f, g, entryRuns, weightBits);
  // The moving rows read, ascending, and their entry counts.
  std::vector<int32_t> row;
  std::vector<int64_t> count;
  size_t p = 0;
  for (auto [lo, hi] : rowRuns) {
    for (hsize_t i = lo; i < hi; ++i, ++p) {
      row.push_back(moving[i]);
      count.push_back(ptr[p + 1] - ptr[p]);
    }
    ++p; // the run's end pointer
  }
  // Only the moving rows are stored; the others stay identity rows, implied.
  rows->impliedIdentity = true;
  rows->rowPtr.assign(1, 0);
  rows->col.reserve(col.size());
  rows->val.reserve(val.size());
  rows->row.reserve(row.size());
  size_t q = 0;
  for (size_t m = 0; m < row.size(); ++m) {
    const PetscInt local = layout.petscRow(row[m]) - layout.rowStart();
    rows->row.push_back(local);
    appendRow(layout, where, static_cast<hsize_t>(row[m]), col.data() + q, val.data() + q, count[m], rows);
    q += static_cast<size_t>(count[m]);
  }
}

} // namespace

LocalFrame readLocalFrame(const h5::File &f, long long version, int weightBits, int k, const Layout &layout,
                          bool withShift) try {
  const std::string g = frameGroup(k);
  const std::string where = "database '" + f.path() + "', frame " + std::to_string(k);
  f.requireGroup(g);
  const hsize_t n = layout.numCells();
  std::vector<std::pair<hsize_t, hsize_t>> cellRuns;
  for (auto [b, e] : layout.ownedNaturalRuns()) cellRuns.emplace_back(b, e);
  LocalFrame fr;
  const auto alphaDims = f.extents(g + "/alpha_s");
  if (alphaDims.size() != 1 || alphaDims[0] != n)
    throw h5::Error(where + ": alpha_s has " + std::to_string(alphaDims.empty() ? 0 : alphaDims[0]) +
                    " values but the mesh has " + std::to_string(n) + " cells");
  fr.alpha = f.readRuns<double>(g + "/alpha_s", cellRuns);
  for (size_t r = 0; r < fr.alpha.size(); ++r)
    if (!std::isfinite(fr.alpha[r]) || fr.alpha[r] < 0.0 || fr.alpha[r] > 1.0)
      throw h5::Error(where + ": alpha_s of cell " + std::to_string(layout.ownedNatural()[r]) +
                      " is " + std::to_string(fr.alpha[r]) + ", expected a number in [0, 1]");
  if (!withShift) return fr;
  if (version >= 3) readLocalRowsMoving(f, g, where, layout, cellRuns, weightBits, &fr.shift);
  else readLocalRowsFull(f, g, where, layout, cellRuns, &fr.shift);
  return fr;
} catch (const h5::Damaged &d) {
  throwDamagedFrame(d, f, k);
}

} // namespace rcfd
