#include "cli/commands.hpp"
#include "base/petsc_compat.hpp"

#include "base/collective.hpp"
#include "base/h5.hpp"
#include "analysis/comparison.hpp"
#include "observable/bed_dynamics.hpp"
#include "rcfd/database.hpp"

#include <cstring>
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

// /extra/<name> as CSV: a comment naming it, a header c0, c1, ... and its rows
// (what -extra_csv writes, e.g. the measured drift field for a figure).
PetscErrorCode writeExtraCsv(MPI_Comm comm, const Database &db, const std::string &name, const std::string &out) {
  std::vector<double> values;
  int cols = 0;
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCall(db.readMatrix(name, &values, &cols));
  PetscCheck(!values.empty() && cols > 0, comm, PETSC_ERR_USER_INPUT,
             "Database '%s' has no dataset /extra/%s to write with -extra_csv", db.path().c_str(), name.c_str());
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(collectively(comm, [&] {
    if (rank != 0) return;
    std::string text = "# /extra/" + name + " of " + db.path() + " (docs/database-format.md)\n";
    for (int c = 0; c < cols; ++c) text += (c ? ",c" : "c") + std::to_string(c);
    char number[32];
    for (std::size_t i = 0; i < values.size(); ++i) {
      std::snprintf(number, sizeof number, "%.17g", values[i]);
      text += (i % cols ? "," : "\n") + std::string(number);
    }
    writeTextFile(out, text + "\n");
  }));
  PetscCall(PetscPrintf(comm, "  wrote /extra/%s (%zu x %d) to %s\n", name.c_str(), values.size() / cols, cols,
                        out.c_str()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

PetscErrorCode infoCommand(MPI_Comm comm, const char *positional) {
  char path[PETSC_MAX_PATH_LEN] = "", extra[PETSC_MAX_PATH_LEN] = "", extraOut[PETSC_MAX_PATH_LEN] = "";
  PetscBool set = PETSC_FALSE, extraSet = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, nullptr, "rcfd info: what a database holds", "rcfd");
  PetscCall(PetscOptionsString("-db", "Database file (or give it as the first argument)", "", "",
                               path, sizeof path, &set));
  PetscCall(PetscOptionsString("-extra_csv", "NAME,FILE: also write the database's /extra/NAME as a CSV file", "",
                               "", extra, sizeof extra, &extraSet));
  PetscOptionsEnd();
  DatabaseLoadOptions options;
  PetscCall(Database::optionsFromCommandLine(&options));
  if (helpRequested()) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(rejectUnusedOptions(comm, "info"));
  std::string file = positional ? positional : path;
  PetscCheck(!file.empty(), comm, PETSC_ERR_USER_INPUT, "No database given: rcfd info FILE");
  char *comma = extraSet ? std::strchr(extra, ',') : nullptr;
  PetscCheck(!extraSet || (comma && comma != extra && comma[1]), comm, PETSC_ERR_USER_INPUT,
             "-extra_csv takes NAME,FILE (a dataset under /extra and the CSV to write), not '%s'", extra);
  if (comma) {
    std::snprintf(extraOut, sizeof extraOut, "%s", comma + 1);
    *comma = '\0';
  }
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
  if (extraSet) PetscCall(writeExtraCsv(comm, *db, extra, extraOut));
  std::vector<double> zCog;
  PetscCall(databaseBedCentres(*db, &zCog));
  double mean = 0.0;
  for (double z : zCog) mean += z / static_cast<double>(zCog.size());
  PetscCall(PetscPrintf(comm, "  bed dynamics: mean z_CoG %.6g m, Delta z_CoG = mean |z_CoG - mean| = %.6g m over %d frames\n",
                        mean, bedDynamics(zCog), static_cast<int>(zCog.size())));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
