// The run's built-in monitor: centres of gravity, masses per fraction and the
// bulk mismatch over time, appended to OUTPUT_DIR/cog.csv as they are made
// (and kept in memory only when asked: Run::keepHistory).
#pragma once

#include "rcfd/observables.hpp"

#include <limits>
#include <memory>

namespace rcfd {

class CogMonitor : public Monitor {
public:
  /// Reads -monitor_every (steps between rows) and -monitor_digits.
  PetscErrorCode setFromOptions(MPI_Comm comm);
  long every() const { return static_cast<long>(monitorEvery); }
  PetscErrorCode setUp(const RunContext &run, const FractionState &state,
                       const std::string &outputDirectory) override;
  PetscErrorCode sample(const MonitorContext &ctx) override;
  PetscErrorCode flush() override { return csv->flush(); }
  /// State: the length of cog.csv (CsvSeries::mark), then the latest
  /// sample's delta_z and z_cog_bed (the signals).
  std::vector<double> saveState() const override;
  PetscErrorCode restoreState(const std::vector<double> &state) override;
  /// delta_z [m] and z_cog_bed [m] of the latest sample.
  std::vector<std::string> signalNames() const override { return {"delta_z", "z_cog_bed"}; }
  double signal(const std::string &name) const override;

  /// Keep every sample in memory as well (samples()); off by default, since
  /// the samples grow with the run's length.
  void keepSamples(bool keep) { keep_ = keep; }
  /// The samples since the start, or since the restart, when kept.
  const std::vector<BedSample> &samples() const { return history; }

private:
  std::string header(const FractionSet &fractions) const;
  CentreOfGravity cog;
  std::unique_ptr<CsvSeries> csv;
  std::vector<BedSample> history;
  double latestDeltaZ = std::numeric_limits<double>::quiet_NaN(); // the signals
  double latestZCogBed = std::numeric_limits<double>::quiet_NaN();
  bool keep_ = false;
  PetscInt monitorEvery = 1, csvDigits = 10;
};

/// Fields for ParaView (FieldWriter) as a monitor.
class FieldMonitor : public Monitor {
public:
  /// With the state's scalars' values too (docs/scalars.md).
  PetscErrorCode setUp(const RunContext &run, const FractionState &state,
                       const std::string &outputDirectory) override;
  PetscErrorCode sample(const MonitorContext &ctx) override {
    return writer.write(ctx.time, ctx.run.db.alphaS(ctx.frame), ctx.state.masses(), // the database in use
                        ctx.state.numScalars() > 0 ? ctx.state.amounts() : nullptr);
  }
  /// The times written so far: a restart continues the series.
  std::vector<double> saveState() const override { return writer.outputTimes(); }
  PetscErrorCode restoreState(const std::vector<double> &times) override {
    return writer.continueSeries(times);
  }

private:
  FieldWriter writer;
};

} // namespace rcfd
