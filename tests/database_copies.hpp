// Test helpers for database files: a copy of a database in another format
// version or with quantised weights, and the sentence a load refuses with.
#pragma once

#include "base/h5.hpp"
#include "base/petsc_compat.hpp"
#include "database/quantise.hpp"
#include "database/stored_frame.hpp"
#include "rcfd/database.hpp"
#include "database/database_file_writer.hpp"

#include <memory>
#include <string>

namespace rcfd::test {

/// Collective; rank 0 writes `out` in format `version`: the frames of `in`,
/// their weights quantised to 2^-bits when bits > 0, as they are otherwise.
inline PetscErrorCode rewriteDatabase(const std::string &in, const std::string &out, int bits,
                                      long long version = kDatabaseFormatVersion) {
  std::unique_ptr<Database> header;
  DatabaseLoadOptions noShifts;
  noShifts.loadShifts = false;
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  PetscCall(Database::load(PETSC_COMM_WORLD, in, noShifts, &header));
  if (rank == 0) {
    DatabaseMetadata meta = header->metadata();
    meta.weightBits = bits;
    DatabaseFileWriter w(out, header->mesh(), meta, version);
    const h5::File f = h5::File::openRead(in, MPI_COMM_NULL);
    for (int k = 0; k < header->numFrames(); ++k) {
      FrameRecord r = readStoredFrame(f, k, header->mesh().numCells());
      if (bits > 0) quantiseWeights(&r.shift, bits);
      w.append(r);
    }
    w.finish();
  }
  PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/// Collective.  The message Database::load refuses `path` with ("" if it loads).
inline std::string loadRefusal(const std::string &path) {
  std::unique_ptr<Database> db;
  const PetscErrorCode ierr = Database::load(PETSC_COMM_WORLD, path, DatabaseLoadOptions{}, &db);
  char *specific = nullptr;
  PetscErrorMessage(ierr, nullptr, &specific);
  return ierr && specific ? specific : "";
}

} // namespace rcfd::test
