#include "observable/scalar_monitor.hpp"
#include "base/petsc_compat.hpp"

namespace rcfd {

PetscErrorCode ScalarMonitor::setUp(const RunContext &run, const FractionState &, const std::string &dir) {
  PetscFunctionBeginUser;
  comm = run.db.layout().comm();
  nf = run.fractions.size();
  std::string header = "time_s";
  for (const std::string &n : names) {
    for (int i = 0; i < nf; ++i) header += "," + n + "_" + run.fractions.label(i);
    header += "," + n + "_bed";
  }
  csv = std::make_unique<CsvSeries>(comm, dir + "/scalars.csv", header);
  PetscFunctionReturn(PETSC_SUCCESS);
}

// One pass over the cells that may hold mass (a cell without mass holds no
// amount) for the masses and the amounts, one reduction.
PetscErrorCode ScalarMonitor::sample(const MonitorContext &ctx) {
  PetscFunctionBeginUser;
  const int ns = static_cast<int>(names.size()), w = ns * nf;
  std::vector<double> sums(nf + w, 0.0); // the masses, then the amounts [scalar][fraction]
  PetscInt end;
  const PetscScalar *m, *a;
  PetscCall(ctx.state.occupiedEnd(&end));
  PetscCall(VecGetArrayRead(ctx.state.masses(), &m));
  PetscCall(VecGetArrayRead(ctx.state.amounts(), &a));
  for (PetscInt c = 0; c < end; ++c) {
    for (int i = 0; i < nf; ++i) sums[i] += m[c * nf + i];
    for (int k = 0; k < w; ++k) sums[nf + k] += a[c * w + k];
  }
  PetscCall(VecRestoreArrayRead(ctx.state.amounts(), &a));
  PetscCall(VecRestoreArrayRead(ctx.state.masses(), &m));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums.data(), nf + w, MPI_DOUBLE, MPI_SUM, comm));
  std::vector<double> row{ctx.time};
  double bed = 0.0;
  for (int i = 0; i < nf; ++i) bed += sums[i];
  for (int s = 0; s < ns; ++s) {
    double all = 0.0;
    for (int i = 0; i < nf; ++i) {
      const double amount = sums[nf + s * nf + i];
      all += amount;
      row.push_back(sums[i] > 0.0 ? amount / sums[i] : 0.0);
    }
    row.push_back(bed > 0.0 ? all / bed : 0.0);
  }
  PetscCall(csv->add(formatNumberRow(row)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ScalarMonitor::flush() { return csv->flush(); }

PetscErrorCode ScalarMonitor::restoreState(const std::vector<double> &state) {
  PetscFunctionBeginUser;
  if (state.empty()) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCheck(state.size() == 1, PETSC_COMM_SELF, PETSC_ERR_FILE_UNEXPECTED,
             "The checkpoint's scalars.csv state holds %zu numbers, expected 1 (the file's length)", state.size());
  PetscCall(csv->resume(state[0]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
