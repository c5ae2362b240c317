// Serial, PETSc-free description of database frames, produced by the
// builders (synthetic bed, particle snapshots, Eulerian frames) and consumed
// by the database writer.  Cell indices are natural mesh indices.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace rcfd {

/// Square sparse matrix in compressed-row form.  For a shift matrix T, row j
/// lists the source cells i whose solid moves into j: T(j, i) is the share of
/// the solid mass of cell i found in cell j one dt_rec later.  Columns sum to 1.
struct CsrMatrix {
  int n = 0;
  std::vector<int64_t> rowPtr; // n + 1 entries
  std::vector<int32_t> col;    // column (source cell) of each entry, sorted per row
  std::vector<double> val;     // share of the source cell's solid mass
  int64_t nnz() const { return rowPtr.empty() ? 0 : rowPtr.back(); }
};

/// One frame k: the bulk solid volume fraction at t_k and the shift from t_k
/// to t_k + dt_rec.
struct FrameRecord {
  std::vector<double> alphaS; // one value per cell, in [0, 1)
  CsrMatrix shift;
};

/// Receives frames in order k = 0, 1, ...; builders stream through it so that
/// only one or two frames are held in memory at a time.
using FrameSink = std::function<void(const FrameRecord &)>;

/// Build a column-stochastic CSR matrix from (destination, source, weight)
/// triplets: duplicates are summed, each column is divided by its total, and
/// columns with no weight become identity columns (an empty cell keeps its
/// nothing).  This is how every builder turns counted transfers into a shift.
CsrMatrix shiftFromTransfers(int n, std::vector<int32_t> dest, std::vector<int32_t> src,
                             std::vector<double> weight);

} // namespace rcfd

namespace rcfd {

/// A row of a shift that a compact frame and a version 3 database file leave
/// out: its only entry is (row, row) with weight exactly 1 (the cell keeps
/// its content).  The one definition for the writer and the loader, so that
/// the rows a file leaves out are the rows the loader would leave out.
template <typename Row, typename Col>
bool isIdentityRow(Row row, const Col *col, const double *val, std::size_t count) {
  return count == 1 && static_cast<Row>(col[0]) == row && val[0] == 1.0;
}

/// One frame's shift on one rank as a loaded database holds it
/// (docs/method.md, "Skipping what does not move"): only the rows of cells
/// whose solid moves.  A row that is not listed is an identity row, T(j, j) = 1
/// alone: its cell keeps its content.  Rows are local (0 .. nlocal - 1).
///
/// Rows come in groups a kernel loops over without branching on their shape:
/// narrow rows of 0, 1, 2, 3 and 4 entries (fixed length: no pointers), narrow
/// rows of more entries, then wide rows.  A narrow row stores each column as
/// a 16-bit offset from the row; a wide row (one entry further away than that,
/// or a cell of another rank while loading) stores full columns.  A column
/// below nlocal is an own cell, nlocal + g is the g-th of the database's ghost
/// cells (ghostRows()).  A row's entries are its own cells in ascending
/// order, then other ranks' cells in ascending PETSc order: the order of
/// PETSc's MPIAIJ product, so that both sum in the same order.
///
/// Entries are numbered across the frame: the narrow rows' in group order,
/// then the wide rows'.  A weight is val[e] in full precision, or
/// (quantum[e] + 1) 2^-weightBits for a database whose weights are quantised
/// (docs/database-format.md, "Quantised weights"); exactly one of the two is
/// filled.
struct CompactFrame {
  static constexpr int kFixed = 5;                 ///< narrow groups of 0 .. 4 entries per row
  static constexpr int kLong = kFixed;             ///< narrow rows of more entries
  static constexpr int kWide = kFixed + 1;         ///< rows with full column numbers
  static constexpr int kGroups = kFixed + 2;
  std::vector<int32_t> rows;                       ///< local row of each moving row, by group
  std::array<int32_t, kGroups + 1> group{};        ///< first row of each group, then the end
  std::array<int32_t, kGroups + 1> firstEntry{};   ///< first entry of each group, then the end
  std::vector<int32_t> ptr;                        ///< first entry of each long or wide row, then the end
  std::vector<int16_t> offset;                     ///< narrow entries: column - row
  std::vector<int32_t> col;                        ///< wide entries (entry e at col[e - offset.size()])
  std::vector<double> val;                         ///< full-precision weights
  std::vector<uint16_t> quantum;                   ///< quantised weights: numerator - 1

  size_t numEntries() const { return offset.size() + col.size(); }
  size_t numRows() const { return rows.size(); }
  size_t bytes() const {
    return (rows.size() + ptr.size() + col.size()) * sizeof(int32_t) + offset.size() * sizeof(int16_t) +
           val.size() * sizeof(double) + quantum.size() * sizeof(uint16_t);
  }
  /// Entries [first, last) of the i-th moving row.
  void entries(size_t i, size_t *first, size_t *last) const {
    int g = 0;
    while (static_cast<int32_t>(i) >= group[g + 1]) ++g;
    if (g < kFixed) {
      *first = static_cast<size_t>(firstEntry[g]) + (i - group[g]) * g;
      *last = *first + g;
    } else {
      *first = ptr[i - group[kLong]];
      *last = ptr[i - group[kLong] + 1];
    }
  }
  /// Column of entry e of the i-th moving row.
  int32_t column(size_t i, size_t e) const {
    return e < offset.size() ? rows[i] + offset[e] : col[e - offset.size()];
  }
};

} // namespace rcfd
