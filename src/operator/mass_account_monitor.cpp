#include "operator/mass_account_monitor.hpp"
#include "base/petsc_compat.hpp"
#include "base/number_rows.hpp"

namespace rcfd {

PetscErrorCode MassAccountMonitor::setUp(const RunContext &run, const FractionState &, const std::string &dir) {
  PetscFunctionBeginUser;
  comm = run.db.layout().comm();
  nf = run.fractions.size();
  reporting.clear();
  for (const auto &op : pipeline.operators())
    if (op->addedMass()) reporting.push_back(op.get());
  std::string header = "time_s";
  const auto columns = [&](const std::string &what) {
    for (int i = 0; i < nf; ++i) header += "," + what + "_" + run.fractions.label(i);
  };
  columns("holdup");
  for (const Operator *op : reporting) columns(op->type());
  columns("residual");
  csv = std::make_unique<CsvSeries>(comm, dir + "/mass_account.csv", header);
  initial.clear();
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode MassAccountMonitor::sample(const MonitorContext &ctx) {
  std::vector<double> holdup;
  PetscFunctionBeginUser;
  PetscCall(ctx.state.totals(&holdup));
  if (initial.empty()) initial = holdup; // the first sample is the initial state
  std::vector<double> row{ctx.time}, residual(nf);
  row.insert(row.end(), holdup.begin(), holdup.end());
  for (int i = 0; i < nf; ++i) residual[i] = holdup[i] - initial[i];
  for (const Operator *op : reporting) {
    const std::vector<double> &added = *op->addedMass();
    row.insert(row.end(), added.begin(), added.end());
    for (int i = 0; i < nf; ++i) residual[i] -= added[i];
  }
  row.insert(row.end(), residual.begin(), residual.end());
  PetscCall(csv->add(numberRow(row)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode MassAccountMonitor::flush() { return csv->flush(); }

std::vector<double> MassAccountMonitor::saveState() const {
  std::vector<double> state = initial;
  const std::vector<double> length = csv->state();
  state.insert(state.end(), length.begin(), length.end());
  return state;
}

PetscErrorCode MassAccountMonitor::restoreState(const std::vector<double> &state) {
  PetscFunctionBeginUser;
  PetscCheck(state.size() == static_cast<std::size_t>(nf) + 1, comm, PETSC_ERR_USER_INPUT,
             "The checkpoint's mass_account.csv state holds %zu numbers, this run needs %d (other fractions?)",
             state.size(), nf + 1);
  initial.assign(state.begin(), state.begin() + nf);
  PetscCall(csv->resume(state[nf]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
