// What a run reports.  Observables are monitors: the run keeps a list of
// them (like PETSc's TSMonitorSet) and calls each at the initial state, every
// `every` steps and at the end; its time loop knows nothing else about them.
// Built in: the centres of gravity and masses per fraction over time
// (cog.csv, -monitor_every) and fields for ParaView (HDF5 + XDMF, -fields).
// Asked for by a case (docs/answers.md): vertical profiles (-profiles), the
// halves' size distributions (-halves), the bottom layer's Sauter diameter,
// u_mf and the de-fluidization warning (-bottom_layer), Lacey's mixing index
// (-mixing_index), bed dynamics (-bed_dynamics), mid-plane snapshots
// (-snapshots_times); src/observable/answers.hpp.
//
// A new observable is a Monitor (or, for a quick one, a MonitorFn):
//
//   run.addMonitor([](const rcfd::MonitorContext &m) -> PetscErrorCode {
//     double low;
//     PetscCall(m.state.minimum(&low));               // collective
//     return PetscPrintf(PETSC_COMM_WORLD, "t = %g s: smallest mass %g kg\n", m.time, low);
//   }, 100, "lowest mass");
#pragma once

#include "rcfd/database.hpp"
#include "rcfd/fractions.hpp"
#include "rcfd/registry.hpp"
#include "rcfd/run_context.hpp"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace rcfd {

/// What a monitor sees when it is called.  All ranks of the run call their
/// monitors together, so a monitor may use collective operations.
struct MonitorContext {
  long step;                          ///< steps taken: 0 is the initial state
  double time;                        ///< simulated time [s]
  int frame;                          ///< database frame whose alpha_s the state should match now
  bool last;                          ///< the run's final call
  const FractionState &state;         ///< masses [kg] of every fraction in every cell
  const RunContext &run;              ///< database, fractions, solid density
  const std::string &outputDirectory; ///< where the run writes its results
};

/// An observable with a life cycle: set up once the database is loaded,
/// called at the steps the run chose, flushed every few wall seconds and at
/// the end (so that results survive an interruption).  A monitor registered
/// by name (MonitorRegistry, -monitors NAME,...) has the life cycle of every
/// extension point (docs/extending.md): created with the prefix "<name>_",
/// setFromOptions, setUp, sample, view (-<name>_view).
class Monitor {
public:
  virtual ~Monitor() = default;
  /// The registered name ("monitor" for one that is not registered).
  virtual std::string type() const { return "monitor"; }
  void setOptionsPrefix(const std::string &p) { prefix = p; }
  const std::string &optionsPrefix() const { return prefix; }
  /// Collective.  Reads the monitor's own options (none by default).
  virtual PetscErrorCode setFromOptions(MPI_Comm comm);
  /// Collective on the viewer.  The default prints "monitor <type()>".
  virtual PetscErrorCode view(PetscViewer viewer) const;
  /// Collective.  `state` gives the layout of the masses the monitor will see.
  /// Keep copies of what it needs of run.db, not pointers into it: a run on
  /// several databases drops the database it started on when it switches;
  /// sample() gets the database in use (MonitorContext::run, docs/databases.md).
  /// Re-entrant: a second call on the same run gives the same monitor.
  /// The default does nothing.
  virtual PetscErrorCode setUp(const RunContext &run, const FractionState &state,
                               const std::string &outputDirectory);
  /// Collective, and called often (every `every` steps): a monitor that writes a
  /// file on one rank here makes the outcome known to all (agreeOnStatus), so
  /// that a failed write cannot leave the other ranks waiting.
  virtual PetscErrorCode sample(const MonitorContext &ctx) = 0;
  /// Collective; the run agrees on its status, so rank 0 may write alone here.
  /// The default does nothing.
  virtual PetscErrorCode flush();

  /// Checkpoint contract.  saveState() returns what the monitor needs to
  /// continue a run exactly -- its own small state: sums over a time window,
  /// a detector's flags, the length of each file it appends to
  /// (CsvSeries::mark()) -- never its time series, so that a checkpoint's
  /// size does not grow with the run's length.  It is the same on every rank.
  /// The run calls flush() on every monitor right before saveState(), so the
  /// files a monitor appends to are complete up to the checkpoint's step.
  /// The run stores the state in the checkpoint under the monitor's name and,
  /// on restart, hands it back to restoreState() after setUp() and before
  /// the monitor sees the steps from the restart on; a monitor that appends
  /// to a file cuts it back there (CsvSeries::resume), so that a restarted
  /// run writes the same file, byte for byte, as an uninterrupted one.
  /// The default saves nothing.
  virtual std::vector<double> saveState() const;
  /// Collective.  The default refuses a non-empty state (a monitor that saves
  /// state must restore it).
  virtual PetscErrorCode restoreState(const std::vector<double> &state);

