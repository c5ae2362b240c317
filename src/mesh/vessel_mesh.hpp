// The vessel API (include/rcfd/vessel.hpp) for internal code that reports by
// exceptions (builders, database readers, the program's serial parts): the
// same results, or std::invalid_argument with the public function's sentence.
#pragma once

#include "rcfd/vessel.hpp"

#include <string>

namespace rcfd {

/// vesselMesh(vessel, box, &mesh), thrown on failure.
Mesh cutVesselMesh(const Vessel &vessel, const BoxSpec &box);
/// Vessel::parse(text, &vessel), thrown on failure.
Vessel parseVessel(const std::string &text);
/// vessel.in(box, &out), thrown on failure.
Vessel vesselInBox(const Vessel &vessel, const BoxSpec &box);

} // namespace rcfd
