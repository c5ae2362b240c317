// product.csv and steady_state.csv: what leaves a granulator's discharge
// zone over time, the holdup's size distribution, and when it is steady.
#pragma once

#include "rcfd/granulation.hpp"
#include "rcfd/observables.hpp"

#include "observable/answers.hpp"
#include "observable/number_rows.hpp"

#include <limits>

namespace rcfd {

/// The steady-state criterion on the product.  tau = H0 / m_d is the mean
/// residence time (initial holdup over the discharge rate).  At time t the
/// product size distribution P(t) is the mass shares of what left during the
/// last residence time (t - tau, t]; its change is the L1 distance
///   change(t) = sum_i |P_i(t) - P_i(t - tau)|
/// (twice the largest difference of a cumulative share; 0 for a steady
/// product), defined from t = 2 tau on.  The product is steady from the
/// first sample after which change <= tolerance holds at every sample to the
/// end of the run; a run that ends above the tolerance has not reached it.
struct ProductSeries {
  /// Rows of {t, discharged_1..nf (cumulative kg), holdup_1..nf (kg)}.
  int nf = 0;
  double rate = 0.0, tolerance = 0.02; // discharge rate [kg/s]
  std::vector<double> rows;
  static constexpr double nan = std::numeric_limits<double>::quiet_NaN();

  std::size_t size() const { return nf ? rows.size() / (1 + 2 * nf) : 0; }
  const double *row(std::size_t r) const { return rows.data() + r * (1 + 2 * nf); }
  /// tau [s] from the first row's holdup (infinite without discharge).
  double residenceTime() const;
  /// P(t) of row r over the window (t - tau, t] (NaN where undefined).
  std::vector<double> product(std::size_t r) const;
  /// change(t) of row r (NaN before 2 tau).
  double change(std::size_t r) const;
  /// Time from which the product stays steady, NaN when the last row is not.
  double steadyTime() const;

private:
  /// Discharged mass of each class up to time t: the last row at or before t (t - 1e-9 tau slack).
  bool dischargedAt(double t, std::vector<double> *mass) const;
};

class ProductMonitor final : public Monitor {
public:
  explicit ProductMonitor(const DischargeOperator &discharge) : discharge(discharge) {}
  PetscErrorCode setUp(const RunContext &run, const FractionState &, const std::string &dir) override;
  PetscErrorCode sample(const MonitorContext &ctx) override;
  PetscErrorCode flush() override;
  std::vector<double> saveState() const override { return series.rows; }
  PetscErrorCode restoreState(const std::vector<double> &state) override;

private:
  const DischargeOperator &discharge;
  const FractionSet *fractions = nullptr;
  MPI_Comm comm = MPI_COMM_NULL;
  std::string dir;
  ProductSeries series;
};

} // namespace rcfd
