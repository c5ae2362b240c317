#include "observable/mass_account_monitor.hpp"
#include "base/petsc_compat.hpp"

namespace rcfd {

PetscErrorCode MassAccountMonitor::setUp(const RunContext &run, const FractionState &, const std::string &dir) {
  PetscFunctionBeginUser;
  comm = run.db.layout().comm();
  nf = run.fractions.size();
  path = dir + "/mass_account.csv";
  reporting.clear();
  for (const auto &op : pipeline.operators())
    if (op->addedMass()) reporting.push_back(op.get());
  header = "time_s";
  const auto columns = [&](const std::string &what) {
    for (int i = 0; i < nf; ++i) header += "," + what + "_" + run.fractions.label(i);
  };
  columns("holdup");
  for (const Operator *op : reporting) columns(op->type());
  columns("residual");
  rows = NumberRows(1 + nf * (2 + static_cast<int>(reporting.size())));
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
  rows.add(row);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode MassAccountMonitor::flush() {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) PetscCall(writeFileAtomically(path, rows.csv(header)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::vector<double> MassAccountMonitor::saveState() const {
  std::vector<double> state = initial;
  state.insert(state.end(), rows.flat().begin(), rows.flat().end());
  return state;
}

PetscErrorCode MassAccountMonitor::restoreState(const std::vector<double> &state) {
  PetscFunctionBeginUser;
  PetscCheck(state.size() >= static_cast<std::size_t>(nf) &&
                 rows.restore(state.data() + nf, state.size() - nf),
             comm, PETSC_ERR_USER_INPUT,
             "The checkpoint's mass_account.csv state does not fit this run (other operators or fractions?)");
  initial.assign(state.begin(), state.begin() + nf);
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
