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

PetscErrorCode ScalarMonitor::sample(const MonitorContext &ctx) {
  PetscFunctionBeginUser;
  const int ns = static_cast<int>(names.size());
  std::vector<double> sums(nf); // the masses, then the amounts [scalar][fraction]
  PetscCall(ctx.state.localTotals(&sums));
  std::vector<double> amounts;
  PetscCall(ctx.state.amountTotals(&amounts)); // reduced over the ranks
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums.data(), nf, MPI_DOUBLE, MPI_SUM, comm));
  std::vector<double> row{ctx.time};
  double bed = 0.0;
  for (int i = 0; i < nf; ++i) bed += sums[i];
  for (int s = 0; s < ns; ++s) {
    double all = 0.0;
    for (int i = 0; i < nf; ++i) {
      const double a = amounts[s * nf + i];
      all += a;
      row.push_back(sums[i] > 0.0 ? a / sums[i] : 0.0);
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
