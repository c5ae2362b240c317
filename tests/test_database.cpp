// Database file: hand-made frames give hand-computed answers through the
// shift operator, a permutation moves mass exactly, and every broken file is
// refused with its sentence.  Runs at 1 and 2 ranks.
#include "check.hpp"
#include "box_meshes.hpp"
#include "fraction_sets.hpp"
#include "rcfd/database.hpp"
#include "rcfd/operator.hpp"
#include "state_access.hpp"
#include "base/h5.hpp"
#include "database_copies.hpp"
#include "database/database_file_writer.hpp"

#include <cstdio>
#include <functional>
#include <numeric>

using namespace rcfd;
using rcfd::test::gatherNatural;
using rcfd::test::setNatural;

namespace {

std::string dir;
int rank = 0;

Mesh column3() {
  BoxSpec s;
  s.nx = 1;
  s.ny = 1;
  s.nz = 3;
  s.length = {0.1, 0.1, 0.3};
  return rcfd::test::boxMesh(s);
}

// A 3-cell column with two frames.  Frame 0 sends half of cell 0 up, 3/4 of
// cell 1 up and keeps cell 2; frame 1 is the identity.  Written in format
// version 2 (full CSR), so that the broken files below keep the version 2
// reader covered; test_database_v3 breaks version 3 files.
void writeColumn(const std::string &path) {
  DatabaseFileWriter w(path, column3(), DatabaseMetadata{}, 2);
  FrameRecord f0;
  f0.alphaS = {0.4, 0.4, 0.1};
  f0.shift = shiftFromTransfers(3, {0, 1, 1, 2, 2}, {0, 0, 1, 1, 2}, {1, 1, 1, 3, 1});
  w.append(f0);
  FrameRecord f1;
  f1.alphaS = {0.2, 0.3, 0.4};
  f1.shift = shiftFromTransfers(3, {}, {}, {});
  w.append(f1);
  w.finish();
}

// Run `edit` on a fresh copy of the column database, then expect load() to
// fail with a message containing `expected`.
void expectRefusal(const std::string &name, const std::function<void(const h5::File &)> &edit,
                   const std::string &expected) {
  const std::string path = dir + "/broken_" + name + ".h5";
  if (rank == 0) {
    writeColumn(path);
    if (edit) {
      h5::File f = h5::File::openReadWrite(path);
      edit(f);
    }
  }
  MPI_Barrier(PETSC_COMM_WORLD);
  const std::string text = rcfd::test::loadRefusal(path);
  if (text.find(expected) == std::string::npos)
    rcfd::test::fail(__FILE__, __LINE__,
                     name + ": expected an error containing '" + expected + "', got '" + text + "'");
}

void replaceDataset(const h5::File &f, const std::string &name, const std::vector<double> &v) {
  H5Ldelete(f.id(), name.c_str(), H5P_DEFAULT);
  f.write(name, v);
}

void handMadeColumn() {
  const std::string path = dir + "/column.h5";
  if (rank == 0) writeColumn(path);
  MPI_Barrier(PETSC_COMM_WORLD);
  std::unique_ptr<Database> db;
  RCFD_CHECK(Database::load(PETSC_COMM_WORLD, path, DatabaseLoadOptions{}, &db) == 0);
  if (!db) return;
  RCFD_CHECK(db->numFrames() == 2);
  RCFD_CHECK(db->mesh().numCells() == 3);
  FractionSet set = rcfd::test::fractionSet({1e-3, 2e-3}, {0.5, 0.5});
  FractionState st;
  st.create(db->layout(), 2);
  setNatural(*db, st, {1, 2, 3, 4, 5, 6});
  ShiftOperator shift;
  RunContext ctx{*db, set, 1440.0};
  RCFD_CHECK(shift.setUp(ctx) == 0);
  StepInfo step;
  step.frame = 0;
  RCFD_CHECK(shift.apply(step, st) == 0);
  const auto m = gatherNatural(*db, st.masses(), 2);
  // Hand-computed: cell0 = 0.5 (1,2); cell1 = 0.5 (1,2) + 0.25 (3,4); cell2 = 0.75 (3,4) + (5,6).
  const double expected[6] = {0.5, 1.0, 1.25, 2.0, 7.25, 9.0};
  for (int k = 0; k < 6; ++k) RCFD_CHECK_CLOSE(m[k], expected[k], 1e-15);
  step.frame = 1; // identity
  shift.apply(step, st);
  const auto same = gatherNatural(*db, st.masses(), 2);
  for (int k = 0; k < 6; ++k) RCFD_CHECK(same[k] == m[k]);
}

void permutation() {
  BoxSpec s;
  s.nx = 4;
  s.ny = 3;
  s.nz = 5;
  const Mesh mesh = rcfd::test::boxMesh(s);
  const int n = mesh.numCells();
  // pi(c) = (7 c + 3) mod 60 is a bijection since gcd(7, 60) = 1.
  auto pi = [n](int c) { return (7 * c + 3) % n; };
  const std::string path = dir + "/permutation.h5";
  if (rank == 0) {
    DatabaseFileWriter w(path, mesh, DatabaseMetadata{});
    FrameRecord f;
    f.alphaS.assign(n, 0.5);
    std::vector<int32_t> dest(n), src(n);
    for (int c = 0; c < n; ++c) dest[c] = pi(c), src[c] = c;
    f.shift = shiftFromTransfers(n, dest, src, std::vector<double>(n, 1.0));
    w.append(f);
    w.finish();
  }
  MPI_Barrier(PETSC_COMM_WORLD);
  std::unique_ptr<Database> db;
  RCFD_CHECK(Database::load(PETSC_COMM_WORLD, path, DatabaseLoadOptions{}, &db) == 0);
  if (!db) return;
  const int nf = 3;
  FractionSet set = rcfd::test::fractionSet({1e-3, 2e-3, 3e-3}, {0.2, 0.3, 0.5});
  FractionState st;
  st.create(db->layout(), nf);
  std::vector<double> start(n * nf);
  std::iota(start.begin(), start.end(), 1.0);
  setNatural(*db, st, start);
  ShiftOperator shift;
  RunContext ctx{*db, set, 1440.0};
  shift.setUp(ctx);
  shift.apply(StepInfo{}, st);
  const auto m = gatherNatural(*db, st.masses(), nf);
  for (int c = 0; c < n; ++c)
    for (int i = 0; i < nf; ++i) RCFD_CHECK(m[pi(c) * nf + i] == start[c * nf + i]);
}

void brokenFiles() {
  expectRefusal("missing", [](const h5::File &f) { std::remove(f.path().c_str()); },
                "does not exist");
  if (rank == 0) {
    FILE *t = std::fopen((dir + "/text.h5").c_str(), "w");
    std::fputs("not hdf5\n", t);
    std::fclose(t);
  }
  MPI_Barrier(PETSC_COMM_WORLD);
  {
    std::unique_ptr<Database> db;
    const PetscErrorCode ierr =
        Database::load(PETSC_COMM_WORLD, dir + "/text.h5", DatabaseLoadOptions{}, &db);
    char *msg = nullptr;
    PetscErrorMessage(ierr, nullptr, &msg);
    RCFD_CHECK(ierr != 0 && msg && std::string(msg).find("is not an HDF5 file") != std::string::npos);
  }
  expectRefusal("format", [](const h5::File &f) { f.writeAttr("/", "format", std::string("other")); },
                "is not an rcfd database");
  expectRefusal("version", [](const h5::File &f) { f.writeAttr("/", "format_version", 99LL); },
                "has format version 99, this rcfd reads versions 1 to 3");
  expectRefusal("metadata", [](const h5::File &f) { H5Ldelete(f.id(), "/metadata", H5P_DEFAULT); },
                "has no group '/metadata'");
  expectRefusal("frame_missing",
                [](const h5::File &f) { H5Ldelete(f.id(), "/frames/000001", H5P_DEFAULT); },
                "group /frames/000001 is missing");
  expectRefusal("alpha_size",
                [](const h5::File &f) { replaceDataset(f, "/frames/000000/alpha_s", {0.1, 0.2}); },
                "alpha_s has 2 values but the mesh has 3 cells");
  expectRefusal("alpha_nan",
                [](const h5::File &f) { replaceDataset(f, "/frames/000001/alpha_s", {0.1, NAN, 0.2}); },
                "expected a number in [0, 1]");
  expectRefusal("negative_share",
                [](const h5::File &f) {
                  replaceDataset(f, "/frames/000001/shift_val", {1.0, -1.0, 1.0});
                },
                "expected a non-negative share");
  expectRefusal("column_sum",
                [](const h5::File &f) { replaceDataset(f, "/frames/000001/shift_val", {1.0, 0.9, 1.0}); },
                "shift column of cell 1 sums to 0.9");
  expectRefusal("mesh_size",
                [](const h5::File &f) { f.writeAttr("/mesh", "box_cells", std::vector<long long>{1, 1, 4}); },
                "= 4 cells");
  expectRefusal("dt", [](const h5::File &f) { f.writeAttr("/metadata", "dt_rec", -1.0); },
                "dt_rec must be a positive number of seconds");
}

// The public writer (rcfd/database.hpp): the same file as the internal one,
// its refusals as PETSc errors with their sentence.
void publicWriter() {
  if (rank == 0) {
    const std::string internal = dir + "/column.h5", path = dir + "/column-public.h5";
    DatabaseWriter w;
    RCFD_CHECK(w.append(FrameRecord{}) == PETSC_ERR_ORDER); // not created yet
    RCFD_CHECK(w.create(path, column3(), DatabaseMetadata{}, 2) == 0);
    RCFD_CHECK(w.setNote("dt_rec", "1") == PETSC_ERR_ARG_WRONG); // a format attribute
    FrameRecord f0;
    f0.alphaS = {0.4, 0.4, 0.1};
    f0.shift = shiftFromTransfers(3, {0, 1, 1, 2, 2}, {0, 0, 1, 1, 2}, {1, 1, 1, 3, 1});
    FrameRecord f1;
    f1.alphaS = {0.2, 0.3, 0.4};
    f1.shift = shiftFromTransfers(3, {}, {}, {});
    FrameRecord wrong;
    wrong.alphaS = {0.1};
    RCFD_CHECK(w.append(wrong) == PETSC_ERR_ARG_WRONG);
    RCFD_CHECK(w.append(f0) == 0 && w.append(f1) == 0 && w.numFrames() == 2);
    RCFD_CHECK(w.finish() == 0);
    DatabaseHeader a, b;
    RCFD_CHECK(Database::readHeader(PETSC_COMM_SELF, internal, DatabaseLoadOptions{}, &a) == 0);
    RCFD_CHECK(Database::readHeader(PETSC_COMM_SELF, path, DatabaseLoadOptions{}, &b) == 0);
    RCFD_CHECK(!a.identity.empty() && a.identity == b.identity);
    DatabaseWriter empty;
    RCFD_CHECK(empty.create(dir + "/empty.h5", column3(), DatabaseMetadata{}) == 0);
    RCFD_CHECK(empty.finish() == PETSC_ERR_ARG_WRONG);
    char *why = nullptr;
    PetscErrorMessage(PETSC_ERR_ARG_WRONG, nullptr, &why);
    RCFD_CHECK(why && std::string(why) == "a database needs at least one frame");
  }
  MPI_Barrier(PETSC_COMM_WORLD);
}

} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  int size;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  dir = (argc > 1 ? argv[1] : std::string(".")) + "/database_np" + std::to_string(size);
  if (rank == 0 && std::system(("mkdir -p '" + dir + "'").c_str()) != 0) return 1;
  MPI_Barrier(PETSC_COMM_WORLD);
  handMadeColumn();
  permutation();
  brokenFiles();
  publicWriter();
  const int total = rcfd::test::globalFailures();
  PetscFinalize();
  return total == 0 ? 0 : 1;
}
