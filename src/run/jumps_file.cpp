#include "run/jumps_file.hpp"
#include "base/collective.hpp"
#include "base/petsc_compat.hpp"

#include <cstdio>
#include <filesystem>

namespace rcfd {
namespace {

std::string headerFor(bool several) {
  if (!several)
    return "# rows of cog.csv at time_s follow a jump of the frame path (stitching, or a replay wrapping to "
           "frame 0): the bed's state was carried from after from_frame's shift into to_frame\n"
           "step,time_s,from_frame,to_frame";
  return "# rows of cog.csv at time_s follow a jump of the frame path (stitching, or a replay wrapping to "
         "frame 0) or of the database in use (its wrap, or a blend's database wrapping inside it): the bed's "
         "state was carried from after from_frame's shift into to_frame, frames of that database; switches "
         "are in switches.csv\nstep,time_s,from_frame,to_frame,database";
}

} // namespace

JumpsFile::JumpsFile(MPI_Comm comm, const std::string &outputDir, bool severalDatabases)
    : comm(comm), path(outputDir + "/jumps.csv"), several(severalDatabases),
      series(comm, path, headerFor(severalDatabases)) {}

PetscErrorCode JumpsFile::add(long step, double time, int from, int to, const std::string &database) {
  char row[160];
  PetscFunctionBeginUser;
  if (several) std::snprintf(row, sizeof row, "%ld,%.9g,%d,%d,%s", step, time, from, to, database.c_str());
  else std::snprintf(row, sizeof row, "%ld,%.9g,%d,%d", step, time, from, to);
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
