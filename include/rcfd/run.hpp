// A simulation run: database + fractions + operator pipeline + frame path,
// stepped in time; observables are monitors called by the time loop, and
// checkpoints let a run continue bit-identically.
//
// Life cycle (collective on the communicator):
//   Run run(comm, operators[, paths]);
//   run.setFromOptions();          // -db, -t_end, -pipeline, -path_type, ... (rcfd run -help)
//   run.setOutputDirectory(...);   // optional setters override the options
//   run.addMonitor(fn, every);     // optional: own observables
//   run.setUp();                   // loads the database, the path, the initial state
//   run.solve();
#pragma once

#include "rcfd/database.hpp"
#include "rcfd/fractions.hpp"
#include "rcfd/observables.hpp"
#include "rcfd/operator.hpp"
#include "rcfd/path.hpp"
#include "rcfd/switching.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace rcfd {

struct Registries; // rcfd/plugin.hpp

class Run {
public:
  /// With the operators, paths, switching rules and monitors of `registries`
  /// (e.g. built-ins plus plugins, rcfd/plugin.hpp); they must outlive the run.
  Run(MPI_Comm comm, const Registries &registries);
  /// The registry supplies the operators named by -pipeline; it must outlive
  /// the run.  Paths come from the built-in path kinds.
  Run(MPI_Comm comm, const OperatorRegistry &operators);
  /// With the path kinds of `paths` (-path_type); it must outlive the run.
  Run(MPI_Comm comm, const OperatorRegistry &operators, const PathRegistry &paths);
  ~Run();
  Run(const Run &) = delete;
  Run &operator=(const Run &) = delete;

  /// Default of -output_dir; call before setFromOptions (rcfd calibrate: rcfd-calibrate).
  void setDefaultOutputDirectory(const std::string &directory);
  /// Reads the run's options and lets the fractions, the operators, the path,
  /// the mass ledger and the built-in monitors read theirs.  Collective.
  /// Options: -db, -t_end, -output_dir, -pipeline, -init, -init_file, -fields,
  /// -fields_every, -checkpoint_every, -checkpoint_file, -restart,
  /// -solid_density, -quiet, -progress_interval, -run_view [viewer]; the answers'
  /// monitors (-profiles, -halves, -bottom_layer, ... src/observable/answers.hpp);
  /// -monitors NAME,... registered monitors, each sampled every -NAME_every
  /// steps (default 1) and viewed by -NAME_view.  -path_view and
  /// -db_switch_view view the path and the switching rule once set up.
  /// -live FILE, -live_end, -live_stop_file, -live_on_bad_line, -live_pace,
  /// -live_poll: follow measured conditions as a file grows; -forecast_every,
  /// -forecast_horizon, -forecast_members, -forecast_seed: forecasts from the
  /// state, forecast.csv (docs/live.md).
  PetscErrorCode setFromOptions();

  /// Setters applied after setFromOptions and before setUp; they override the options.
  void setOutputDirectory(const std::string &directory);
  void setQuiet(bool quiet);
  /// -quiet: no progress or messages on stdout.
  bool quiet() const;
  /// Keep the centre-of-gravity samples and the frames of every step in
  /// memory as well (history(), framesUsed()); off by default, since they
  /// grow with the run's length (the files cog.csv and path.txt hold them).
  void keepHistory(bool keep);
  void setWriteFields(bool write);
  /// Seed of a stochastic path (an ensemble's members use s, s+1, ...).
  /// Collective; an error for a path without a seed.
  PetscErrorCode setPathSeed(std::uint64_t seed);

  /// Adds an observable to the list the time loop calls: at the initial
  /// state (not after a restart), after every step whose number is a multiple
  /// of `every` (0: none), and after the last step.  Before solve().
  /// A checkpoint stores each monitor's Monitor::saveState() under its name
  /// and a restart hands it back (restoreState) before the monitor sees the
  /// steps from the restart on.  Collective when called after setUp().
  PetscErrorCode addMonitor(MonitorFn fn, long every, const std::string &name = "monitor");
  PetscErrorCode addMonitor(std::unique_ptr<Monitor> monitor, long every,
                            const std::string &name = "monitor");

  /// Use an already loaded database (e.g. shared by the members of an
  /// ensemble) instead of reading -db.
  void useDatabase(std::shared_ptr<Database> database);
  /// The switching rules -db_switch_type chooses from when -db names several
  /// databases (default: the built-in ones); it must outlive the run.  Before setFromOptions.
  void useSwitchRules(const SwitchRuleRegistry &rules);
  /// Whether -db names several databases (after setFromOptions): such a run
  /// reads and drops them as it switches, so it cannot share one loaded
  /// database (useDatabase) with other runs.
  bool switchesDatabases() const;
  /// Whether the run follows a live file (-live FILE, docs/live.md; after setFromOptions).
  bool followsLive() const;
  /// Loads the database (unless one was given), sets up the operators, the
  /// path, the monitors and the initial state (or the state of -restart
  /// FILE); views the run given -run_view.  Collective.  A restart refuses a
  /// checkpoint made with other physics (database, diameters, mass shares,
  /// solid density, pipeline, path, an operator's options) with a sentence
  /// naming it, and cuts the time series in the output directory back to the
  /// checkpoint's step (docs/method.md, "Checkpoints and restarts").
  PetscErrorCode setUp();
  /// Steps to the end time, calling the monitors and writing checkpoints (collective).
  PetscErrorCode solve();
  PetscErrorCode view(PetscViewer viewer) const;

  const Database &database() const;
  std::shared_ptr<Database> sharedDatabase() const;
  const FractionSet &fractions() const;
  /// What operators and monitors read (database, fractions, solid density), once set up.
  RunContext context() const;
  const FractionState &state() const;
  FractionState &state();
  Pipeline &pipeline();
  /// The frame path (after setFromOptions).
  const FramePath &path() const;
  /// Samples of the built-in centre-of-gravity monitor (every -monitor_every
  /// steps) since the start or the restart; empty unless keepHistory(true).
  const std::vector<BedSample> &history() const;
  /// Frame used by each step since the start or the restart; empty unless keepHistory(true).
  const std::vector<int> &framesUsed() const;
  /// The scalars' sources so far (docs/scalars.md, "Sources"): liquid sprayed
  /// [kg], liquid that missed an empty spray zone [kg], liquid dried [kg], heat
  /// from the gas into the solid [J], heat of evaporation taken [J]; the same on
  /// every rank.
  std::vector<double> scalarSourceAccount() const;
  long numSteps() const;
  const std::string &outputDirectory() const;

private:
  struct Impl; // src/run/run_impl.hpp
  std::unique_ptr<Impl> impl;
};

} // namespace rcfd
