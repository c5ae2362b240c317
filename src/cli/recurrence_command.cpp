#include "cli/commands.hpp"
#include "base/petsc_compat.hpp"

#include "cli/figures.hpp"
#include "path/database_recurrence.hpp"
#include "base/atomic_file.hpp"
#include "base/collective.hpp"
#include "base/h5.hpp"

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <cstdio>
#include <sstream>

namespace rcfd::cli {
namespace {

/// The K x K matrix as CSV (row i, column j: frames i and j), for the heat
/// map's script and for anyone's own analysis; written atomically.
void writeMatrixCsv(const std::string &path, const std::vector<double> &R, int K, const std::string &note) {
  std::ostringstream out;
  out.precision(6);
  out << "# " << note << "; row i, column j: frames i and j\n";
  for (int i = 0; i < K; ++i)
    for (int j = 0; j < K; ++j) out << R[static_cast<size_t>(i) * K + j] << (j + 1 < K ? ',' : '\n');
  writeTextAtomically(path, out.str());
}

} // namespace

// rcfd recurrence DB.h5: compute the recurrence matrix of every frame pair
// (collectively), store it in the database under /extra, write it as CSV
// next to the database and draw it.
PetscErrorCode recurrenceCommand(MPI_Comm comm, const char *positional) {
  char text[PETSC_MAX_PATH_LEN] = "";
  char normName[32] = "sqrDiff";
  PetscBool set = PETSC_FALSE, store = PETSC_TRUE, quiet = PETSC_FALSE;
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscOptionsBegin(comm, nullptr, "rcfd recurrence: the recurrence matrix of a database", "rcfd");
  PetscCall(PetscOptionsString("-db", "Database file (or give it as the first argument)", "", "",
                               text, sizeof text, &set));
  PetscCall(PetscOptionsString("-recurrence_norm", "sqrDiff, euclidean, absDiff or max", "",
                               normName, normName, sizeof normName, nullptr));
  PetscCall(PetscOptionsBool("-store", "Store the matrix in the database file", "", store, &store, nullptr));
  PetscCall(PetscOptionsBool("-quiet", "No report", "", quiet, &quiet, nullptr));
  PetscOptionsEnd();
  DatabaseLoadOptions options;
  options.loadShifts = false; // alpha_s is all it needs
  if (helpRequested()) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(rejectUnusedOptions(comm, "recurrence"));
  const std::string file = positional ? positional : text;
  PetscCheck(!file.empty(), comm, PETSC_ERR_USER_INPUT, "No database given: rcfd recurrence FILE");
  RecurrenceNorm norm = RecurrenceNorm::SqrDiff;
  PetscCall(collectively(comm, [&] { norm = parseRecurrenceNorm(normName); }, PETSC_ERR_USER_INPUT));

  std::unique_ptr<Database> db;
  PetscCall(Database::load(comm, file, options, &db));
  const double start = MPI_Wtime();
  std::vector<double> R;
  PetscCall(computeRecurrence(*db, norm, &R));
  const double seconds = MPI_Wtime() - start;
  const int K = db->numFrames();
  const double frameDt = db->metadata().dtRec;
  db.reset(); // close before writing into the file
  const std::string stem = file.substr(0, file.rfind('.')) + "-recurrence";
  const std::string note = std::string("recurrence matrix, norm ") + recurrenceNormName(norm) +
                           ", divided by its largest entry";
  PetscCall(collectively(comm, [&] {
    if (rank != 0) return;
    if (store) {
      // Into a copy that replaces the database when complete: an interrupted
      // or failed write leaves the database as it was.
      AtomicFile updated(file);
      std::error_code copyError;
      std::filesystem::copy_file(file, updated.temporaryPath(),
                                 std::filesystem::copy_options::overwrite_existing, copyError);
      if (copyError)
        throw std::runtime_error("cannot copy database '" + file + "' to store the recurrence matrix: " +
                                 copyError.message());
      h5::File f = h5::File::openReadWrite(updated.temporaryPath());
      f.createGroup("/extra");
      const std::string name = "/extra/" + recurrenceDatasetName(norm);
      if (f.exists(name)) H5Ldelete(f.id(), name.c_str(), H5P_DEFAULT);
      f.write(name, R, static_cast<hsize_t>(K));
      f.writeAttr(name, "note", note);
      f.close(); // with its status
      updated.commit();
    }
    writeMatrixCsv(stem + ".csv", R, K, note + "; database " + file);
  }));
  const std::string png = stem + ".png";
  PetscCall(drawFigure(comm, "recurrence.py",
                       {stem + ".csv", "-o", png, "--norm", recurrenceNormName(norm), "--frame_dt",
                        std::to_string(frameDt), "--title", "recurrence matrix of " + file}));
  if (!quiet) {
    double offDiagonalMin = 1.0;
    for (int i = 0; i < K; ++i)
      for (int j = 0; j < K; ++j)
        if (std::abs(i - j) >= std::max(1, K / 10)) offDiagonalMin = std::min(offDiagonalMin, R[i * K + j]);
    PetscCall(PetscPrintf(comm,
                          "Recurrence matrix (%s) of %d frames in %.2f s; closest pair at least K/10 apart: %.3f\n"
                          "%s%s.csv, heat map %s\n",
                          recurrenceNormName(norm), K, seconds, offDiagonalMin,
                          store ? ("stored in " + file + " and ").c_str() : "", stem.c_str(), png.c_str()));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
