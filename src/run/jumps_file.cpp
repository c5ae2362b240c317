#include "run/jumps_file.hpp"
#include "base/collective.hpp"
#include "base/petsc_compat.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>

namespace rcfd {
namespace {

std::string headerFor(bool several, const std::vector<std::string> &labels) {
  std::string columns = "step,time_s,from_frame,to_frame";
  if (several) columns += ",database";
  for (const char *when : {"before", "after"}) {
    columns += std::string(",delta_z_") + when + "_m";
    for (const std::string &l : labels) columns += ",z_cog_" + l + "_" + when + "_m";
  }
  const std::string what = "; delta_z and each fraction's z_cog just before and just after the carry onto to_frame "
                           "(the carry operator, docs/paths.md), nan where not recorded\n";
  if (!several)
    return "# rows of cog.csv at time_s follow a jump of the frame path (stitching, or a replay wrapping to "
           "frame 0): the bed's state was carried from after from_frame's shift into to_frame" + what + columns;
  return "# rows of cog.csv at time_s follow a jump of the frame path (stitching, or a replay wrapping to "
         "frame 0) or of the database in use (its wrap, or a blend's database wrapping inside it): the bed's "
         "state was carried from after from_frame's shift into to_frame, frames of that database; switches "
         "are in switches.csv" + what + columns;
}

// The bed's numbers of one side of the carry, 7 significant digits (so that
// round-off between partitions does not show).
void appendSample(std::string &row, const BedSample *s, int nf) {
  char v[32];
  for (int i = -1; i < nf; ++i) {
    const double x = !s ? std::nan("") : i < 0 ? s->deltaZ : s->zCog[i];
    std::snprintf(v, sizeof v, ",%.7g", x);
    row += v;
  }
}

} // namespace

JumpsFile::JumpsFile(MPI_Comm comm, const std::string &outputDir, bool severalDatabases,
                     std::vector<std::string> labels)
    : comm(comm), path(outputDir + "/jumps.csv"), several(severalDatabases), nf(static_cast<int>(labels.size())),
      series(comm, path, headerFor(severalDatabases, labels)) {}

PetscErrorCode JumpsFile::add(long step, double time, int from, int to, const std::string &database,
                              const BedSample *before, const BedSample *after) {
  char head[160];
  PetscFunctionBeginUser;
  if (several) std::snprintf(head, sizeof head, "%ld,%.9g,%d,%d,%s", step, time, from, to, database.c_str());
  else std::snprintf(head, sizeof head, "%ld,%.9g,%d,%d", step, time, from, to);
  std::string row = head;
  appendSample(row, before, nf);
  appendSample(row, after, nf);
  PetscCall(series.add(row));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode JumpsFile::flush() {
  PetscFunctionBeginUser;
  if (mark() >= 0 || series.rows() > 0) PetscCall(series.flush()); // no header alone
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode JumpsFile::finish() {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCall(flush());
  if (mark() >= 0) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(collectively(comm, [&] {
    if (rank == 0) std::filesystem::remove(path); // an earlier run's, or the checkpoint's run's after it
  }, PETSC_ERR_FILE_WRITE));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode JumpsFile::resume(double mark) {
  PetscFunctionBeginUser;
  if (mark >= 0) PetscCall(series.resume(mark)); // else the first row's write replaces the file
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
