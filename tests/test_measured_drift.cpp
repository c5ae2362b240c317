// The drift measured from particles: two hand-made particles in one cell
// give their velocities relative to the cell's bulk by hand, with the
// standard error of two frames; particles seen once or outside are left out;
// the least-squares k_d recovers the k_d that made a drift.
#include "check.hpp"
#include "registry_helpers.hpp"

#include "analysis/measured_drift.hpp"
#include "rcfd/size_law.hpp"

#include <cmath>
#include <stdexcept>

using namespace rcfd;

namespace {

ParticleSnapshot snapshot(const std::vector<int64_t> &id, const std::vector<double> &d,
                          const std::vector<double> &z) {
  ParticleSnapshot s;
  s.id = id;
  s.diameter = d;
  for (std::size_t p = 0; p < id.size(); ++p) {
    s.type.push_back(1);
    s.position.push_back({0.01, 0.01, z[p]});
    s.mass.push_back(1000.0 * M_PI / 6.0 * d[p] * d[p] * d[p]); // the large one weighs 8 small ones
  }
  return s;
}

} // namespace

int main() {
  SizeClasses classes;
  classes.diameter = {1e-3, 2e-3};
  BoxSpec cell;
  cell.nx = cell.ny = cell.nz = 1;
  cell.length = {0.02, 0.02, 0.02};
  MeasuredDrift drift(classes, AxisMap{}, cell);
  const double dt = 0.01;
  // Frame 1: small +3e-4 m, large -1e-4 m; bulk (3e-4 - 8e-4) / 9.  Particle 3 is
  // only in the first snapshot, particle 4 starts outside the mesh.
  drift.add(snapshot({1, 2, 3, 4}, {1e-3, 2e-3, 1e-3, 1e-3}, {0.010, 0.012, 0.005, 0.05}),
            snapshot({2, 1, 4}, {2e-3, 1e-3, 1e-3}, {0.0119, 0.0103, 0.0}), dt);
  // Frame 2: small +1e-4 m, large -1e-4 m.
  drift.add(snapshot({1, 2}, {1e-3, 2e-3}, {0.010, 0.012}), snapshot({1, 2}, {1e-3, 2e-3}, {0.0101, 0.0119}),
            dt);
  const auto r = drift.result();
  RCFD_CHECK(r.size() == 2 && drift.framesAdded() == 2);
  const double bulk1 = (3e-4 - 8e-4) / 9.0, bulk2 = (1e-4 - 8e-4) / 9.0;
  const double s1 = (3e-4 - bulk1) / dt, s2 = (1e-4 - bulk2) / dt;
  const double l1 = (-1e-4 - bulk1) / dt, l2 = (-1e-4 - bulk2) / dt;
  RCFD_CHECK_CLOSE(r[0].velocity, 0.5 * (s1 + s2), 1e-12);
  RCFD_CHECK_CLOSE(r[1].velocity, 0.5 * (l1 + l2), 1e-12);
  // Two frame means: standard error |a - b| / 2.
  RCFD_CHECK_CLOSE(r[0].standardError, std::fabs(s1 - s2) / 2.0, 1e-12);
  RCFD_CHECK(r[0].particles == 2 && r[1].particles == 2 && r[0].frames == 2);
  // Relative to the bulk: the mass-weighted drifts cancel in every frame.
  RCFD_CHECK_CLOSE(r[0].velocity * 1.0 + r[1].velocity * 8.0, 0.0, 1e-12);
  // The fit recovers k_d from drifts made with it, for both shapes.
  const double kd = 4.2e3, d32 = 2.2e-3;
  const SizeLawRegistry laws = SizeLawRegistry::withBuiltins();
  const auto lawA = created(laws, "A"), lawB = created(laws, "B");
  for (const SizeLaw *shape : {lawA.get(), lawB.get()}) {
    std::vector<MeasuredDrift::ClassDrift> made;
    for (double d : {1.5e-3, 2.0e-3, 3.0e-3}) {
      const double dd = d - d32, x = shape == lawA.get() ? d * d - d32 * d32 : dd * std::fabs(dd);
      made.push_back({d, -kd * x, 1e-4, 100, 10});
    }
    const DriftFit fit = fitDriftCoefficient(made, d32, *shape);
    RCFD_CHECK_CLOSE(fit.kd / kd, 1.0, 1e-12);
    RCFD_CHECK(fit.chiSquarePerDof < 1e-20 && fit.standardError > 0.0);
  }
  // Relative to the bulk (the drift the face swaps realise): u_i = -k_d (x_i - sum s_j x_j)
  // with the classes' mass shares s_j; the mass-weighted velocities cancel, and the fit
  // recovers k_d, which the plain fit does not; the table round trip keeps every number.
  {
    const std::vector<double> d{1.6e-3, 3.0e-3}, share{0.5, 0.5};
    const double sauter = 1.0 / (0.5 / 1.6e-3 + 0.5 / 3.0e-3);
    for (const SizeLaw *shape : {lawA.get(), lawB.get()}) {
      auto law = [&](double di) {
        const double dd = di - sauter;
        return shape == lawA.get() ? di * di - sauter * sauter : dd * std::fabs(dd);
      };
      const double mean = share[0] * law(d[0]) + share[1] * law(d[1]);
      std::vector<MeasuredDrift::ClassDrift> made;
      for (int c = 0; c < 2; ++c) made.push_back({d[c], -kd * (law(d[c]) - mean), 1e-4, 100, 10, share[c]});
      RCFD_CHECK_CLOSE(made[0].velocity * share[0] + made[1].velocity * share[1], 0.0, 1e-15);
      RCFD_CHECK_CLOSE(fitDriftCoefficient(made, sauter, *shape, true).kd / kd, 1.0, 1e-12);
      RCFD_CHECK(std::fabs(fitDriftCoefficient(made, sauter, *shape).kd / kd - 1.0) > 0.05);
      const auto back = measuredDriftFromTable(measuredDriftTable(made), kMeasuredDriftColumns);
      RCFD_CHECK(back.size() == 2 && back[1].velocity == made[1].velocity && back[1].massShare == 0.5 &&
                 back[0].frames == 10 && back[0].particles == 100);
    }
    RCFD_CHECK_CLOSE(r[0].massShare, 1.0 / 9.0, 1e-12); // matched mass: one small, one large of 8
    // Nobody left the cell: everything is in the first agitation bin, a = 0.
    const auto bins = drift.byAgitation();
    RCFD_CHECK(bins.size() == 2 * MeasuredDrift::kAgitationBins && bins[0].agitation == 0.0 &&
               drift.meanAgitation() == 0.0);
    RCFD_CHECK(bins[0].drift.velocity == r[0].velocity && bins[1].drift.velocity == r[1].velocity);
    RCFD_CHECK(bins[2].drift.frames == 0 && std::isnan(bins[2].drift.velocity));
  }
  // The exponent of a drift scaled by (a/a_bar)^n: bins made with n = 1.7 and k_d give both back.
  {
    const double sauter = 2.0e-3, aBar = 0.2, n = 1.7;
    std::vector<MeasuredDrift::ClassDrift> bed{{1.6e-3, 0.0, 1e-4, 10, 10, 0.5}, {3.0e-3, 0.0, 1e-4, 10, 10, 0.5}};
    const double mean = 0.5 * (1.6e-3 * 1.6e-3 + 3.0e-3 * 3.0e-3) - sauter * sauter;
    std::vector<MeasuredDrift::BinDrift> bins;
    for (double a : {0.05, 0.15, 0.3, 0.6})
      for (const auto &c : bed) {
        MeasuredDrift::BinDrift b{a, c};
        b.drift.velocity = -kd * (c.diameter * c.diameter - sauter * sauter - mean) * std::pow(a / aBar, n);
        bins.push_back(b);
      }
    const auto table = driftByAgitationTable(bins);
    const AgitationDriftFit fit = fitAgitationExponent(
        driftByAgitationFromTable(table, kDriftByAgitationColumns), bed, aBar, sauter, *lawA);
    RCFD_CHECK_CLOSE(fit.exponent, n, 1e-9);
    RCFD_CHECK_CLOSE(fit.kd / kd, 1.0, 1e-9);
  }
  bool refused = false;
  try {
    fitDriftCoefficient({{1e-3, 0.1, 0.0, 1, 1}}, 1e-3, *lawB);
  } catch (const std::invalid_argument &) {
    refused = true;
  }
  RCFD_CHECK(refused);
  return RCFD_TEST_RESULT();
}
