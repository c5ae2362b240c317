// Minimum fluidization velocity of a bed of particles of one (Sauter) diameter,
// and the de-fluidization warning built on it.
//
// Every correlation here has the Archimedes-number form
//   Re_mf = sqrt(a^2 + b Ar) - a,   Ar = g d^3 rho_g (rho_p - rho_g) / mu^2,
//   u_mf = Re_mf mu / (rho_g d),
// with its own constants a and b.  They differ by up to 25 % at the sizes of the
// paper's beds (Wen-Yu 0.91 m/s, Saxena-Vogel 1.14 m/s at 2.284 mm), so every
// result names the correlation it used (docs/answers.md shows the spread).
#pragma once

#include <string>
#include <vector>

namespace rcfd {

/// The fluidizing gas.  mu = rho_g nu.
struct GasProperties {
  double density = 1.189;               ///< rho_g [kg/m^3]
  double kinematicViscosity = 1.0e-5;   ///< nu [m^2/s]
  double dynamicViscosity() const { return density * kinematicViscosity; }
};

/// One correlation of the Archimedes-number form.
struct UmfCorrelation {
  std::string name;     ///< option value, e.g. "wen-yu"
  std::string citation; ///< printed with results
  double a = 0.0, b = 0.0;
};

/// The built-in correlations: wen-yu (default), richardson, saxena-vogel, grace, chitester.
const std::vector<UmfCorrelation> &umfCorrelations();
/// Looks a correlation up by name; throws std::invalid_argument listing the known names.
const UmfCorrelation &findUmfCorrelation(const std::string &name);

/// Ar = g d^3 rho_g (rho_p - rho_g) / mu^2 (dimensionless).
double archimedesNumber(double diameter, double particleDensity, const GasProperties &gas,
                        double gravity);
/// u_mf [m/s] of particles of diameter d [m] and density rho_p [kg/m^3].  Uses the
/// cancellation-free form Re_mf = b Ar / (sqrt(a^2 + b Ar) + a), so that fine particles
/// (b Ar << a^2) keep their digits.  Throws std::invalid_argument for a non-positive or
/// non-finite diameter, or a particle density not above the gas density.
double minFluidizationVelocity(const UmfCorrelation &correlation, double diameter,
                               double particleDensity, const GasProperties &gas, double gravity);

/// Fires once: the first time u_mf of the watched layer reaches the superficial gas
/// velocity.  Its state (whether and when it fired) is what a checkpoint keeps.
class DefluidizationDetector {
public:
  explicit DefluidizationDetector(double superficialVelocity = 0.0) : usup(superficialVelocity) {}
  /// True exactly once: at the first call with umf >= the superficial velocity.
  bool update(double time, double umf);
  bool fired() const { return hasFired; }
  /// Time of the first crossing [s]; meaningful only when fired().
  double firstTime() const { return when; }
  double superficialVelocity() const { return usup; }
  /// For checkpoints: {fired ? 1 : 0, first time}.
  std::vector<double> saveState() const { return {hasFired ? 1.0 : 0.0, when}; }
  void restoreState(const std::vector<double> &state);

private:
  double usup;
  bool hasFired = false;
  double when = 0.0;
};

} // namespace rcfd
