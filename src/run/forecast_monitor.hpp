// Forecasts (-forecast_every, docs/live.md): every so often the run forks its
// state into members that each follow a stitched path of their own for
// -forecast_horizon seconds, holding the conditions of the moment (or
// following a what-if schedule, -forecast_schedule), and writes
// OUTPUT_DIR/forecast.csv: the members' mean and spread of the answers users
// act on, with a discharge the product's mass and size distribution.  A
// monitor of the run's list: it reads the live state and the operators' saved
// state and changes neither (the members have their own operators, made from
// the same options, and their own copies of the state).
#pragma once

#include "rcfd/observables.hpp"
#include "rcfd/operator.hpp"
#include "rcfd/path.hpp"

#include "database/fluidization_model.hpp"
#include "run/live_input.hpp"
#include "state/layer_masses.hpp"

#include <memory>
#include <string>
#include <vector>

namespace rcfd {

class ForecastMonitor final : public Monitor {
public:
  /// `operators` and `paths` make the members' operators (named by `pipeline`) and
  /// paths; `live` is the run's pipeline, whose saved state and rates the members
  /// start from; `fluidization` the bottom layer's u_mf correlation and gas.  All
  /// must outlive the monitor.  `fixedDatabase`: the run stays on one database, so the
  /// members' operators are set up once (else for each member, on the database in use).
  ForecastMonitor(const OperatorRegistry &operators, const PathRegistry &paths, const Pipeline &live,
                  std::vector<std::string> pipeline, const FluidizationModel &fluidization, bool fixedDatabase);
  std::string type() const override { return "forecast"; }
  /// -forecast_every [s] (0: none), -forecast_horizon [s], -forecast_members,
  /// -forecast_seed, -forecast_schedule FILE (a what-if: the live file's format, times
  /// from each forecast's start; read at setUp); the members' stitching reads
  /// -forecast_path_* (docs/paths.md).
  PetscErrorCode setFromOptions(MPI_Comm comm) override;
  bool enabled() const { return every > 0; }
  /// Steps between forecasts for the database's dt_rec.
  long everySteps(double dt) const;
  PetscErrorCode setUp(const RunContext &run, const FractionState &state, const std::string &dir) override;
  PetscErrorCode sample(const MonitorContext &ctx) override;
  PetscErrorCode flush() override { return csv->flush(); }
  std::vector<double> saveState() const override;
  PetscErrorCode restoreState(const std::vector<double> &state) override;
  PetscErrorCode view(PetscViewer viewer) const override;
  /// The latest forecast's row of forecast.csv (empty before the first): the status page's.
  const std::vector<double> &latestRow() const { return latest; }
  /// With a discharge: the fractions' labels of the product's columns, which follow the first
  /// 12 of a row (product mass mean and spread, then each fraction's share mean and spread); else empty.
  const std::vector<std::string> &productLabels() const { return labels; }
  /// -forecast_schedule's file, or "" when the members hold the latest conditions.
  const std::string &whatIf() const { return scheduleFile; }

private:
  /// One member from the state of `ctx`: its Delta z, bottom d32 and u_mf/u_sup at
  /// the horizon, the time until u_mf >= u_sup (NaN: not within the horizon) and, with a
  /// discharge, the product over the horizon: its mass and each fraction's share.
  PetscErrorCode member(const MonitorContext &ctx, int m, std::vector<double> *out);
  /// The what-if schedule's conditions at `t` [s] after the forecast's start onto the member's
  /// operators and gas (its u_sup); what it has no column for stays as held.
  void followSchedule(double t, const Pipeline &ops, OperatingConditions *gas) const;
  /// Collective.  Reads -forecast_schedule and refuses a column nothing in the members follows.
  PetscErrorCode readSchedule(const RunContext &run);

  const OperatorRegistry &operators;
  const PathRegistry &paths;
  const Pipeline &live;
  std::vector<std::string> names;
  const FluidizationModel &fluidization;
  bool fixedDatabase;
  std::unique_ptr<Pipeline> memberOps; // the members' operators; each member restores the run's state into them
  MPI_Comm comm = MPI_COMM_NULL;
  double every = 0.0, horizon = 10.0;
  PetscInt members = 4, seed = 1;
  std::string scheduleFile; // -forecast_schedule
  LiveInput schedule;       // its rows, read once
  std::vector<std::string> labels; // the product's fractions (with a discharge)
  long issued = 0; // forecasts made: the members' seeds go on from here after a restart
  double gravity = 9.81;
  HorizontalLayers layers;
  CentreOfGravity cog;
  std::vector<std::unique_ptr<FramePath>> memberPaths; // each member's, continued from forecast to forecast
  std::unique_ptr<CsvSeries> csv;
  std::vector<double> latest;
};

} // namespace rcfd
