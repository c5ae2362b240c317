// OUTPUT_DIR/jumps.csv: the rows of cog.csv (and of the other time series)
// that follow a step the run took as a jump, where the state was carried into
// another bed: a stitched path's jump, a replay's wrap to frame 0, and on
// several databases a wrap of the database in use inside the path's frames
// (docs/paths.md, docs/databases.md).  Appended as the run steps and cut back
// on a restart, like the other time series; a run without a jump leaves none.
#pragma once

#include "rcfd/observables.hpp"

#include <string>
#include <vector>

namespace rcfd {

class JumpsFile {
public:
  /// On several databases the frames are those of the database in use, and a
  /// column names it; on one, the file is what it always was.
  /// `labels`: the fractions' column labels (FractionSet::label).
  JumpsFile(MPI_Comm comm, const std::string &outputDir, bool severalDatabases, std::vector<std::string> labels);
  /// Collective: the step from `from` to `to` (the database in use's frames)
  /// ending at `time`; `database` names the database in use (several only).
  /// `before` and `after`: the bed just before and just after the carry
  /// (delta_z and each fraction's z_cog), or null when not recorded (the
  /// rows an older checkpoint's run did not write: "nan").
  PetscErrorCode add(long step, double time, int from, int to, const std::string &database,
                     const BedSample *before, const BedSample *after);
  /// Collective: writes the rows so far (nothing before the first jump).
  PetscErrorCode flush();
  /// Collective, at the run's end: flush(); without a jump, removes the file
  /// of an earlier run in the directory.
  PetscErrorCode finish();
  /// For a checkpoint: the file's length, or -1 while it holds no row.
  double mark() const { return series.state().empty() ? -1.0 : series.mark(); }
  /// Collective, on restart: continues the checkpoint's file (mark() >= 0), or
  /// starts anew, replacing the file written after the checkpoint.
  PetscErrorCode resume(double mark);

private:
  MPI_Comm comm;
  std::string path;
  bool several;
  int nf;
  CsvSeries series;
};

} // namespace rcfd
