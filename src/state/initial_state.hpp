// The state a run starts from: the inventory mixed into frame 0's solid, in
// layers by size (largest at the bottom), or read from a file.
#pragma once

#include "rcfd/database.hpp"
#include "rcfd/fractions.hpp"

#include <string>

namespace rcfd {

struct InitialState {
  std::string kind = "mixed"; ///< mixed, layered or file (-init)
  std::string file;           ///< HDF5 file with /masses [cells x fractions] in kg (-init_file)
};

/// Collective.  Fills `state` with the masses of `spec`.  A file must match the mesh and
/// the fractions, hold only finite, non-negative masses and some mass; mass in cells that
/// frame 0 says are empty gets one warning with the count and the mass.
PetscErrorCode setInitialState(const InitialState &spec, const Database &db, const FractionSet &fractions,
                               double solidDensity, FractionState &state);

} // namespace rcfd
