// mass_account.csv: every fraction's balance when operators add or remove
// mass on purpose (feed, discharge, growth between classes).
#pragma once

#include "rcfd/observables.hpp"
#include "rcfd/operator.hpp"

#include "observable/answers.hpp"
#include <memory>

namespace rcfd {

/// Per fraction i and row: the holdup H_i (mass in the bed), what each
/// operator that changes mass has added since the start, A_op,i (Operator::
/// addedMass; removed mass negative), and the residual
///   r_i = H_i - H_i(0) - sum_op A_op,i,
/// which is round-off when every operator tells the truth (the run's mass
/// ledger refuses more than -mass_leak_tolerance every -mass_check_every steps).
/// Columns: time_s, holdup_<f>..., <op>_<f>... per operator, residual_<f>...
/// Rows are appended to the file as they are made (CsvSeries).
class MassAccountMonitor final : public Monitor {
public:
  explicit MassAccountMonitor(const Pipeline &pipeline) : pipeline(pipeline) {}
  PetscErrorCode setUp(const RunContext &run, const FractionState &, const std::string &dir) override;
  PetscErrorCode sample(const MonitorContext &ctx) override;
  PetscErrorCode flush() override;
  /// {initial holdup..., length of mass_account.csv} (the length missing before it is written)
  std::vector<double> saveState() const override;
  PetscErrorCode restoreState(const std::vector<double> &state) override;

private:
  const Pipeline &pipeline;
  std::vector<const Operator *> reporting; // operators with addedMass()
  MPI_Comm comm = MPI_COMM_NULL;
  int nf = 0;
  std::vector<double> initial;
  std::unique_ptr<CsvSeries> csv;
};

} // namespace rcfd
