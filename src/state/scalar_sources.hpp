// Sources of the scalars carried with the fractions (docs/scalars.md), beside
// the first-order decay: a spray zone that adds liquid to the moisture, and
// the exchange of heat and moisture with the gas (Gunn 1978, or constant
// coefficients), with the gas well mixed at its inlet state or in plug flow
// through the bed's horizontal layers with its own energy and vapour balance.
#pragma once

#include "state/layer_masses.hpp"

#include "rcfd/database.hpp"
#include "rcfd/fractions.hpp"
#include "rcfd/zone.hpp"

#include <memory>
#include <string>
#include <vector>

namespace rcfd {

/// The plug-flow gas's exchange with one layer (docs/scalars.md, "The gas"): the layer's gas is mixed
/// and takes the step's flow G dt; the exchange is implicit (backward Euler) in the gas and the
/// particles together, so every result is a convex combination of the states it starts from.
namespace gas_layer {
/// Heat a particle group of conductance UA dt [J/K] and capacity C = m c_p [J/K] takes per kelvin of
/// T_g - T: g = UA dt C / (C + UA dt) (its new temperature is (C T + UA dt T_g) / (C + UA dt)).
inline double share(double conductanceDt, double capacity) {
  return conductanceDt * capacity / (capacity + conductanceDt);
}
/// The layer's gas (and outlet) state from its inlet state `in`, its flow's capacity F (G c_p,g dt
/// [J/K], or G dt [kg] for the humidity) and the particles' sums S = sum g_k, SX = sum g_k x_k:
/// (F in + SX) / (F + S), between the inlet and the particles' states.
inline double outlet(double in, double flow, double sum, double weighted) {
  return (flow * in + weighted) / (flow + sum);
}
/// The upward sweep: from the inlet state (T_in, Y_in), each layer l's gas state (T_l, Y_l) from its sums
/// sums[4 l ..] = {sum g, sum g T, sum k, sum k Y_s} (k = beta rho_g S dt [kg], Y_s the saturation
/// humidity at the particle's surface), with heatFlow = G c_p,g dt [J/K], vapourFlow = G dt [kg]; the
/// layer's outlet is the next layer's inlet.
void sweep(double inletT, double inletY, double heatFlow, double vapourFlow, const std::vector<double> &sums,
           std::vector<double> *T, std::vector<double> *Y);
/// Saturation humidity [kg vapour per kg dry gas] of water at temperature T [K] and pressure p [Pa]:
/// 0.622 p_s / (p - p_s), p_s from Antoine's equation for water (log10 p_s[mmHg] = 8.07131 -
/// 1730.63 / (233.426 + theta[C]), 1-100 C); T is clipped to that range (99 C at most, where p_s < p).
double saturationHumidity(double T, double pressure);
} // namespace gas_layer

/// Drying's two periods (docs/scalars.md, "Falling rate"): the moisture X [kg/kg] left after dt of
/// drying at the constant rate r [kg/kg/s] while X > X_c and at r X / X_c below (falling linearly to
/// zero at zero moisture): X - r dt, or X_c exp(-r (dt - t_1) / X_c) once it crosses X_c at
/// t_1 = (X - X_c) / r, or X exp(-r dt / X_c) from below; exact for any dt, never below zero.
double dryingRemains(double X, double rate, double dt, double critical);

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
  ///  -scalar_heat_of_evaporation [J/kg] (taken from the temperature as it dries);
  ///  -scalar_critical_moisture X_c [kg/kg]: below it the drying rate falls linearly to zero at zero
  ///   moisture (0, the default: the constant rate down to zero);
  ///  -scalar_gas_model inlet|plug: the gas well mixed at its inlet state, or rising layer by layer
  ///   with its own energy and vapour balance (-scalar_gas_humidity Y_in [kg/kg],
  ///   -scalar_gas_pressure [Pa]; drying toward the saturation humidity of water at the particle's
  ///   temperature).
  PetscErrorCode setFromOptions(MPI_Comm comm, const std::vector<std::string> &names);
  bool any() const { return sprayRate > 0.0 || sprayFollowed || model != Model::None; }
  /// Conditions that change during a run (a live file, docs/live.md), for the steps from now on.
  /// followSpray(), before setUp: the spray rate will be set, so the spray zone is set up even
  /// when -scalar_spray_rate is 0.  setSuperficialVelocity(), after setUp: Gunn's Reynolds numbers
  /// and the gas's flow follow u_sup [m/s].
  void followSpray() { sprayFollowed = true; }
  void setSprayRate(double kgPerSecond) { sprayRate = kgPerSecond; }
  void setGasTemperature(double kelvin) { gasTemperature = kelvin; }
  void setSuperficialVelocity(double metresPerSecond);
  /// The conditions in force (a forecast's members start from the run's).
  bool followsSpray() const { return sprayFollowed; }
  double sprayRateNow() const { return sprayRate; }
  double superficialVelocity() const { return velocity; }
  /// Whether a spray has a scalar to add to (moisture) and the gas an exchange to drive.
  bool canSpray() const { return moisture >= 0; }
  bool exchanges() const { return model != Model::None; }
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
  /// With the plug-flow gas, [5] the heat the gas gave by its own balance, sum G c_p,g dt (T_in -
  /// T_out) [J] (= [3] to round-off), and [6] the water leaving with it at the top, sum G dt Y_out [kg].
  void restoreAccount(const std::vector<double> &a) {
    totals = a;
    totals.resize(7, 0.0);
  }
  bool plugGas() const { return gasModel == Gas::Plug; }
  /// The plug-flow gas at the top of the bed after the last step: temperature [K] and humidity [kg/kg].
  double gasOutletTemperature() const { return outletTemperature; }
  double gasOutletHumidity() const { return outletHumidity; }
  double gasInletHumidity() const { return inletHumidity; }
  double gasPressure() const { return pressure; }
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
  enum class Gas { Inlet, Plug };
  /// The step's exchange with the plug-flow gas (apply's part for -scalar_gas_model plug).
  PetscErrorCode applyPlug(double dt, int frame, PetscInt end, const PetscScalar *m, PetscScalar *a,
                           std::vector<double> &sums);
  /// What follows from u_sup: Gunn's terms per class, the gas's flow and heat capacity flow.
  void gasFromVelocity();
  /// Takes min(wanted, X) [kg] from the moisture of class i in a cell's amounts (never below zero;
  /// negative: condensation), and its heat of evaporation from the temperature (never below 0 K);
  /// adds both to the step's change [scalar][fraction] and to the liquid dried and heat taken.
  void dry(double wanted, int i, PetscScalar *cell, double *change, double *dried, double *evaporated) const;
  Gas gasModel = Gas::Inlet;
  HorizontalLayers layers;
  double inletHumidity = 0.0, pressure = 101325.0, gasFlow = 0.0, outletTemperature = 0.0, outletHumidity = 0.0;
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
  bool sprayFollowed = false;
  std::string sprayZoneName = "spray";
  std::unique_ptr<Zone> sprayZone;
  Model model = Model::None;
  double h = 0.0, beta = 0.0, gasTemperature = 293.15, humidityDeficit = 0.0, conductivity = 0.026,
         prandtl = 0.71, schmidt = 0.6, heatCapacity = 1000.0, evaporation = 0.0, critical = 0.0;
  double gasDensity = 1.2, viscosity = 1.5e-5, velocity = 1.1, solidDensity = 1440.0, gasHeatCapacity = 1005.0,
         capacityFlow = 0.0;
  std::vector<double> diameter;
  const Database *db = nullptr;
  MPI_Comm comm = MPI_COMM_NULL;
  std::vector<double> totals = std::vector<double>(7, 0.0);
};

} // namespace rcfd
