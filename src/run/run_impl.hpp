// The state of a Run, private to the library.
#pragma once

#include "rcfd/mass_ledger.hpp"
#include "rcfd/run.hpp"

#include "observable/answers.hpp"
#include "observable/cog_monitor.hpp"
#include "operator/mass_account_monitor.hpp"
#include "run/jumps_file.hpp"
#include "run/forecast_monitor.hpp"
#include "run/live_input.hpp"
#include "run/status_monitor.hpp"
#include "state/scalars.hpp"
#include "switching/database_switcher.hpp"

#include "rcfd/carry.hpp"

namespace rcfd {

struct Run::Impl {
  Impl(MPI_Comm comm, const OperatorRegistry &registry, const PathRegistry &paths)
      : comm(comm), registry(registry), paths(paths) {}
  Impl(MPI_Comm comm, const OperatorRegistry &registry)
      : comm(comm), registry(registry), builtinPaths(PathRegistry::withBuiltins()),
        paths(builtinPaths) {}

  /// One entry of the monitor list.
  struct Entry {
    std::unique_ptr<Monitor> monitor;
    long every;
    std::string name;
    double seconds = 0.0; // wall time spent in the monitor while stepping
  };

  PetscErrorCode callMonitors(long step, double time, int frame, bool last);
  PetscErrorCode flushMonitors();
  PetscErrorCode steadyAt(long step, double time, int frame, bool anyDue, bool *steady); // -stop_at_steady
  PetscErrorCode march();                               // solve()'s time loop
  /// A jump's step: the operators, and the bed just before and after the carry.
  PetscErrorCode applyAcrossJump(const StepInfo &info, BedSample *before, BedSample *after);
  PetscErrorCode reportFailure(PetscErrorCode status); // OUTPUT_DIR/FAILED; returns the error
  PetscErrorCode progress(long step, double time, bool last);
  PetscErrorCode writeCheckpoint(long step) const; // src/run/checkpoint.cpp
  PetscErrorCode readCheckpoint();                 // src/run/checkpoint.cpp
  PetscErrorCode adoptOutputsOf(const std::string &previousDirectory) const; // src/run/checkpoint.cpp
  PetscErrorCode jumpsFromPathFile(); // an older checkpoint's jumps.csv rows (src/run/checkpoint.cpp)
  /// What the physics was made with (src/run/checkpoint.cpp); a restart refuses a difference.
  std::vector<std::pair<std::string, std::string>> physicsRecord() const;
  // Several databases (src/run/run_switching.cpp, docs/databases.md).
  /// After the step ending at `time`: asks the rule and switches when it says so.
  PetscErrorCode followSwitches(long step, double time, int nextFrame);
  /// Makes the databases of `target` the active one: the operators are set up on it
  /// again (keeping their saved state), and with `remap` the state is carried
  /// onto its frame for the path's frame `nextFrame` (dbFrame) by the composition
  /// remap of a stitching jump.
  PetscErrorCode switchTo(const SwitchDecision &target, int nextFrame, double time, bool remap);
  /// The database in use, as the status page names it: its file, or a blend's two with their weights.
  std::string databaseInUse() const;
  // A live run (-live FILE, src/run/run_live.cpp, docs/live.md).
  /// In setUp, before the databases open: the file's header and first row, and the columns' users.
  PetscErrorCode liveStart();
  /// The file's conditions at `time` onto the operators' rates, the switching rule and the monitors.
  PetscErrorCode liveFollow(double time);
  /// Before the monitors of step k: the rows up to the end of step k + 1 (waiting for them), or the
  /// input's end (*ended; the run's last step is then k).
  PetscErrorCode liveAdvance(long k, bool *ended);
  RunContext context() const {
    RunContext c{*db, set, solidDensity,
                 switching ? &switching->operatingConditions() : (liveVelocity ? &liveConditions : nullptr)};
    c.numScalars = scalars.size();
    if (c.numScalars > 0) c.scalarNames = &fstate.scalarNames();
    return c;
  }
  /// The active database's frame for the path's frame k: the path runs over the
  /// frames of the database the run started on, a database of another length
  /// takes k modulo its own (docs/databases.md, "Databases of different lengths").
  /// Reads -monitors and makes the registered monitors it names (into `registered`).
  PetscErrorCode registeredMonitorsFromOptions();
  /// With one database, k itself.
  int dbFrame(int k) const { return k % db->numFrames(); }

