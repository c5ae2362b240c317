#include "database/min_fluidization.hpp"

#include <cmath>
#include <stdexcept>

namespace rcfd {

const std::vector<UmfCorrelation> &umfCorrelations() {
  // Constants (a, b) of Re_mf = sqrt(a^2 + b Ar) - a as tabulated in the
  // fluidization literature.
  static const std::vector<UmfCorrelation> table = {
      {"wen-yu", "Wen & Yu (1966)", 33.7, 0.0408},
      {"richardson", "Richardson (1971)", 25.7, 0.0365},
      {"saxena-vogel", "Saxena & Vogel (1977)", 25.3, 0.0571},
      {"grace", "Grace (1982)", 27.2, 0.0408},
      {"chitester", "Chitester et al. (1984)", 28.7, 0.0494},
  };
  return table;
}

const UmfCorrelation &findUmfCorrelation(const std::string &name) {
  std::string known;
  for (const auto &c : umfCorrelations()) {
    if (c.name == name) return c;
    known += (known.empty() ? "" : ", ") + c.name;
  }
  throw std::invalid_argument("the minimum fluidization correlation '" + name +
                              "' is not known; use one of " + known);
}

double archimedesNumber(double d, double rhoP, const GasProperties &gas, double g) {
  const double mu = gas.dynamicViscosity();
  return g * d * d * d * gas.density * (rhoP - gas.density) / (mu * mu);
}

double minFluidizationVelocity(const UmfCorrelation &c, double d, double rhoP,
                               const GasProperties &gas, double g) {
  if (!(d > 0.0) || !std::isfinite(d))
    throw std::invalid_argument("u_mf needs a positive, finite particle diameter");
  if (!(rhoP > gas.density) || !std::isfinite(rhoP))
    throw std::invalid_argument("u_mf needs a particle density above the gas density");
  if (!(gas.density > 0.0) || !(gas.kinematicViscosity > 0.0))
    throw std::invalid_argument("u_mf needs a positive gas density and viscosity");
  const double bAr = c.b * archimedesNumber(d, rhoP, gas, g);
  const double reynolds = bAr / (std::sqrt(c.a * c.a + bAr) + c.a);
  return reynolds * gas.dynamicViscosity() / (gas.density * d);
}

bool DefluidizationDetector::update(double time, double umf) {
  if (hasFired || !(umf >= usup)) return false;
  hasFired = true;
  when = time;
  return true;
}

void DefluidizationDetector::restoreState(const std::vector<double> &state) {
  if (state.size() != 2 || (state[0] != 0.0 && state[0] != 1.0))
    throw std::invalid_argument("the saved de-fluidization state is malformed");
  hasFired = state[0] == 1.0;
  when = state[1];
}

} // namespace rcfd