  /// A steady-state detector (the granulator's product.csv) lets a run end
  /// when its criterion is met (-stop_at_steady).  The run asks steadyAt()
  /// at the steps where the monitor is due, before sample(), with the state
  /// after the step (and, on restart, at the checkpoint's step).  Collective;
  /// the answer must come from globally reduced values.  Defaults: no detector.
  virtual bool detectsSteadyState() const { return false; }
  virtual PetscErrorCode steadyAt(const MonitorContext &ctx, bool *steady) const;

  /// Quantities a switching rule may decide on (-db_switch_quantity NAME,
  /// docs/databases.md): the names this monitor offers, and one's value at
  /// the monitor's latest sample, the same on every rank (NaN before the
  /// first).  A monitor that offers signals keeps their latest values in its
  /// saveState(), so that a restart decides as the run would have.  Defaults:
  /// none.
  virtual std::vector<std::string> signalNames() const { return {}; }
  virtual double signal(const std::string &name) const;

protected:
  std::string prefix;
};

using MonitorFactory = std::function<std::unique_ptr<Monitor>()>;

/// Name -> factory of monitors a run adds by -monitors NAME,... (each sampled
/// every -<name>_every steps, default 1), owned by the program (no global).
class MonitorRegistry : public Registry<Monitor> {
public:
  MonitorRegistry() : Registry("-monitors", "monitor") {}
  /// mixing_index (the same monitor as -mixing_index).
  static MonitorRegistry withBuiltins();
};

/// A monitor given as a function.
using MonitorFn = std::function<PetscErrorCode(const MonitorContext &)>;

struct BedSample {
  double time = 0.0;
  std::vector<double> mass;  // total mass of each fraction [kg]
  std::vector<double> zCog;  // centre of gravity of each fraction along "up" [m]
  double zCogBed = 0.0;      // of all fractions together [m]
  double deltaZ = 0.0;       // zCog(smallest) - zCog(largest) [m]
  double minMass = 0.0;      // smallest mass in any cell and fraction [kg]
  /// sum_c |M_c - rho alpha_c V_c| / sum_c rho alpha_c V_c against the frame
  /// the state should match: how far the bulk has strayed from the database.
  double bulkMismatch = 0.0;
};

/// Heights of this rank's cells along -gravity, and the sums that turn a
/// state into a BedSample.
class CentreOfGravity {
public:
  PetscErrorCode setUp(const Database &db, const FractionSet &fractions);
  /// Collective.  `alpha` is the database frame the state should match.
  PetscErrorCode measure(double time, Vec masses, Vec alpha, double rho, BedSample *sample) const;
  const std::vector<double> &localHeights() const { return height; }

private:
  MPI_Comm comm = MPI_COMM_NULL;
  std::vector<double> height, volume;
  int nf = 0, small = 0, large = 0;
};

