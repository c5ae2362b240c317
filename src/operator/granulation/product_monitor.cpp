#include "operator/granulation/product_monitor.hpp"
#include "base/petsc_compat.hpp"

#include <cmath>
#include <cstdio>

namespace rcfd {

double ProductSeries::residenceTime() const {
  if (size() == 0 || !(rate > 0)) return std::numeric_limits<double>::infinity();
  double holdup = 0.0;
  for (int i = 0; i < nf; ++i) holdup += row(0)[1 + nf + i];
  return holdup / rate;
}

bool ProductSeries::dischargedAt(double t, std::vector<double> *mass) const {
  const double slack = 1e-9 * residenceTime();
  const double *found = nullptr;
  for (std::size_t r = 0; r < size() && row(r)[0] <= t + slack; ++r) found = row(r);
  if (!found || t < -slack) return false;
  mass->assign(found + 1, found + 1 + nf);
  return true;
}

std::vector<double> ProductSeries::product(std::size_t r) const {
  std::vector<double> shares(nf, nan), before;
  const double tau = residenceTime();
  if (!std::isfinite(tau) || !dischargedAt(row(r)[0] - tau, &before)) return shares;
  double total = 0.0;
  for (int i = 0; i < nf; ++i) total += row(r)[1 + i] - before[i];
  if (!(total > 0)) return shares;
  for (int i = 0; i < nf; ++i) shares[i] = (row(r)[1 + i] - before[i]) / total;
  return shares;
}

double ProductSeries::change(std::size_t r) const {
  const double tau = residenceTime();
  if (!std::isfinite(tau)) return nan;
  const std::vector<double> now = product(r);
  std::size_t earlier = r; // the row at t - tau
  const double slack = 1e-9 * tau;
  while (earlier > 0 && row(earlier)[0] > row(r)[0] - tau + slack) --earlier;
  if (row(earlier)[0] > row(r)[0] - tau + slack) return nan;
  const std::vector<double> then = product(earlier);
  double sum = 0.0;
  for (int i = 0; i < nf; ++i) sum += std::fabs(now[i] - then[i]);
  return sum; // NaN when either window is undefined
}

double ProductSeries::steadyTime() const {
  double from = nan;
  for (std::size_t r = size(); r-- > 0;) {
    const double c = change(r);
    if (!(c <= tolerance)) break; // NaN too
    from = row(r)[0];
  }
  return from;
}

PetscErrorCode ProductMonitor::setUp(const RunContext &run, const FractionState &, const std::string &directory) {
  PetscFunctionBeginUser;
  comm = run.db.layout().comm();
  fractions = &run.fractions;
  dir = directory;
  series.nf = run.fractions.size();
  series.rate = discharge.dischargeRate();
  series.tolerance = discharge.steadyTolerance();
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ProductMonitor::sample(const MonitorContext &ctx) {
  std::vector<double> holdup;
  PetscFunctionBeginUser;
  PetscCall(ctx.state.totals(&holdup));
  const std::vector<double> out = discharge.discharged();
  series.rows.push_back(ctx.time);
  series.rows.insert(series.rows.end(), out.begin(), out.end());
  series.rows.insert(series.rows.end(), holdup.begin(), holdup.end());
  if (ctx.last) {
    const double steady = series.steadyTime();
    if (std::isfinite(steady))
      PetscCall(PetscPrintf(comm, "  granulator: product steady from t = %.6g s (change per residence time %.4g s "
                                  "<= %g to the end; product.csv, steady_state.csv)\n",
                            steady, series.residenceTime(), series.tolerance));
    else
      PetscCall(PetscPrintf(comm, "  granulator: product not steady at the end (residence time %.4g s, last change "
                                  "%.4g > %g or undefined before two residence times)\n",
                            series.residenceTime(), series.change(series.size() - 1), series.tolerance));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ProductMonitor::flush() {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank != 0 || series.size() == 0) PetscFunctionReturn(PETSC_SUCCESS);
  const int nf = series.nf;
  std::string header = "time_s";
  for (const char *what : {"discharged", "product", "holdup"})
    for (int i = 0; i < nf; ++i) header += std::string(",") + what + "_" + fractions->label(i);
  header += ",change,steady";
  const double steady = series.steadyTime();
  NumberRows table(1 + 3 * nf + 2);
  for (std::size_t r = 0; r < series.size(); ++r) {
    const double *row = series.row(r);
    std::vector<double> line(row, row + 1 + nf);
    const std::vector<double> p = series.product(r);
    line.insert(line.end(), p.begin(), p.end());
    double holdup = 0.0;
    for (int i = 0; i < nf; ++i) holdup += row[1 + nf + i];
    for (int i = 0; i < nf; ++i) line.push_back(row[1 + nf + i] / holdup);
    line.push_back(series.change(r));
    line.push_back(std::isfinite(steady) && row[0] >= steady ? 1.0 : 0.0);
    table.add(line);
  }
  PetscCall(writeFileAtomically(dir + "/product.csv", table.csv(header)));
  std::string summary = "residence_time_s,tolerance,steady_time_s";
  for (int i = 0; i < nf; ++i) summary += ",product_" + fractions->label(i);
  NumberRows last(3 + nf);
  std::vector<double> values{series.residenceTime(), series.tolerance, steady};
  const std::vector<double> p = series.product(series.size() - 1);
  values.insert(values.end(), p.begin(), p.end());
  last.add(values);
  PetscCall(writeFileAtomically(dir + "/steady_state.csv", last.csv(summary)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ProductMonitor::restoreState(const std::vector<double> &state) {
  PetscFunctionBeginUser;
  PetscCheck(state.size() % (1 + 2 * series.nf) == 0, comm, PETSC_ERR_USER_INPUT,
             "The checkpoint's product.csv state does not fit this run's fractions");
  series.rows = state;
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
