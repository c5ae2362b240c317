#include "observable/scalar_mixing_monitor.hpp"
#include "base/petsc_compat.hpp"

#include <cmath>
#include <cstdio>
#include <limits>

namespace rcfd {

PetscErrorCode ScalarMixingMonitor::setUp(const RunContext &run, const FractionState &, const std::string &dir) {
  PetscFunctionBeginUser;
  comm = run.db.layout().comm();
  nf = run.fractions.size();
  std::string header = "time_s";
  for (const std::string &n : names) header += ",spread_" + n;
  csv = std::make_unique<CsvSeries>(comm, dir + "/scalar_mixing.csv", header);
  contrast.assign(names.size(), std::numeric_limits<double>::quiet_NaN());
  since.assign(names.size(), std::numeric_limits<double>::quiet_NaN());
  PetscFunctionReturn(PETSC_SUCCESS);
}

// Two reductions: the bed's totals (and the occupied cells), then the largest departure.
PetscErrorCode ScalarMixingMonitor::sample(const MonitorContext &ctx) {
  PetscFunctionBeginUser;
  const int ns = static_cast<int>(names.size()), w = ns * nf;
  PetscInt end;
  const PetscScalar *m, *a;
  PetscCall(ctx.state.occupiedEnd(&end));
  PetscCall(VecGetArrayRead(ctx.state.masses(), &m));
  PetscCall(VecGetArrayRead(ctx.state.amounts(), &a));
  std::vector<double> cellMass(end, 0.0), sums(2 + ns, 0.0); // solid, occupied cells, amounts per scalar
  for (PetscInt c = 0; c < end; ++c) {
    for (int i = 0; i < nf; ++i) cellMass[c] += m[c * nf + i];
    sums[0] += cellMass[c];
    sums[1] += cellMass[c] > 0.0;
    for (int k = 0; k < w; ++k) sums[2 + k / nf] += a[c * w + k];
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums.data(), 2 + ns, MPI_DOUBLE, MPI_SUM, comm));
  const double least = sums[1] > 0.0 ? 1e-3 * sums[0] / sums[1] : 0.0;
  std::vector<double> departure(ns, 0.0);
  for (PetscInt c = 0; c < end; ++c) {
    if (!(cellMass[c] >= least) || !(cellMass[c] > 0.0)) continue;
    for (int s = 0; s < ns; ++s) {
      double amount = 0.0;
      for (int i = 0; i < nf; ++i) amount += a[c * w + s * nf + i];
      departure[s] = std::fmax(departure[s], std::fabs(amount / cellMass[c] - sums[2 + s] / sums[0]));
    }
  }
  PetscCall(VecRestoreArrayRead(ctx.state.amounts(), &a));
  PetscCall(VecRestoreArrayRead(ctx.state.masses(), &m));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, departure.data(), ns, MPI_DOUBLE, MPI_MAX, comm));
  std::vector<double> row{ctx.time};
  for (int s = 0; s < ns; ++s) {
    if (std::isnan(contrast[s])) contrast[s] = departure[s]; // the first sample: the start
    const double spread = contrast[s] > 0.0 ? departure[s] / contrast[s] : 0.0;
    row.push_back(spread);
    if (!(spread <= tolerance)) since[s] = std::numeric_limits<double>::quiet_NaN();
    else if (std::isnan(since[s])) since[s] = ctx.time;
  }
  PetscCall(csv->add(formatNumberRow(row)));
  if (ctx.last)
    for (int s = 0; s < ns; ++s) {
      if (std::isfinite(since[s]))
        PetscCall(PetscPrintf(comm, "  %s: mixed within %.3g %% of its starting contrast from t = %.6g s "
                                    "(scalar_mixing.csv)\n", names[s].c_str(), 100 * tolerance, since[s]));
      else
        PetscCall(PetscPrintf(comm, "  %s: not mixed within %.3g %% at the end (spread %.4g of its starting "
                                    "contrast; scalar_mixing.csv)\n", names[s].c_str(), 100 * tolerance, row[1 + s]));
    }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ScalarMixingMonitor::flush() { return csv->flush(); }

std::vector<double> ScalarMixingMonitor::saveState() const {
  std::vector<double> state = contrast;
  state.insert(state.end(), since.begin(), since.end());
  const std::vector<double> length = csv->state();
  state.push_back(length.empty() ? -1.0 : length[0]);
  return state;
}

PetscErrorCode ScalarMixingMonitor::restoreState(const std::vector<double> &state) {
  PetscFunctionBeginUser;
  const std::size_t ns = names.size();
  PetscCheck(state.size() == 2 * ns + 1, PETSC_COMM_SELF, PETSC_ERR_FILE_UNEXPECTED,
             "The checkpoint's scalar_mixing.csv state holds %zu numbers, expected %zu", state.size(), 2 * ns + 1);
  contrast.assign(state.begin(), state.begin() + ns);
  since.assign(state.begin() + ns, state.begin() + 2 * ns);
  if (state[2 * ns] >= 0) PetscCall(csv->resume(state[2 * ns]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
