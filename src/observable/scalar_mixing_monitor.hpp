// scalar_mixing.csv: how far each scalar is from mixed over the bed, and when
// it mixed (docs/scalars.md, "Answers"): a hot batch or a tracer added in one
// zone, and the time until every cell's value is within a tolerance (5 %) of
// the bed's mean, relative to the contrast at the start.
#pragma once

#include "rcfd/observables.hpp"

#include <memory>
#include <string>
#include <vector>

namespace rcfd {

/// The spread of scalar s at time t is
///   S(t) = max_c |phi_c(t) - phi_bed(t)| / max_c |phi_c(0) - phi_bed(0)|,
/// phi_c = sum_i a_i,c / sum_i m_i,c the value of cell c over all classes and
/// phi_bed the bed's mean, over the cells holding at least 1e-3 of the mean
/// occupied cell's solid (the freeboard's traces left out).  The scalar is
/// mixed from the first sample of the last unbroken run of samples with
/// S <= tolerance up to the end (as the granulator's steady state).
class ScalarMixingMonitor final : public Monitor {
public:
  ScalarMixingMonitor(std::vector<std::string> names, double tolerance)
      : names(std::move(names)), tolerance(tolerance) {}
  std::string type() const override { return "scalar_mixing"; }
  PetscErrorCode setUp(const RunContext &run, const FractionState &, const std::string &dir) override;
  PetscErrorCode sample(const MonitorContext &ctx) override;
  PetscErrorCode flush() override;
  /// State: the contrast at the start and the mixed time of each scalar, the file's length.
  std::vector<double> saveState() const override;
  PetscErrorCode restoreState(const std::vector<double> &state) override;
  /// Mixed time of scalar s [s] (NaN: not mixed at the last sample).
  double mixedSince(int s) const { return since[s]; }

private:
  std::vector<std::string> names;
  double tolerance;
  MPI_Comm comm = MPI_COMM_NULL;
  int nf = 0;
  std::vector<double> contrast, since; // per scalar
  std::unique_ptr<CsvSeries> csv;
};

} // namespace rcfd
