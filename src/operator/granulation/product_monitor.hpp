// product.csv and steady_state.csv: what leaves a granulator's discharge
// zone over time, the holdup's size distribution, and when it is steady.
#pragma once

#include "rcfd/granulation.hpp"
#include "rcfd/observables.hpp"

#include <limits>
#include <memory>

namespace rcfd {

/// The steady-state criterion on the product.  tau = H0 / m_d is the mean
/// residence time (initial holdup over the discharge rate).  At time t the
/// product size distribution P(t) is the mass shares of what left during the
/// last residence time (t - tau, t]; its change is the L1 distance
///   change(t) = sum_i |P_i(t) - P_i(t - tau)|
/// (twice the largest difference of a cumulative share; 0 for a steady
/// product), defined from t = 2 tau on.  The product is steady from the
/// first row of the last unbroken run of rows with change <= tolerance; a
/// run whose last row is above the tolerance has not reached it.
/// Rows are added one by one (add()); the series keeps only the rows that
/// later rows still need (the last 2 tau and one before), so its memory is
/// bounded by the residence time, not by the run's length, and every
/// product and change is what the whole history would give.
struct ProductSeries {
  int nf = 0;
  double rate = 0.0, tolerance = 0.02; // discharge rate [kg/s]
  static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  /// H0 [kg], the first row's holdup, and the start of the current run of
  /// steady rows (NaN: the last row is not steady).
  double holdup0 = nan, steadySince = nan;
  /// The rows kept, {t, discharged_1..nf (cumulative kg), holdup_1..nf (kg)}.
  std::vector<double> rows;

  std::size_t width() const { return 1 + 2 * nf; }
  std::size_t size() const { return nf ? rows.size() / width() : 0; }
  const double *row(std::size_t r) const { return rows.data() + r * width(); }
  /// Appends a row (times increasing) and updates steadySince; drops the rows
  /// no later row can need.  Returns the row's change (NaN before 2 tau).
  double add(const std::vector<double> &row);
  /// tau [s] from the first row's holdup (infinite without discharge).
  double residenceTime() const;
  /// P(t) of kept row r over the window (t - tau, t] (NaN where undefined).
  std::vector<double> product(std::size_t r) const;
  /// change(t) of kept row r (NaN before 2 tau).
  double change(std::size_t r) const;
  /// Time from which the product stays steady, NaN when the last row is not.
  double steadyTime() const { return steadySince; }
  /// {holdup0, steadySince, rows...}, and back.
  std::vector<double> state() const;
  bool restore(const double *begin, std::size_t n);

private:
  /// Index of the last kept row at or before time t (1e-9 tau slack), or -1.
  long rowAt(double t) const;
  double slack() const { return 1e-9 * residenceTime(); }
};

class ProductMonitor final : public Monitor {
public:
  explicit ProductMonitor(const DischargeOperator &discharge) : discharge(discharge) {}
  PetscErrorCode setUp(const RunContext &run, const FractionState &, const std::string &dir) override;
  PetscErrorCode sample(const MonitorContext &ctx) override;
  PetscErrorCode flush() override;
  /// {length of product.csv or -1 before it is written, the series' state}
  std::vector<double> saveState() const override;
  PetscErrorCode restoreState(const std::vector<double> &state) override;
  bool detectsSteadyState() const override { return true; }
  /// Collective.  The criterion at ctx's time, on a copy of the series with
  /// the row the monitor would add there; at the time of its last row, that row's.
  PetscErrorCode steadyAt(const MonitorContext &ctx, bool *steady) const override;

private:
  PetscErrorCode currentRow(const MonitorContext &ctx, std::vector<double> *row) const;
  /// The product's value of each scalar over the last interval (its amount
  /// discharged over the mass discharged since the last row; NaN when none
  /// left), and moves the last row's totals on.
  std::vector<double> productValues();
  const DischargeOperator &discharge;
  std::vector<std::string> scalarNames;
  std::vector<double> lastOut, values; // discharged {mass, amount per scalar} at the last row; the values then
  const FractionSet *fractions = nullptr;
  MPI_Comm comm = MPI_COMM_NULL;
  std::string dir;
  ProductSeries series;
  std::unique_ptr<CsvSeries> csv;
};

} // namespace rcfd
