// The loader's read of one frame: this rank's rows, checked, in PETSc
// numbering, from any format version (database_loader.cpp batches them).
#pragma once

#include "base/h5.hpp"
#include "database/compact_frames.hpp"
#include "rcfd/layout.hpp"

#include <vector>

namespace rcfd {

// This rank's rows of one frame: alpha_s in PETSc order, and the shift as
// local CSR with PETSc column numbers.  Throws on any inconsistency.
struct LocalFrame {
  std::vector<double> alpha;
  LocalShiftRows shift;
};

/// Frame k of an open database file in format `version`: alpha_s of the
/// rank's cells, and with `withShift` the rows of its shift (version 3: only
/// the moving rows, the others implied identity rows).  Throws h5::Error with
/// a sentence naming the frame for anything inconsistent or damaged.
LocalFrame readLocalFrame(const h5::File &f, long long version, int weightBits, int k, const Layout &layout,
                          bool withShift);

} // namespace rcfd
