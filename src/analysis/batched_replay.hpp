// Replays that share a database and a frame path and differ only in what
// their other operators do (drift laws, exponents, constants: the candidates
// of a calibration) run as one state with nf x nc columns (nf fractions of
// nc candidates, interleaved per cell).  The shift is linear and the same
// for every column, so it is applied once per step to all columns and reads
// each frame once for all candidates; every other operator of the pipeline
// (the drift with the candidate's law and parameters, which reads the
// composition, local d32 and bulk of the candidate's own columns), the mass
// ledger and the centre of gravity act on each candidate's own nf columns,
// copied out of the batch after the shift and back before the next one.
//
// Each candidate evolves bit for bit as its one-by-one run (Run::solve):
// the shift's kernels sum every column in the entry order of the frame,
// whatever the number of columns, and everything else is the candidate's
// own operators on its own state (tests/test_batched_calibration.cpp).
//
// What can be batched: one database (no -db set), the shift first in the
// pipeline and the only operator that reads other cells' columns in common,
// a pipeline that conserves mass, no restart.  Candidates are split into
// batches of at most kMaxFractions columns.  Output per candidate: its
// samples in memory (history()), and cog.csv when given a directory.  What the
// candidates share is made once: the loaded database and the agitation
// field of each measure their drift scales by.
#pragma once

#include "observable/cog_monitor.hpp"
#include "rcfd/agitation.hpp"
#include "rcfd/plugin.hpp"
#include "rcfd/mass_ledger.hpp"
#include "rcfd/run.hpp"

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace rcfd {

class BatchedReplay {
public:
  struct Candidate {
    /// Where its cog.csv goes (the run's -output_dir for this candidate);
    /// empty: no cog.csv, the samples are kept in memory only (a scan's
    /// points: formatting and writing the rows is most of a small bed's step).
    std::string outputDirectory;
    /// Options of this candidate alone, e.g. "-drift_kd 2836 -drift_agitation
    /// leaving", read over the command line's by its run (each must be used).
    std::string options;
    /// Typed settings of its operators, between its run's setFromOptions and
    /// setUp (may be empty).
    std::function<PetscErrorCode(Run &)> configure;
  };

  /// The registry supplies the runs' operators; it must outlive the batch.
  BatchedReplay(MPI_Comm comm, const OperatorRegistry &registry);
  ~BatchedReplay();
  /// All the program's registries (paths, monitors, ... with what plugins
  /// added) for the candidates' runs and the shared path; nullptr: the
  /// operator registry and the built-in paths.
  void useRegistries(const Registries *all) { registries = all; }
  /// The database every candidate replays (else each batch loads -db once).
  void useDatabase(std::shared_ptr<Database> db) { database = std::move(db); }

  /// Collective.  Whether runs of these options can be batched, checked on
  /// a run set up with them; `why` says why not.
  static bool batchable(Run &run, std::string *why);

  /// Collective.  Calls `read` with `options` (a candidate's, e.g.
  /// "-drift_kd 2836") over the command line's, which stay as they were;
  /// refuses an option of `options` that `read` did not read.
  static PetscErrorCode withOptions(MPI_Comm comm, const std::string &options,
                                    const std::function<PetscErrorCode()> &read);

  /// Collective.  One candidate as a run of its own (Run::solve, with the
  /// batch's database): what its part of a batch equals.  `run` is made by
  /// the caller with this batch's registry and keeps the samples (history())
  /// and the state.
  PetscErrorCode solveAlone(const Candidate &candidate, Run &run) const;

  /// Collective.  Replays every candidate and keeps its samples; candidates
  /// beyond kMaxFractions / nf columns go in further batches.
  PetscErrorCode solve(const std::vector<Candidate> &candidates);
  /// The centre-of-gravity samples of candidate c (every -monitor_every steps).
  const std::vector<BedSample> &history(int c) const { return histories[c]; }
  /// This rank's masses of candidate c at the end (cell-major, nf per cell).
  const std::vector<double> &finalMasses(int c) const { return finals[c]; }
  /// Batches the last solve() made.
  int batches() const { return batchCount; }
  /// At most this many columns (fractions x candidates) per batch; default
  /// and upper limit kMaxFractions.
  void setColumnsPerBatch(int n) { columnsPerBatch = n; }

private:
  struct Group; // one candidate: its run, operators, ledger and monitor
  PetscErrorCode solveBatch(const std::vector<Candidate> &candidates, std::size_t first, std::size_t count);
  PetscErrorCode setUpGroup(const Candidate &candidate, Group *group);
  PetscErrorCode shareAgitation(Run &run);

  MPI_Comm comm;
  const OperatorRegistry &registry;
  const Registries *registries = nullptr;
  std::shared_ptr<Database> database;
  // The agitation fields of the database by measure, made once for all
  // candidates that scale their drift by one (the same numbers each
  // candidate's drift would make for itself).
  std::map<std::string, std::shared_ptr<const AgitationField>> fields;
  std::vector<std::vector<BedSample>> histories;
  std::vector<std::vector<double>> finals;
  int batchCount = 0, columnsPerBatch = kMaxFractions;
};

} // namespace rcfd
