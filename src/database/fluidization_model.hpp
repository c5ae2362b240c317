// How a run works out u_mf and u_sup: the one place that decides which gas,
// which superficial velocity and which correlation, so that the bottom layer
// (bottom.csv, the de-fluidization warning) and the switcher's umf_usup signal
// (src/switching) give the same number at the same state.
#pragma once

#include "database/min_fluidization.hpp"
#include "rcfd/database.hpp"

#include <string>

namespace rcfd {

/// The case's operating conditions (-superficial_velocity, -gas_density,
/// -gas_kinematic_viscosity; NaN where not given) and its u_mf correlation
/// (-umf_correlation), read by the answers (src/observable/answers.cpp).
struct FluidizationModel {
  OperatingConditions given;
  UmfCorrelation correlation = findUmfCorrelation("wen-yu");

  /// Each quantity the case's, else the database's in use (`recorded`), else
  /// the default (u_sup 1.1 m/s, air); `sources`, when given, says which for
  /// each of u_sup, rho_g, nu ("case", "database", "default").
  OperatingConditions resolve(const OperatingConditions &recorded, std::string *sources = nullptr) const;
  /// u_mf [m/s] of particles of diameter d [m] and density rho_p [kg/m^3] in
  /// the gas of `resolved` (from resolve()); throws as minFluidizationVelocity.
  double minFluidizationVelocity(double diameter, double particleDensity, const OperatingConditions &resolved,
                                 double gravity) const;
};

} // namespace rcfd
