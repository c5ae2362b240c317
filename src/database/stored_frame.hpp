// A frame as a database file stores it (docs/database-format.md): the
// datasets of each format version, written and read whole, and the checks
// on the version 3 moving-row index that the loader shares.  Whole frames
// are for tools that transform them (rcfd coarsen, quantisation) and must not
// see the loader's rescaling; the loader reads each rank's rows itself.
#pragma once

#include "base/h5.hpp"
#include "rcfd/frames.hpp"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace rcfd {

/// "/frames/000012" for k = 12.
std::string frameGroup(int k);

/// Throws `damaged` (met while reading frame k of `f`) again as the sentence
/// of the frame: "database 'F', frame 12: dataset shift_col is damaged (...)".
[[noreturn]] void throwDamagedFrame(const h5::Damaged &damaged, const h5::File &f, int k);

/// Writes `frame` as group `group` in format `version`: 2 (and 1) full CSR
/// (shift_row_ptr int64, shift_col, shift_val); 3 its moving rows only
/// (moving_row, moving_row_ptr int32 or int64 as the entries need,
/// shift_col, and shift_val or, with weightBits > 0, shift_quantum uint16
/// = 2^weightBits w - 1).  The weights must already be quantised so.
void writeStoredFrame(const h5::File &f, const std::string &group, const FrameRecord &frame, long long version,
                      int weightBits);

/// Frame k of an open database file with `cells` cells, as full CSR in
/// natural order, weights as written (a version 3 file's identity rows put
/// back); throws h5::Error with a sentence naming the frame and the fault.
FrameRecord readStoredFrame(const h5::File &f, int k, int cells);

/// Version 3: what one frame's shift datasets hold, checked against each
/// other and the mesh before any entry is read.  `movingRow` is read whole
/// (every rank needs it to find its rows; 4 bytes per moving row).
struct MovingRowIndex {
  std::vector<int32_t> movingRow; ///< natural rows, strictly ascending, within the mesh
  hsize_t entries = 0;            ///< length of shift_col and of the weights
};
MovingRowIndex readMovingRowIndex(const h5::File &f, const std::string &group, const std::string &where, int cells,
                                  int weightBits);

/// Version 3: moving_row_ptr for the positions [lo, hi + 1) of each run
/// [lo, hi) (sorted, disjoint, not touching), checked non-decreasing and
/// within the index's entries; the entry runs they delimit come back in
/// `entryRuns` (empty rows left out).
std::vector<int64_t> readMovingRowPtr(const h5::File &f, const std::string &group, const std::string &where,
                                      const MovingRowIndex &index,
                                      const std::vector<std::pair<hsize_t, hsize_t>> &rowRuns,
                                      std::vector<std::pair<hsize_t, hsize_t>> *entryRuns);

/// Version 3: the weights of the entries in `runs` as doubles (shift_val, or
/// (shift_quantum + 1) 2^-weightBits, exact).
std::vector<double> readStoredWeights(const h5::File &f, const std::string &group,
                                      const std::vector<std::pair<hsize_t, hsize_t>> &runs, int weightBits);

} // namespace rcfd
