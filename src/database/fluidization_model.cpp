// The case's conditions over the database's, and u_mf in the resolved gas
// (src/database/fluidization_model.hpp).
#include "database/fluidization_model.hpp"

#include <cmath>

namespace rcfd {

OperatingConditions FluidizationModel::resolve(const OperatingConditions &recorded, std::string *sources) const {
  const GasProperties air;
  const double defaults[3] = {1.1, air.density, air.kinematicViscosity};
  const double caseValue[3] = {given.superficialVelocity, given.gasDensity, given.gasKinematicViscosity};
  const double dbValue[3] = {recorded.superficialVelocity, recorded.gasDensity, recorded.gasKinematicViscosity};
  double value[3];
  for (int i = 0; i < 3; ++i) {
    const bool fromCase = std::isfinite(caseValue[i]), fromDb = std::isfinite(dbValue[i]);
    value[i] = fromCase ? caseValue[i] : fromDb ? dbValue[i] : defaults[i];
    if (sources) sources[i] = fromCase ? "case" : fromDb ? "database" : "default";
  }
  return OperatingConditions{value[0], value[1], value[2]};
}

double FluidizationModel::minFluidizationVelocity(double diameter, double particleDensity,
                                                  const OperatingConditions &resolved, double gravity) const {
  GasProperties gas;
  gas.density = resolved.gasDensity;
  gas.kinematicViscosity = resolved.gasKinematicViscosity;
  return rcfd::minFluidizationVelocity(correlation, diameter, particleDensity, gas, gravity);
}

} // namespace rcfd
