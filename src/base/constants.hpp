// Physical constants and the defaults rcfd assumes when a case does not say
// otherwise.  The one place these numbers are written in the library and the
// program (the public DatabaseMetadata repeats the two defaults, since public
// headers cannot include this one; tests/test_base.cpp checks they agree).
#pragma once

namespace rcfd {

inline constexpr double kPi = 3.14159265358979323846;

/// Standard gravity [m/s^2]; databases store gravity as a vector, pointing
/// down along -z unless a builder is told otherwise.
inline constexpr double kGravity = 9.81;

/// Particle material density [kg/m^3] of the paper's glass beads, the
/// default for databases and particle input that give none.
inline constexpr double kDefaultSolidDensity = 1440.0;

} // namespace rcfd
