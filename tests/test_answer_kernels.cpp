// The kernels behind the run's answers, against hand-computed numbers: minimum
// fluidization velocity of each correlation, the de-fluidization warning that
// fires once, Lacey's mixing index, bed dynamics and the database distance.
#include "check.hpp"

#include "database/min_fluidization.hpp"
#include "observable/bed_dynamics.hpp"
#include "observable/mixing_index.hpp"

#include <cmath>
#include <stdexcept>

using namespace rcfd;

namespace {

template <typename F> bool throws(F &&f) {
  try {
    f();
  } catch (const std::invalid_argument &) {
    return true;
  }
  return false;
}

void minimumFluidization() {
  const GasProperties air{1.189, 1.0e-5}; // the paper's gas
  const double g = 9.81, rho = 1440.0;
  // Ar = 9.81 * 2.284e-3^3 * 1.189 * 1438.811 / (1.189e-5)^2 = 1,414,422.6; Wen-Yu:
  // Re = sqrt(33.7^2 + 0.0408 Ar) - 33.7 = 255.33, u = Re mu / (rho_g d) = 0.91453 m/s.
  RCFD_CHECK_CLOSE(archimedesNumber(2.284e-3, rho, air, g), 1414422.6453, 1e-10 * 1414422.6453);
  const auto &wy = findUmfCorrelation("wen-yu");
  RCFD_CHECK_CLOSE(minFluidizationVelocity(wy, 2.284e-3, rho, air, g), 0.9145275771, 1e-9);
  RCFD_CHECK_CLOSE(minFluidizationVelocity(wy, 1.459e-3, rho, air, g), 0.6408025684, 1e-9);
  RCFD_CHECK_CLOSE(minFluidizationVelocity(wy, 4.075e-3, rho, air, g), 1.3246129442, 1e-9);
  // Saxena-Vogel lies above 1.1 m/s at 2.284 mm (the example).
  const auto &sv = findUmfCorrelation("saxena-vogel");
  RCFD_CHECK_CLOSE(minFluidizationVelocity(sv, 2.284e-3, rho, air, g), 1.1384115660, 1e-9);
  // Every correlation grows with the diameter.
  for (const auto &c : umfCorrelations())
    RCFD_CHECK(minFluidizationVelocity(c, 3e-3, rho, air, g) > minFluidizationVelocity(c, 2e-3, rho, air, g));
  // Fine particles: the Stokes limit u = b g d^2 (rho_p - rho_g) / (2 a mu), kept to its digits.
  const double d = 1e-6, mu = air.dynamicViscosity();
  const double stokes = wy.b * g * d * d * (rho - air.density) / (2.0 * wy.a * mu);
  RCFD_CHECK(std::fabs(minFluidizationVelocity(wy, d, rho, air, g) / stokes - 1.0) < 1e-6);
  RCFD_CHECK(throws([] { findUmfCorrelation("wenyu"); }));
  RCFD_CHECK(throws([&] { minFluidizationVelocity(wy, -1e-3, rho, air, g); }));
  RCFD_CHECK(throws([&] { minFluidizationVelocity(wy, std::nan(""), rho, air, g); }));
  RCFD_CHECK(throws([&] { minFluidizationVelocity(wy, 1e-3, 1.0, air, g); }));
}

void warningFiresOnce() {
  DefluidizationDetector detector(1.1);
  RCFD_CHECK(!detector.update(0.0, 0.95));
  RCFD_CHECK(!detector.update(0.5, 1.0999999));
  RCFD_CHECK(detector.update(1.0, 1.1)); // reaching u_sup is enough
  RCFD_CHECK(!detector.update(1.5, 1.3)); // never twice
  RCFD_CHECK(!detector.update(2.0, 0.9));
  RCFD_CHECK(!detector.update(2.5, 1.4));
  RCFD_CHECK(detector.fired() && detector.firstTime() == 1.0);
  DefluidizationDetector restarted(1.1);
  restarted.restoreState(detector.saveState());
  RCFD_CHECK(restarted.fired() && restarted.firstTime() == 1.0 && !restarted.update(3.0, 2.0));
  RCFD_CHECK(!DefluidizationDetector(1.1).update(0.0, std::nan(""))); // NaN never fires
  RCFD_CHECK(throws([&] { restarted.restoreState({0.5, 1.0}); }));
}

void laceyIndex() {
  // Completely segregated: two cells of one fraction each, p = 1/2: M = 0.
  LaceySums seg;
  seg.addCell(1.0, 1.0, 1e6);
  seg.addCell(0.0, 1.0, 1e6);
  RCFD_CHECK_CLOSE(seg.index(0.5), 0.0, 1e-15);
  // Shares 0.3 and 0.7 in equal masses, 100 particles a cell:
  // s^2 = 0.04, s0^2 = 0.25, sR^2 = 0.0025, M = 0.21 / 0.2475.
  LaceySums part;
  part.addCell(0.3, 1.0, 100);
  part.addCell(0.7, 1.0, 100);
  RCFD_CHECK_CLOSE(part.index(0.5), 0.21 / 0.2475, 1e-14);
  // A random mixture sampled 100 particles at a time: s^2 = sR^2, M = 1.
  LaceySums random;
  const double p = 0.2, sr = std::sqrt(p * (1 - p) / 100.0);
  random.addCell(p + sr, 1.0, 100);
  random.addCell(p - sr, 1.0, 100);
  RCFD_CHECK_CLOSE(random.index(p), 1.0, 1e-12);
  // Empty cells do not count; one fraction only (p = 1) has no index.
  LaceySums withEmpty = part;
  withEmpty.addCell(0.0, 0.0, 0.0);
  RCFD_CHECK(withEmpty.index(0.5) == part.index(0.5));
  RCFD_CHECK(std::isnan(part.index(1.0)) && std::isnan(LaceySums().index(0.5)));
}

void bedDynamicsAndDistance() {
  // mean 3, deviations 2, 1, 0, 3: 1.5.
  RCFD_CHECK_CLOSE(bedDynamics({1.0, 2.0, 3.0, 6.0}), 1.5, 1e-15);
  RCFD_CHECK(bedDynamics({0.25, 0.25, 0.25}) == 0.0);
  RCFD_CHECK_CLOSE(databaseDistance(0.0092, 0.0100), 0.08, 1e-14);
  RCFD_CHECK_CLOSE(databaseDistance(0.0331, 0.0100), 2.31, 1e-14); // paper Table 6's 231 %
  RCFD_CHECK(throws([] { bedDynamics({}); }));
  RCFD_CHECK(throws([] { databaseDistance(1.0, 0.0); }));
}

} // namespace

int main() {
  minimumFluidization();
  warningFiresOnce();
  laceyIndex();
  bedDynamicsAndDistance();
  return RCFD_TEST_RESULT();
}
