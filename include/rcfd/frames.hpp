// Serial, PETSc-free description of database frames, produced by the
// builders (synthetic bed, particle snapshots, Eulerian frames) and consumed
// by the database writer.  Cell indices are natural mesh indices.
#pragma once

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