  MPI_Comm comm;
  const OperatorRegistry &registry;
  PathRegistry builtinPaths; // used when the run was given no registry
  const PathRegistry &paths;
  std::shared_ptr<Database> db; // the active database
  // Several databases: the rules (-db_switch_type), the switcher, the carry
  // across a switch.  Only the active database is held (docs/databases.md, "Memory").
  SwitchRuleRegistry builtinRules = SwitchRuleRegistry::withBuiltins();
  const SwitchRuleRegistry *rules = &builtinRules;
  // The monitors -monitors names (Run(comm, registries) gives the program's).
  MonitorRegistry builtinMonitors = MonitorRegistry::withBuiltins();
  const MonitorRegistry *monitorKinds = &builtinMonitors;
  std::vector<Entry> registered; // made by setFromOptions, set up with the others
  std::unique_ptr<DatabaseSwitcher> switching;
  std::unique_ptr<CarryOperator> switchCarry;
  FractionSet set;
  FractionState fstate;
  Pipeline ops;
  MassLedger ledger;
  ScalarSet scalars; // -scalars: carried per fraction, with their ledger (docs/scalars.md)
  std::unique_ptr<FramePath> path;
  int pathFrames = 0; // the path's frame index: frames of the database the run started on
  CogMonitor *cog = nullptr; // the first entry of `monitors`
  std::vector<Entry> monitors;
  Answers answers; // the monitors a case asks for by option (profiles, halves, ...)
  std::unique_ptr<CsvSeries> pathFile; // OUTPUT_DIR/path.txt, the frame of every step, appended
  std::unique_ptr<JumpsFile> jumps;    // OUTPUT_DIR/jumps.csv, the steps taken as jumps, appended
  CentreOfGravity jumpCog;             // measures the bed on both sides of a jump's carry
  std::vector<int> frames;             // the same, in memory, only with keepHistory
  long startStep = 0, lastStep = 0;    // lastStep: the step being made, for a failure report
  bool isSetUp = false, solved = false, keepHistory = false;

  // Options.
  std::string dbPath, outputDir = "rcfd-output", initKind = "mixed", initFile;
  std::string pipelineSpec = "shift,drift,carry";
  std::string checkpointFile, restartFile;
  double dtRec = 0.0; // of every database of the run
  double tEnd = -1.0, fieldsEvery = 0.0, progressInterval = 2.0, solidDensity = -1.0;
  double checkpointEvery = 0.0;
  long steps = 0;
  PetscBool quiet = PETSC_FALSE, writeFields = PETSC_TRUE, stopAtSteady = PETSC_FALSE;
  OwnedViewer viewer; // -run_view
  PetscViewerFormat viewFormat = PETSC_VIEWER_DEFAULT;
  DatabaseLoadOptions loadOptions;
  double wallStart = 0.0, lastProgress = 0.0;
  LiveInput live;                      // -live FILE
  OperatingConditions liveConditions;  // one database and a live u_sup: the conditions the monitors see
  bool liveVelocity = false;           // ... whether it is so
  std::size_t liveRowsScheduled = 0;   // rows handed to the switching rule
  std::unique_ptr<ForecastMonitor> forecast; // -forecast_every: moved into `monitors` at setUp
  std::unique_ptr<StatusMonitor> status;     // -status: moved into `monitors`, last, at setUp
  double ledgerSeconds = 0.0; // wall time of the mass ledger's checks while stepping
};

} // namespace rcfd
