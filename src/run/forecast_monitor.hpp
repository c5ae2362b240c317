// Forecasts (-forecast_every, docs/live.md): every so often the run forks its
// state into members that each follow a stitched path of their own for
// -forecast_horizon seconds, holding the conditions of the moment (or
// following a what-if schedule, -forecast_schedule), and writes
// OUTPUT_DIR/forecast.csv: the members' mean and spread of the answers users
// act on, with a discharge the product's mass and size distribution; with
// scalars (-scalars) the members carry them and their sources, and the file
// gains the bottom layer's moisture, the wet-bottom warning's time and the
// product's scalar values.  A
// monitor of the run's list: it reads the live state and the operators' saved
// state and changes neither (the members have their own operators, made from
// the same options, and their own copies of the state).
#pragma once

#include "rcfd/observables.hpp"
#include "rcfd/operator.hpp"
#include "rcfd/path.hpp"

#include "database/fluidization_model.hpp"
#include "run/live_input.hpp"
#include "rcfd/carry.hpp"
#include "state/layer_masses.hpp"
#include "state/scalars.hpp"
#include "switching/database_switcher.hpp"

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace rcfd {

class ForecastMonitor final : public Monitor {
public:
  /// `operators` and `paths` make the members' operators (named by `pipeline`) and
  /// paths; `live` is the run's pipeline, whose saved state and rates the members
  /// start from; `fluidization` the bottom layer's u_mf correlation and gas.  All
  /// must outlive the monitor.  `switcher`: the run's on a database set (null: one database, and the
  /// members' operators are set up once; else for each member, on the database in use, and with a
  /// rule that chooses by u_sup each member switches by its own u_sup, docs/live.md).
  /// `scalars`: the run's (-scalars), whose conditions of the moment (spray rate, gas
  /// temperature, u_sup) the members hold; the members carry their own, made from the same options.
  ForecastMonitor(const OperatorRegistry &operators, const PathRegistry &paths, const Pipeline &live,
                  std::vector<std::string> pipeline, const FluidizationModel &fluidization, DatabaseSwitcher *switcher,
                  const ScalarSet &scalars);
  std::string type() const override { return "forecast"; }
  /// -forecast_every [s] (0: none), -forecast_horizon [s], -forecast_members,
  /// -forecast_seed, -forecast_digits (10), -forecast_schedule FILE (a what-if: the live file's format, times
  /// from each forecast's start; read at setUp); the members' stitching reads
  /// -forecast_path_* (docs/paths.md).
  PetscErrorCode setFromOptions(MPI_Comm comm) override;
  bool enabled() const { return every > 0; }
  /// Before setUp: the wet-bottom warning (-moisture_warning, Answers) the members look for; 0: none.
  void setMoistureWarning(double threshold, double umfShare) { wetThreshold = threshold, wetShare = umfShare; }
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
  /// The column of forecast.csv named `name` in latestRow(), -1 when the file has none.
  int column(const std::string &name) const;
  /// The wet-bottom warning's threshold [kg/kg] (0: not looked for).
  double moistureWarning() const { return wetThreshold; }
  double moistureWarningUmfShare() const { return wetShare; }
  /// With scalars and a discharge: the scalars whose product values forecast.csv holds.
  const std::vector<std::string> &productScalars() const { return scalarLabels; }

private:
  /// What one member forecasts (NaN: not known, or not within the horizon).
  struct Outcome {
    double deltaZ, d32, umfUsup, warning; // at the horizon; the time until u_mf >= u_sup
    std::vector<double> product;          // with a discharge: mass, each fraction's share, each scalar's value
    double wetBottom, wetWarning;         // with moisture: the bottom layer's at the horizon, the wet warning's time
  };
  /// One member from the state of `ctx`: its Delta z, bottom d32 and u_mf/u_sup at
  /// the horizon, the time until u_mf >= u_sup (NaN: not within the horizon), with a
  /// discharge the product over the horizon (its mass, each fraction's share and each
  /// scalar's value) and with moisture the bottom layer's and the wet-bottom warning's time.
  PetscErrorCode member(const MonitorContext &ctx, int m, Outcome *out);
  /// The what-if schedule's conditions at `t` [s] after the forecast's start onto the member's
  /// operators, gas (its u_sup) and scalars' sources; what it has no column for stays as held.
  void followSchedule(double t, const Pipeline &ops, OperatingConditions *gas) const;
  /// Collective.  The members' scalars, set up on the database in use.
  PetscErrorCode setUpScalars(const RunContext &run);
  /// Collective.  A member's switch to `choice` before a step that starts on the path's frame
  /// `pathFrame`, as the run's (Run::Impl::switchTo): its operators set up on the database (kept
  /// state restored), its state carried onto it by the composition remap; `*db` the database now.
  PetscErrorCode switchMember(const SwitchDecision &choice, int pathFrame, const RunContext &run,
                              const OperatingConditions &gas, Pipeline &ops, FractionState &state,
                              std::shared_ptr<Database> *db);
  /// Collective.  Reads -forecast_schedule and refuses a column nothing in the members follows.
  PetscErrorCode readSchedule(const RunContext &run);

  const OperatorRegistry &operators;
  const PathRegistry &paths;
  const Pipeline &live;
  std::vector<std::string> names;
  const FluidizationModel &fluidization;
  DatabaseSwitcher *switcher; // the run's, on a database set
  bool fixedDatabase;
  std::unique_ptr<CarryOperator> remap;                       // a member's switch: the state onto the new database
  std::map<std::string, std::shared_ptr<Database>> loaded;    // the databases members switched to, this forecast
  const ScalarSet &liveScalars;
  std::unique_ptr<ScalarSet> memberScalars; // the members' (-scalars), their sources set to the run's conditions
  int moisture = -1;                        // the scalar named moisture, -1: none
  double wetThreshold = 0.0, wetShare = 0.8; // the wet-bottom warning (-moisture_warning)
  std::vector<std::string> scalarLabels;    // the product's scalars (with a discharge)
  std::vector<std::string> columns;         // forecast.csv's header
  std::unique_ptr<Pipeline> memberOps; // the members' operators; each member restores the run's state into them
  MPI_Comm comm = MPI_COMM_NULL;
  double every = 0.0, horizon = 10.0;
  PetscInt members = 4, seed = 1, digits = 10;
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
