// Mesh::createBox for internal code that reports by exceptions (the database
// writers and readers): the same mesh, or std::invalid_argument with
// createBox's sentence.
#pragma once

#include "rcfd/mesh.hpp"

namespace rcfd {

/// Not collective.  Throws std::invalid_argument ("a box mesh of nx x ny x nz
/// cells ...") for a box Mesh::createBox refuses.
Mesh boxMesh(const BoxSpec &spec);

} // namespace rcfd
