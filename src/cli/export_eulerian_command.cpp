// rcfd export-eulerian DB.h5 -o DIR: a database's frames as Eulerian ASCII
// frames (x y z alpha Ux Uy Uz Usx Usy Usz per cell, the format rcfd build
// -eulerian reads): alpha = 1 - alpha_s, U = 0, and Us the mass-averaged
// displacement per dt_rec that the shift matrix implies,
//   Us_c = sum_j T(j, c) (x_j - x_c) / dt_rec,
// the cell-resolution solid velocity of the database.  Rank 0 reads the
// database (a window of frames at a time, PETSC_COMM_SELF) and writes.
#include "cli/commands.hpp"
#include "base/petsc_compat.hpp"

#include "builders/eulerian/eulerian_frames.hpp"
#include "rcfd/database.hpp"
#include "base/collective.hpp"
#include "base/h5.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace rcfd::cli {
namespace {

constexpr int kWindow = 16; // frames held in memory at a time

struct ExportOptions {
  std::string database, directory = "eulerian-frames", prefix = "frame_";
  DatabaseLoadOptions load;
  PetscBool quiet = PETSC_FALSE;
};

PetscErrorCode readExportOptions(MPI_Comm comm, const char *positional, ExportOptions *o) {
  char db[PETSC_MAX_PATH_LEN] = "", dir[PETSC_MAX_PATH_LEN], prefix[PETSC_MAX_PATH_LEN];
  PetscBool setDb = PETSC_FALSE;
  PetscFunctionBeginUser;
  std::snprintf(dir, sizeof dir, "%s", o->directory.c_str());
  std::snprintf(prefix, sizeof prefix, "%s", o->prefix.c_str());
  PetscOptionsBegin(comm, nullptr, "rcfd export-eulerian: a database's frames as Eulerian ASCII frames",
                    "rcfd");
  PetscCall(PetscOptionsString("-db", "Database file (or give it as the first argument)", "", db, db,
                               sizeof db, &setDb));
  PetscCall(PetscOptionsString("-o", "Output directory (created)", "", dir, dir, sizeof dir, nullptr));
  PetscCall(PetscOptionsString("-prefix", "File names: PREFIX000000.txt, one per frame", "", prefix,
                               prefix, sizeof prefix, nullptr));
  PetscCall(PetscOptionsBool("-quiet", "No report", "", o->quiet, &o->quiet, nullptr));
  PetscOptionsEnd();
  PetscCall(Database::optionsFromCommandLine(&o->load));
  if (helpRequested()) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCheck(positional || setDb, comm, PETSC_ERR_USER_INPUT,
             "No database given: rcfd export-eulerian DB.h5 -o DIR");
  PetscCheck(!(positional && setDb), comm, PETSC_ERR_USER_INPUT,
             "Give the database once: as the first argument or with -db");
  PetscCheck(prefix[0] && !std::strchr(prefix, '/'), comm, PETSC_ERR_USER_INPUT,
             "-prefix must be a non-empty file name prefix without '/'");
  o->database = positional ? positional : db;
  o->directory = dir;
  o->prefix = prefix;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/// The shift of frame k of a database loaded on one rank, in natural order.
PetscErrorCode naturalShift(const Database &db, int k, CsrMatrix *T) {
  const Layout &L = db.layout();
  const int N = static_cast<int>(L.numCells());
  PetscFunctionBeginUser;
  T->n = N;
  T->rowPtr.assign(1, 0);
  T->col.clear();
  T->val.clear();
  OwnedMat shift;
  PetscCall(db.shiftMatrix(k, &shift));
  for (int j = 0; j < N; ++j) {
    PetscInt ncols;
    const PetscInt *cols;
    const PetscScalar *vals;
    const PetscInt row = L.petscRow(j);
    PetscCall(MatGetRow(shift, row, &ncols, &cols, &vals));
    for (PetscInt e = 0; e < ncols; ++e) {
      T->col.push_back(static_cast<int32_t>(L.naturalCell(cols[e])));
      T->val.push_back(vals[e]);
    }
    PetscCall(MatRestoreRow(shift, row, &ncols, &cols, &vals));
    T->rowPtr.push_back(static_cast<int64_t>(T->col.size()));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode naturalAlpha(const Database &db, int k, std::vector<double> *alpha) {
  const Layout &L = db.layout();
  const PetscScalar *a;
  PetscFunctionBeginUser;
  alpha->assign(L.numCells(), 0.0);
  PetscCall(VecGetArrayRead(db.alphaS(k), &a));
  for (PetscInt r = 0; r < L.numCells(); ++r) (*alpha)[L.naturalCell(r)] = a[r];
  PetscCall(VecRestoreArrayRead(db.alphaS(k), &a));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/// Rank 0's work, on PETSC_COMM_SELF.
PetscErrorCode exportOnRoot(const ExportOptions &o, int *written, int *cells) {
  MPI_Comm self = PETSC_COMM_SELF;
  PetscFunctionBeginUser;
  // The first frame validates the file; then its frame count is known.
  DatabaseLoadOptions window = o.load;
  window.lastFrame = window.firstFrame;
  std::unique_ptr<Database> db;
  PetscCall(Database::load(self, o.database, window, &db));
  long long K = 0;
  PetscCall(collectively(self, [&] {
    K = h5::File::openRead(o.database, MPI_COMM_NULL).readAttrInt("/frames", "num_frames");
    std::filesystem::create_directories(o.directory);
  }));
  const int last = o.load.lastFrame < 0 ? static_cast<int>(K) - 1 : o.load.lastFrame;
  PetscCheck(last < K && last >= o.load.firstFrame, self, PETSC_ERR_ARG_OUTOFRANGE,
             "-db_frames %d:%d is outside the %lld frames of database '%s'",
             (int)o.load.firstFrame, last, K, o.database.c_str());
  const Mesh mesh = db->mesh();
  const double dt = db->metadata().dtRec;
  *cells = mesh.numCells();
  EulerianFrame frame;
  frame.gasVelocity.assign(mesh.numCells(), Vec3{0.0, 0.0, 0.0});
  CsrMatrix T;
  for (int first = o.load.firstFrame; first <= last; first += kWindow) {
    window.firstFrame = first;
    window.lastFrame = std::min(last, first + kWindow - 1);
    if (first != o.load.firstFrame || window.lastFrame != first)
      PetscCall(Database::load(self, o.database, window, &db));
    for (int k = first; k <= window.lastFrame; ++k) {
      PetscCall(naturalAlpha(*db, k - first, &frame.alphaS));
      PetscCall(naturalShift(*db, k - first, &T));
      frame.solidVelocity = impliedSolidVelocity(mesh, T, dt);
      char name[PETSC_MAX_PATH_LEN];
      std::snprintf(name, sizeof name, "%s%06d.txt", o.prefix.c_str(), k);
      PetscCall(collectively(self, [&] {
        writeEulerianFrame((std::filesystem::path(o.directory) / name).string(), mesh, frame);
      }));
      ++*written;
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

PetscErrorCode exportEulerianCommand(MPI_Comm comm, const char *positional) {
  ExportOptions o;
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(readExportOptions(comm, positional, &o));
  if (helpRequested()) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(rejectUnusedOptions(comm, "export-eulerian"));
  int written = 0, cells = 0;
  PetscErrorCode ierr = PETSC_SUCCESS;
  std::string why;
  if (rank == 0) {
    ierr = exportOnRoot(o, &written, &cells);
    if (ierr) {
      const char *generic = nullptr;
      char *specific = nullptr;
      PetscErrorMessage(ierr, &generic, &specific);
      why = specific && *specific ? specific : (generic ? generic : "unknown error");
    }
  }
  PetscCall(agreeOnFailure(comm, ierr != PETSC_SUCCESS, why));
  if (!o.quiet)
    PetscCall(PetscPrintf(comm,
                          "Wrote %d Eulerian frames of %d cells to %s/%s*.txt (alpha = 1 - alpha_s, "
                          "U = 0, Us = mass-averaged displacement of the shift per dt_rec)\n",
                          written, cells, o.directory.c_str(), o.prefix.c_str()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
