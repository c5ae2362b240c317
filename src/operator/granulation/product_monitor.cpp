#include "operator/granulation/product_monitor.hpp"
#include "base/petsc_compat.hpp"
#include "base/number_rows.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

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
  // The scalars (docs/scalars.md): the product's value of each, over the last interval.
  scalarNames = run.scalarNames ? *run.scalarNames : std::vector<std::string>{};
  for (const std::string &name : scalarNames) header += ",product_" + name;
  lastOut.assign(scalarNames.empty() ? 0 : 1 + scalarNames.size(), 0.0);
  values.assign(scalarNames.size(), ProductSeries::nan);
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
  const std::vector<double> v = productValues();
  line.insert(line.end(), v.begin(), v.end());
  PetscCall(csv->add(numberRow(line)));
  if (ctx.last && !v.empty()) {
    std::string text;
    char item[96];
    for (std::size_t k = 0; k < v.size(); ++k) {
      std::snprintf(item, sizeof item, "%s%s %.6g", k ? ", " : "", scalarNames[k].c_str(), v[k]);
      text += item;
    }
    PetscCall(PetscPrintf(comm, "  granulator: product's values over the last %g s: %s (product.csv)\n",
                          discharge.sampleInterval(), text.c_str()));
  }
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

std::vector<double> ProductMonitor::productValues() {
  const int ns = static_cast<int>(scalarNames.size());
  if (ns == 0) return {};
  const std::vector<double> mass = discharge.discharged(), amount = discharge.dischargedAmounts();
  const int nf = static_cast<int>(mass.size());
  std::vector<double> out(1 + ns, 0.0);
  for (int i = 0; i < nf; ++i) out[0] += mass[i];
  for (int s = 0; s < ns; ++s)
    for (int i = 0; i < nf; ++i) out[1 + s] += amount[s * nf + i];
  const double left = out[0] - lastOut[0];
  for (int s = 0; s < ns; ++s) values[s] = left > 0 ? (out[1 + s] - lastOut[1 + s]) / left : ProductSeries::nan;
  lastOut = out;
  return values;
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
  const std::vector<double> p = series.product(last);
  std::vector<double> row{series.residenceTime(), series.tolerance, series.steadyTime(), series.row(last)[0]};
  row.insert(row.end(), p.begin(), p.end());
  for (std::size_t k = 0; k < scalarNames.size(); ++k) summary += ",product_" + scalarNames[k];
  row.insert(row.end(), values.begin(), values.end());
  PetscCall(writeFileAtomically(dir + "/steady_state.csv", summary + "\n" + numberRow(row) + "\n"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::vector<double> ProductMonitor::saveState() const {
  const std::vector<double> length = csv->state();
  std::vector<double> s{length.empty() ? -1.0 : length[0]};
  const std::vector<double> kept = series.state();
  s.insert(s.end(), kept.begin(), kept.end());
  s.insert(s.end(), lastOut.begin(), lastOut.end()); // with scalars: the last row's totals, then their values
  s.insert(s.end(), values.begin(), values.end());
  return s;
}

PetscErrorCode ProductMonitor::restoreState(const std::vector<double> &state) {
  PetscFunctionBeginUser;
  const std::size_t extra = lastOut.size() + values.size();
  PetscCheck(state.size() > extra && series.restore(state.data() + 1, state.size() - 1 - extra), comm,
             PETSC_ERR_USER_INPUT,
             "The checkpoint's product.csv state does not fit this run's fractions");
  const std::size_t at = state.size() - extra;
  std::copy(state.begin() + at, state.begin() + at + lastOut.size(), lastOut.begin());
  std::copy(state.begin() + at + lastOut.size(), state.end(), values.begin());
  if (state[0] >= 0) PetscCall(csv->resume(state[0]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
