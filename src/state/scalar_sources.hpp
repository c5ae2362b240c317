// Sources of the scalars carried with the fractions (docs/scalars.md), beside
// the first-order decay: a spray zone that adds liquid to the moisture, and
// the exchange of heat and moisture with the gas (Gunn 1978, or constant
// coefficients), with the gas well mixed at its inlet state.
#pragma once

#include "rcfd/database.hpp"
#include "rcfd/fractions.hpp"
#include "rcfd/zone.hpp"

#include <memory>
#include <string>
#include <vector>

namespace rcfd {

class ScalarSources {
public:
  /// Collective.  Reads, for the scalars `names` (-scalars):
  ///  -scalar_spray_rate m_l [kg/s] of liquid into -scalar_spray_zone (a zone of
  ///   -zones, default spray), added to the scalar `moisture` (kg liquid per kg
  ///   solid), shared by surface (m_i / d_i) among the zone's particles;
  ///  -scalar_exchange_model none|gunn|constant: heat to `temperature` [K] and
  ///   drying of `moisture` toward the gas, per unit particle surface;
  ///  -scalar_exchange_h [W/m^2/K], -scalar_exchange_beta [m/s] (constant), the gas:
  ///  -scalar_gas_temperature [K], -scalar_gas_humidity_deficit (Y_s - Y_g, kg/kg),
  ///  -scalar_gas_conductivity, -scalar_gas_prandtl, -scalar_gas_schmidt, and the
  ///  solid's -scalar_solid_heat_capacity [J/kg/K] and the liquid's
  ///  -scalar_heat_of_evaporation [J/kg] (taken from the temperature as it dries).
  PetscErrorCode setFromOptions(MPI_Comm comm, const std::vector<std::string> &names);
  bool any() const { return sprayRate > 0.0 || model != Model::None; }
  /// Collective.  The spray zone on the mesh, the diameters, the gas (-superficial_velocity,
  /// -gas_density, -gas_kinematic_viscosity, else the database's, else air at 1.1 m/s).
  PetscErrorCode setUp(const Database &db, const FractionSet &fractions, double solidDensity);
  /// Collective (one reduction).  One step of dt on the state in frame `frame`
  /// (its alpha_s gives the voidage of Gunn's correlation): exchange and drying
  /// in every cell, then the spray.  `change` [scalar][fraction] receives the
  /// global change of every total (for the ledger).
  PetscErrorCode apply(double dt, int frame, FractionState &state, std::vector<double> *change);
  /// Totals since the start (the same on every rank): liquid sprayed [kg],
  /// liquid that missed an empty spray zone [kg], liquid dried [kg], heat into
  /// the solid from the gas [J], heat of evaporation taken [J].
  const std::vector<double> &account() const { return totals; }
  void restoreAccount(const std::vector<double> &a) { totals = a; }
  /// Heat-transfer coefficient h [W/m^2/K] and mass-transfer coefficient
  /// beta [m/s] of particles of diameter d in a cell of voidage eps.
  double heatCoefficient(double d, double eps) const;
  double massCoefficient(double d, double eps) const;
  /// tau = rho_s c_p d / (6 h): the time constant of a particle's temperature.
  double heatTimeConstant(double d, double eps) const;
  /// One line on what the sources are, for the run's view.
  std::string describe() const;
  /// The gas's heat capacity flow rho_g u_sup A c_p,g [W/K] through the bed's cross-section A (a box
  /// mesh; 0 when unknown), for the check of the well-mixed gas (ScalarSet::report).
  double gasCapacityFlow() const { return capacityFlow; }
  double gasInletTemperature() const { return gasTemperature; }
  bool exchangesHeat() const { return model != Model::None && temperature >= 0; }
  int temperatureColumn() const { return temperature; }

private:
  enum class Model { None, Gunn, Constant };
  /// Gunn (1978): Nu (or Sh, with Sc for Pr) of a particle in a bed of voidage eps.
  double gunn(double reynolds, double prandtl, double eps) const;
  /// Gunn's Nu = (7 - 10 eps + 5 eps^2) a + (1.33 - 2.4 eps + 1.2 eps^2) b with a, b of the class
  /// (its Re and Pr or Sc), computed once at set-up: the steps evaluate polynomials only.
  struct Terms {
    double a = 0.0, b = 0.0;
  };
  std::vector<Terms> heatTerms, massTerms; // per class
  /// h [W/m^2/K] and beta [m/s] of class i in a cell of voidage eps.
  void classCoefficients(int i, double eps, double *heat, double *mass) const;
  int temperature = -1, moisture = -1, ns = 0, nf = 0;
  double sprayRate = 0.0;
  std::string sprayZoneName = "spray";
  std::unique_ptr<Zone> sprayZone;
  Model model = Model::None;
  double h = 0.0, beta = 0.0, gasTemperature = 293.15, humidityDeficit = 0.0, conductivity = 0.026,
         prandtl = 0.71, schmidt = 0.6, heatCapacity = 1000.0, evaporation = 0.0;
  double gasDensity = 1.2, viscosity = 1.5e-5, velocity = 1.1, solidDensity = 1440.0, gasHeatCapacity = 1005.0,
         capacityFlow = 0.0;
  std::vector<double> diameter;
  const Database *db = nullptr;
  MPI_Comm comm = MPI_COMM_NULL;
  std::vector<double> totals = std::vector<double>(5, 0.0);
};

} // namespace rcfd
