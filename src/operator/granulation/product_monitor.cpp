#include "operator/granulation/product_monitor.hpp"
#include "base/petsc_compat.hpp"
#include "base/number_rows.hpp"

#include <cmath>

namespace rcfd {

double ProductSeries::residenceTime() const {
  if (!std::isfinite(holdup0) || !(rate > 0)) return std::numeric_limits<double>::infinity();
  return holdup0 / rate;
}

long ProductSeries::rowAt(double t) const {
  long found = -1;
  for (std::size_t r = 0; r < size() && row(r)[0] <= t + slack(); ++r) found = static_cast<long>(r);
  return found;
}

std::vector<double> ProductSeries::product(std::size_t r) const {
  std::vector<double> shares(nf, nan);
  const double tau = residenceTime(), t = row(r)[0] - tau;
  const long before = std::isfinite(tau) && t >= -slack() ? rowAt(t) : -1;
  if (before < 0) return shares;
  double total = 0.0;
  for (int i = 0; i < nf; ++i) total += row(r)[1 + i] - row(before)[1 + i];
  if (!(total > 0)) return shares;
  for (int i = 0; i < nf; ++i) shares[i] = (row(r)[1 + i] - row(before)[1 + i]) / total;
  return shares;
}

double ProductSeries::change(std::size_t r) const {
  const double tau = residenceTime();
  if (!std::isfinite(tau)) return nan;
  const long earlier = rowAt(row(r)[0] - tau); // the row at t - tau
  if (earlier < 0) return nan;
  const std::vector<double> now = product(r), then = product(earlier);
  double sum = 0.0;
  for (int i = 0; i < nf; ++i) sum += std::fabs(now[i] - then[i]);
  return sum; // NaN when either window is undefined
}

double ProductSeries::add(const std::vector<double> &values) {
  if (size() == 0 && !std::isfinite(holdup0)) {
    holdup0 = 0.0;
    for (int i = 0; i < nf; ++i) holdup0 += values[1 + nf + i];
  }
  rows.insert(rows.end(), values.begin(), values.end());
  const std::size_t last = size() - 1;
  const double c = change(last);
  if (!(c <= tolerance)) steadySince = nan; // NaN too
  else if (std::isnan(steadySince)) steadySince = row(last)[0];
  // The earliest time any later row asks for is the window before the row
  // at t - tau; a row followed by one at or before it is never the answer.
  const long earlier = rowAt(row(last)[0] - residenceTime());
  if (earlier >= 0) {
    const double oldest = row(earlier)[0] - residenceTime() + slack();
    std::size_t drop = 0;
    while (drop + 1 < size() && row(drop + 1)[0] <= oldest) ++drop;
    rows.erase(rows.begin(), rows.begin() + drop * width());
  }
  return c;
}

std::vector<double> ProductSeries::state() const {
  std::vector<double> s{holdup0, steadySince};
  s.insert(s.end(), rows.begin(), rows.end());
  return s;
}

bool ProductSeries::restore(const double *begin, std::size_t n) {
  if (n < 2 || (n - 2) % width() != 0) return false;
  holdup0 = begin[0];
  steadySince = begin[1];
  rows.assign(begin + 2, begin + n);
  return true;
}

PetscErrorCode ProductMonitor::setUp(const RunContext &run, const FractionState &, const std::string &directory) {
  PetscFunctionBeginUser;
  comm = run.db.layout().comm();
  dir = directory;
  fractions = &run.fractions;
  series = ProductSeries{};
  series.nf = run.fractions.size();
  series.rate = discharge.dischargeRate();
  series.tolerance = discharge.steadyTolerance();
  std::string header = "time_s";
  for (const char *what : {"discharged", "product", "holdup"})
    for (int i = 0; i < series.nf; ++i) header += std::string(",") + what + "_" + run.fractions.label(i);
  header += ",change,steady";
  csv = std::make_unique<CsvSeries>(comm, dir + "/product.csv", header);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ProductMonitor::currentRow(const MonitorContext &ctx, std::vector<double> *row) const {
  std::vector<double> holdup;
  PetscFunctionBeginUser;
  PetscCall(ctx.state.totals(&holdup)); // globally reduced: the same row on every rank
  const std::vector<double> out = discharge.discharged();
  row->assign(1, ctx.time);
  row->insert(row->end(), out.begin(), out.end());
  row->insert(row->end(), holdup.begin(), holdup.end());
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ProductMonitor::sample(const MonitorContext &ctx) {
  std::vector<double> values;
  PetscFunctionBeginUser;
  PetscCall(currentRow(ctx, &values));
  const int nf = series.nf;
  const double change = series.add(values);
  // The line: time, discharged, product shares, holdup shares, change, steady (change within the tolerance).
  std::vector<double> line(values.begin(), values.begin() + 1 + nf);
  const std::vector<double> p = series.product(series.size() - 1);
  line.insert(line.end(), p.begin(), p.end());
  double holdup = 0.0;
  for (int i = 0; i < nf; ++i) holdup += values[1 + nf + i];
  for (int i = 0; i < nf; ++i) line.push_back(values[1 + nf + i] / holdup);
  line.push_back(change);
  line.push_back(change <= series.tolerance ? 1.0 : 0.0);
  PetscCall(csv->add(numberRow(line)));
  if (ctx.last) {
    const double steady = series.steadyTime();
    if (std::isfinite(steady))
      PetscCall(PetscPrintf(comm, "  granulator: product steady from t = %.6g s (change per residence time %.4g s "
                                  "<= %g to the end; product.csv, steady_state.csv)\n",
                            steady, series.residenceTime(), series.tolerance));
    else
      PetscCall(PetscPrintf(comm, "  granulator: product not steady at the end (residence time %.4g s, last change "
                                  "%.4g > %g or undefined before two residence times)\n",
                            series.residenceTime(), change, series.tolerance));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ProductMonitor::steadyAt(const MonitorContext &ctx, bool *steady) const {
  PetscFunctionBeginUser;
  if (series.size() > 0 && series.row(series.size() - 1)[0] >= ctx.time - 1e-9 * series.residenceTime()) {
    *steady = std::isfinite(series.steadyTime()); // already sampled at this time (a restart's step)
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  std::vector<double> values;
  PetscCall(currentRow(ctx, &values));
  ProductSeries trial = series; // a few residence times of rows
  *steady = trial.add(values) <= trial.tolerance;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ProductMonitor::flush() {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCall(csv->flush());
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank != 0 || series.size() == 0) PetscFunctionReturn(PETSC_SUCCESS);
  std::string summary = "residence_time_s,tolerance,steady_time_s,end_time_s";
  for (int i = 0; i < series.nf; ++i) summary += ",product_" + fractions->label(i);
  const std::size_t last = series.size() - 1;
  std::vector<double> values{series.residenceTime(), series.tolerance, series.steadyTime(), series.row(last)[0]};
  const std::vector<double> p = series.product(last);
  values.insert(values.end(), p.begin(), p.end());
  PetscCall(writeFileAtomically(dir + "/steady_state.csv", summary + "\n" + numberRow(values) + "\n"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::vector<double> ProductMonitor::saveState() const {
  const std::vector<double> length = csv->state();
  std::vector<double> s{length.empty() ? -1.0 : length[0]};
  const std::vector<double> kept = series.state();
  s.insert(s.end(), kept.begin(), kept.end());
  return s;
}

PetscErrorCode ProductMonitor::restoreState(const std::vector<double> &state) {
  PetscFunctionBeginUser;
  PetscCheck(!state.empty() && series.restore(state.data() + 1, state.size() - 1), comm, PETSC_ERR_USER_INPUT,
             "The checkpoint's product.csv state does not fit this run's fractions");
  if (state[0] >= 0) PetscCall(csv->resume(state[0]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