/// A text time series -- a header line, then one line per row -- written by
/// rank 0 and appended to as the run goes: rows wait in memory only until the
/// next flush() (every few wall seconds and at every checkpoint) or until
/// 64 kB wait, so memory does not grow with the run's length.  The file is
/// complete up to its last write: the first write of a new run makes it
/// atomically (header and the rows so far, replacing any older file); later
/// writes append whole rows (flush() also syncs them to disk), and a failed
/// write is an error naming the file.  A file cut by a crash between two
/// writes ends at a row boundary only if the crash was not in the middle of
/// an append; the checkpoint's length is what a restart trusts.
/// On restart, resume() cuts the file back to the length it had at the
/// checkpoint (mark()), and the run appends from there.
class CsvSeries {
public:
  CsvSeries(MPI_Comm comm, std::string path, std::string header);
  /// Collective: one line, without its newline (the same on every rank);
  /// writes the waiting rows (without syncing them to disk) when 64 kB wait.
  PetscErrorCode add(const std::string &row);
  /// Collective: writes the waiting rows and syncs them to disk; errors reach every rank.
  PetscErrorCode flush() { return write(true); }
  /// Bytes in the file after the last flush (the same on every rank), for a checkpoint.
  double mark() const { return static_cast<double>(written); }
  /// A monitor's state when the series is all it keeps: {mark()}, or nothing
  /// before the file is written, so that a restart adding the monitor starts
  /// its file anew (restoreState with an empty state).
  std::vector<double> state() const { return started ? std::vector<double>{mark()} : std::vector<double>{}; }
  /// Collective: continue a file that held `mark` bytes at the checkpoint:
  /// cuts it back to them; refuses, naming the file, one that is missing or shorter.
  PetscErrorCode resume(double mark);
  /// Rows added since the series was made or resumed (flushed or not).
  long rows() const { return count; }

private:
  PetscErrorCode write(bool sync);
  MPI_Comm comm;
  std::string path, header;
  std::string waiting; // rows not yet in the file
  unsigned long long written = 0;
  long count = 0;
  bool started = false; // the file exists and ends at `written`
};

/// One CSV line of numbers with 10 significant digits (%.10g).
std::string formatNumberRow(const std::vector<double> &row);

/// Writes cell fields of the state, one HDF5 file per output time plus an
/// XDMF index that ParaView opens as a time series.  Fields: alpha_s of the
/// state, alpha_s of the database frame, alpha of each fraction, and the local
/// Sauter diameter.  It keeps the mesh's sizes from setUp, not the database:
/// the frame's alpha_s is handed to write(), from the database in use (a run
/// on several databases switches, docs/databases.md).
class FieldWriter {
public:
  PetscErrorCode setUp(const Database &db, const FractionSet &fractions, double solidDensity,
                       const std::string &directory, Vec stateTemplate);
  /// Collective.  `databaseAlpha`: alpha_s of the frame the state should match,
  /// on the layout of setUp's database.
  PetscErrorCode write(double time, Vec databaseAlpha, Vec masses, Vec amounts = nullptr);
  /// Collective, after setUp: write() also writes, given the state's scalar
  /// amounts (FractionState::amounts(), docs/scalars.md), each scalar's value
  /// per fraction and cell, NAME_<fraction label> = amount / mass, and per
  /// cell over the fractions, NAME = sum of amounts / sum of masses (NaN
  /// where there is no mass).
  PetscErrorCode setUpScalars(const Database &db, const std::vector<std::string> &names, Vec amountsTemplate);
  int count() const { return static_cast<int>(times.size()); }
  /// The times written so far, oldest first (kept by checkpoints).
  const std::vector<double> &outputTimes() const { return times; }
  /// After a restart, continue the series of an earlier run (collective):
  /// when its files are all in this directory they are kept and the index
  /// lists their times too; otherwise the series starts afresh.
  PetscErrorCode continueSeries(const std::vector<double> &earlier);

private:
  PetscErrorCode writeIndex() const;
  MPI_Comm comm = MPI_COMM_NULL;
  PetscErrorCode writeVesselCells() const;
  BoxSpec box;
  std::vector<double> cellVolume; // natural order, on rank 0
  std::vector<int> boxCells;      // a vessel's cells (their box cells), on rank 0; empty on a box
  int vesselPoints = 0;           // corners of the vessel's cells, in fields_mesh.h5
  const FractionSet *fractions = nullptr;
  double rho = 0.0;
  std::string dir;
  OwnedVec natural, naturalAlpha, zeroMasses, zeroAlpha; // zero*: everything on rank 0
  OwnedScatter toNatural, alphaToNatural, toZero, alphaToZero;
  std::vector<std::string> scalarNames;
  OwnedVec naturalAmounts, zeroAmounts;
  OwnedScatter amountsToNatural, amountsToZero;
  std::vector<double> times;
};

/// One row of cog.csv with the given number of significant digits.
std::string formatCsvRow(const BedSample &sample, int digits);

/// Atomically replace `path` with `text` (write to a temporary name, rename).
PetscErrorCode writeFileAtomically(const std::string &path, const std::string &text);
/// mkdir -p on rank 0 (collective).
PetscErrorCode makeDirectories(MPI_Comm comm, const std::string &path);

} // namespace rcfd
