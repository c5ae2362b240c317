// The METIS partition of a mesh's cells over the ranks (used by Layout::create).
#pragma once

#include "rcfd/mesh.hpp"

#include "rcfd/handle.hpp"

#include <metis.h>

#include <vector>

namespace rcfd {

/// Part of each cell from METIS (k-way, contiguous parts, fixed seed), balancing
/// `work` per cell when given.  Called on one rank; not collective.
PetscErrorCode partitionCells(const Mesh &mesh, PetscMPIInt nparts, const std::vector<int> *work,
                              std::vector<idx_t> &part);

} // namespace rcfd
