// scalars.csv: each size class's mean value of every scalar the run carries
// (docs/scalars.md), the amount-weighted mean sum_c a_c / sum_c m_c over the
// bed, and each scalar's mean over all classes.
#pragma once

#include "rcfd/observables.hpp"

#include <memory>
#include <string>
#include <vector>

namespace rcfd {

class ScalarMonitor final : public Monitor {
public:
  explicit ScalarMonitor(std::vector<std::string> names) : names(std::move(names)) {}
  std::string type() const override { return "scalars"; }
  PetscErrorCode setUp(const RunContext &run, const FractionState &, const std::string &dir) override;
  PetscErrorCode sample(const MonitorContext &ctx) override;
  PetscErrorCode flush() override;
  /// State: the length of scalars.csv.
  std::vector<double> saveState() const override { return csv->state(); }
  PetscErrorCode restoreState(const std::vector<double> &state) override;

private:
  std::vector<std::string> names;
  MPI_Comm comm = MPI_COMM_NULL;
  int nf = 0;
  std::unique_ptr<CsvSeries> csv;
};

} // namespace rcfd
