// The answers' figures (paper Fig. 1, 4, 5, 6) from the CSV files a run wrote.
#pragma once

#include "rcfd/handle.hpp"

#include <string>

namespace rcfd::cli {

/// Collective.  Draws, for each file the run wrote in `dir`: profiles.png
/// (profiles.py), halves.png (halves.py), bottom.png (bottom_layer.py) and
/// snapshots.png (snapshots.py, every snapshot_*.csv).  With a reference
/// directory (rcfd reference's output), its profiles.csv and halves.csv are
/// drawn alongside.
PetscErrorCode drawAnswerFigures(MPI_Comm comm, const std::string &dir, const std::string &referenceDir);

} // namespace rcfd::cli
