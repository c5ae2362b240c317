#include "cli/commands.hpp"
#include "base/petsc_compat.hpp"

#include "base/collective.hpp"
#include "base/h5.hpp"
#include "observable/bed_dynamics.hpp"
#include "rcfd/database.hpp"

#include <filesystem>

namespace rcfd::cli {
namespace {

// The whole file read back on rank 0, every dataset and attribute, so that
// every checksum is compared, not only those of what the load read (the mesh
// arrays a box does not need, /extra): "verified", or the damage named (an error).
PetscErrorCode printIntegrity(MPI_Comm comm, const Database &db) {
  PetscMPIInt rank;
  std::pair<long long, double> read{0, 0.0};
  PetscFunctionBeginUser;
  if (!db.checksummed()) {
    PetscCall(PetscPrintf(comm, "  integrity: cannot be verified: the file has no checksums (an older rcfd wrote it); "
                                "rcfd coarsen %s -factor 1,1,1 -o NEW writes a copy that has them\n",
                          db.path().c_str()));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(collectively(comm, [&] {
    if (rank == 0) read = h5::File::openRead(db.path(), MPI_COMM_NULL).verifyAll();
  }));
  PetscCall(PetscPrintf(comm, "  integrity: verified (%lld datasets, %.1f MB: every chunk's Fletcher-32 checksum and HDF5's own checksums match)\n",
                        read.first, read.second / 1e6));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

PetscErrorCode infoCommand(MPI_Comm comm, const char *positional) {
  char path[PETSC_MAX_PATH_LEN] = "";
  PetscBool set = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, nullptr, "rcfd info: what a database holds", "rcfd");
  PetscCall(PetscOptionsString("-db", "Database file (or give it as the first argument)", "", "",
                               path, sizeof path, &set));
  PetscOptionsEnd();
  DatabaseLoadOptions options;
  PetscCall(Database::optionsFromCommandLine(&options));
  if (helpRequested()) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(rejectUnusedOptions(comm, "info"));
  std::string file = positional ? positional : path;
  PetscCheck(!file.empty(), comm, PETSC_ERR_USER_INPUT, "No database given: rcfd info FILE");
  std::unique_ptr<Database> db;
  PetscCall(Database::load(comm, file, options, &db));
  PetscCall(db->view(PETSC_VIEWER_STDOUT_(comm)));
  std::error_code failed;
  const auto bytes = std::filesystem::file_size(file, failed);
  PetscCall(PetscPrintf(comm, "  file: format version %lld, %.1f MB%s\n", db->formatVersion(),
                        failed ? 0.0 : static_cast<double>(bytes) / 1e6,
                        db->formatVersion() < kDatabaseFormatVersion
                            ? " (an older version: rcfd coarsen FILE -factor 1,1,1 -o NEW rewrites it, smaller and "
                              "faster to load, docs/database-format.md)"
                            : ""));
  PetscCall(printIntegrity(comm, *db));
  std::vector<double> zCog;
  PetscCall(databaseBedCentres(*db, &zCog));
  double mean = 0.0;
  for (double z : zCog) mean += z / static_cast<double>(zCog.size());
  PetscCall(PetscPrintf(comm, "  bed dynamics: mean z_CoG %.6g m, Delta z_CoG = mean |z_CoG - mean| = %.6g m over %d frames\n",
                        mean, bedDynamics(zCog), static_cast<int>(zCog.size())));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
