// The vessel API (include/rcfd/vessel.hpp) for internal code that reports by
// exceptions (builders, database readers, the program's serial parts): the
// same results, or std::invalid_argument with the public function's sentence.
#pragma once

#include "rcfd/vessel.hpp"

#include <string>
#include <vector>

namespace rcfd {

/// vesselMesh(vessel, box, &mesh), thrown on failure.
Mesh cutVesselMesh(const Vessel &vessel, const BoxSpec &box);
/// The vessel of the box cells flagged in `inside` (one per box cell, natural
/// order), each whole; faces open, whole, between two of them; recorded as
/// `line` (a vessel taken from where particles were, docs/vessels.md).  Throws
/// std::invalid_argument when no cell is flagged.
Mesh cellsVesselMesh(const BoxSpec &box, const std::vector<char> &inside, const std::string &line);
/// Vessel::parse(text, &vessel), thrown on failure.
Vessel parseVessel(const std::string &text);
/// vessel.in(box, &out), thrown on failure.
Vessel vesselInBox(const Vessel &vessel, const BoxSpec &box);

} // namespace rcfd
