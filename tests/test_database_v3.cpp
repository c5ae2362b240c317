// Database format version 3 (docs/database-format.md): the file stores each
// frame's moving rows only.
//  - small.h5 written in version 2 and in version 3 (full precision and
//    weights quantised to 2^-16) loads into the same compact frames, entry for
//    entry, the same alpha_s and ghost rows, and replays all frames to the same
//    bits; readStoredFrame gives the same full CSR from both.
//  - An identity row left out of the file whose column also holds round-off
//    from another row is rescaled on load as a stored one is.
//  - Both versions have the same identity (the content hash of the full CSR).
//  - The version 3 file is smaller (the quantised one much smaller).
//  - Each kind of broken version 3 frame is refused with its sentence, also
//    one broken in a row or column that only one of 2 ranks reads (no hang).
// Runs at 1 and 2 ranks; argv[1] is the test-data directory with small.h5.
#include "base/h5.hpp"
#include "box_meshes.hpp"
#include "base/petsc_compat.hpp"
#include "check.hpp"
#include "database_copies.hpp"
#include "operator/moving_rows.hpp"
#include "state_access.hpp"
#include "database/database_file_writer.hpp"

#include <filesystem>
#include <functional>

using namespace rcfd;
namespace fs = std::filesystem;

namespace {

int rank = 0;
std::string dir;

bool sameFrame(const CompactFrame &a, const CompactFrame &b) {
  return a.rows == b.rows && a.group == b.group && a.firstEntry == b.firstEntry && a.ptr == b.ptr &&
         a.offset == b.offset && a.col == b.col && a.val == b.val && a.quantum == b.quantum;
}

// Every frame applied in turn to masses that depend on the natural cell only,
// gathered in natural order.
PetscErrorCode replay(const Database &db, std::vector<double> *natural) {
  constexpr int nf = 2;
  const Layout &L = db.layout();
  MovingRows moving;
  OwnedVec x;
  PetscFunctionBeginUser;
  PetscCall(moving.setUp(db, nf));
  PetscCall(VecCreateMPI(L.comm(), L.numLocal() * nf, L.numCells() * nf, x.put()));
  PetscCall(VecSetBlockSize(x, nf));
  PetscScalar *m;
  PetscCall(VecGetArrayWrite(x, &m));
  for (PetscInt r = 0; r < L.numLocal(); ++r)
    for (int i = 0; i < nf; ++i) m[r * nf + i] = 1e-3 * (1 + (L.ownedNatural()[r] * 7919 + i * 104729) % 1000);
  PetscCall(VecRestoreArrayWrite(x, &m));
  for (int k = 0; k < db.numFrames(); ++k) PetscCall(moving.apply(k, x));
  PetscCall(L.gatherToAll(nf, x, natural));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The two files load, frame for frame, into the same database and replay to the same bits.
PetscErrorCode sameDatabase(const std::string &v2, const std::string &v3) {
  std::unique_ptr<Database> a, b;
  PetscFunctionBeginUser;
  PetscCall(Database::load(PETSC_COMM_WORLD, v2, DatabaseLoadOptions{}, &a));
  PetscCall(Database::load(PETSC_COMM_WORLD, v3, DatabaseLoadOptions{}, &b));
  RCFD_CHECK(a->formatVersion() == 2 && b->formatVersion() == 3);
  RCFD_CHECK(a->identity() == b->identity());
  RCFD_CHECK(a->numFrames() == b->numFrames() && a->numFrames() > 0);
  RCFD_CHECK(a->ghostRows() == b->ghostRows());
  int differ = 0;
  size_t entries = 0;
  for (int k = 0; k < a->numFrames() && k < b->numFrames(); ++k) {
    differ += !sameFrame(a->frame(k), b->frame(k));
    entries += b->frame(k).numEntries();
    PetscBool equal;
    PetscCall(VecEqual(a->alphaS(k), b->alphaS(k), &equal));
    differ += !equal;
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &differ, 1, MPI_INT, MPI_SUM, PETSC_COMM_WORLD));
  RCFD_CHECK(differ == 0);
  RCFD_CHECK(entries > 0);
  std::vector<double> x2, x3;
  PetscCall(replay(*a, &x2));
  PetscCall(replay(*b, &x3));
  RCFD_CHECK(x2.size() == x3.size() && !x2.empty() && x2 == x3);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s and %s: %d frames, %zu bytes against %zu, %d frames differ\n",
                        fs::path(v2).filename().c_str(), fs::path(v3).filename().c_str(), a->numFrames(),
                        (size_t)fs::file_size(v2), (size_t)fs::file_size(v3), differ));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// A column that also holds round-off from another row: its identity row
// T(0, 0) = 1 is left out of the version 3 file but rescaled on load to
// 1 / (1 + 1e-12), so it becomes a moving row, as it is from version 2.
PetscErrorCode roundOffColumn() {
  const std::string v2 = dir + "/roundoff_v2.h5", v3 = dir + "/roundoff_v3.h5";
  PetscFunctionBeginUser;
  if (rank == 0) {
    BoxSpec s;
    s.nx = s.ny = 1;
    s.nz = 4;
    FrameRecord f;
    f.alphaS = {0.5, 0.4, 0.3, 0.0};
    f.shift.n = 4;
    f.shift.rowPtr = {0, 1, 3, 5, 6};
    f.shift.col = {0, 0, 1, 1, 2, 3};
    f.shift.val = {1.0, 1e-12, 0.5, 0.5, 1.0, 1.0};
    for (const auto &[path, version] : {std::pair{v2, 2LL}, std::pair{v3, 3LL}}) {
      DatabaseFileWriter w(path, rcfd::test::boxMesh(s), DatabaseMetadata{}, version);
      w.append(f);
      w.finish();
    }
  }
  PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
  PetscCall(sameDatabase(v2, v3));
  std::unique_ptr<Database> db;
  PetscCall(Database::load(PETSC_COMM_WORLD, v3, DatabaseLoadOptions{}, &db));
  long long moving = static_cast<long long>(db->frame(0).numRows());
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &moving, 1, MPI_LONG_LONG, MPI_SUM, PETSC_COMM_WORLD));
  RCFD_CHECK(moving == 3); // rows 0 (rescaled), 1 and 2; row 3 stays an identity row
  PetscFunctionReturn(PETSC_SUCCESS);
}

// readStoredFrame (rcfd coarsen's reader) gives the same full CSR from both.
void sameStoredFrames(const std::string &v2, const std::string &v3, int cells) {
  const h5::File a = h5::File::openRead(v2, MPI_COMM_NULL), b = h5::File::openRead(v3, MPI_COMM_NULL);
  const int K = static_cast<int>(a.readAttrInt("/frames", "num_frames"));
  int differ = 0;
  for (int k = 0; k < K; ++k) {
    const FrameRecord x = readStoredFrame(a, k, cells), y = readStoredFrame(b, k, cells);
    differ += x.alphaS != y.alphaS || x.shift.rowPtr != y.shift.rowPtr || x.shift.col != y.shift.col ||
              x.shift.val != y.shift.val;
  }
  RCFD_CHECK(K > 0 && differ == 0);
}

// A copy of `good` with frame `frame` edited by `edit` must be refused with `expected`.
void expectRefusal(const std::string &good, const std::string &name,
                   const std::function<void(const h5::File &, const std::string &)> &edit,
                   const std::string &expected, int frame = 5) {
  const std::string path = dir + "/broken_" + name + ".h5";
  if (rank == 0) {
    fs::copy_file(good, path, fs::copy_options::overwrite_existing);
    h5::File f = h5::File::openReadWrite(path);
    edit(f, frameGroup(frame) + "/");
  }
  MPI_Barrier(PETSC_COMM_WORLD);
  const std::string text = test::loadRefusal(path);
  if (text.find(expected) == std::string::npos)
    rcfd::test::fail(__FILE__, __LINE__, name + ": expected an error containing '" + expected + "', got '" + text + "'");
}

template <typename T> void edited(const h5::File &f, const std::string &name, const std::function<void(std::vector<T> &)> &change) {
  auto v = f.read<T>(name);
  change(v);
  H5Ldelete(f.id(), name.c_str(), H5P_DEFAULT);
  f.write(name, v);
}

void brokenFramesRefused(const std::string &good, const std::string &quantised) {
  expectRefusal(good, "unsorted", [](const h5::File &f, const std::string &g) {
    edited<int32_t>(f, g + "moving_row", [](std::vector<int32_t> &r) { std::swap(r[1], r[2]); });
  }, "frame 5: moving_row is not ascending at position 2");
  expectRefusal(good, "row_outside", [](const h5::File &f, const std::string &g) {
    edited<int32_t>(f, g + "moving_row", [](std::vector<int32_t> &r) { r.back() = 400; });
  }, "names row 400, outside the mesh's 400 cells");
  expectRefusal(good, "ptr_decreasing", [](const h5::File &f, const std::string &g) {
    edited<int32_t>(f, g + "moving_row_ptr", [](std::vector<int32_t> &p) { p[1] = p.back(); });
  }, "expected non-decreasing offsets");
  expectRefusal(good, "ptr_length", [](const h5::File &f, const std::string &g) {
    edited<int32_t>(f, g + "moving_row_ptr", [](std::vector<int32_t> &p) { p.pop_back(); });
  }, "moving_row_ptr has");
  expectRefusal(good, "column_outside", [](const h5::File &f, const std::string &g) {
    edited<int32_t>(f, g + "shift_col", [](std::vector<int32_t> &c) { c[c.size() / 2] = 400; });
  }, "names cell 400, outside the mesh's 400 cells");
  expectRefusal(good, "missing_col", [](const h5::File &f, const std::string &g) {
    H5Ldelete(f.id(), (g + "shift_col").c_str(), H5P_DEFAULT);
  }, "frame 5: dataset shift_col is missing");
  expectRefusal(good, "short_val", [](const h5::File &f, const std::string &g) {
    edited<double>(f, g + "shift_val", [](std::vector<double> &v) { v.pop_back(); });
  }, "expected as many");
  // Broken in one row, which one rank reads (at 2 ranks the other reads
  // good rows and must not wait for ever): a negative weight, refused by the
  // rank reading it, and a weight too large, refused by the rank owning its
  // column (in a later batch of frames than the first).
  expectRefusal(good, "one_rank_weight", [](const h5::File &f, const std::string &g) {
    edited<double>(f, g + "shift_val", [](std::vector<double> &v) { v[0] = -v[0]; });
  }, "frame 5: shift entry (");
  expectRefusal(good, "one_rank_column", [](const h5::File &f, const std::string &g) {
    edited<double>(f, g + "shift_val", [](std::vector<double> &v) { v[0] += 0.5; });
  }, "frame 37: shift column of cell", 37);
  expectRefusal(quantised, "missing_quantum", [](const h5::File &f, const std::string &g) {
    H5Ldelete(f.id(), (g + "shift_quantum").c_str(), H5P_DEFAULT);
  }, "dataset shift_quantum is missing");
}

} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  const std::string data = argc > 1 ? argv[1] : ".", small = data + "/small.h5";
  dir = test::rankCountDirectory(argc, argv, "database_v3");
  RCFD_CHECK(!dir.empty());
  const std::string v2 = dir + "/v2.h5", v3 = dir + "/v3.h5", q2 = dir + "/q2.h5", q3 = dir + "/q3.h5";
  PetscCall(test::rewriteDatabase(small, v2, 0, 2));
  PetscCall(test::rewriteDatabase(small, v3, 0, 3));
  PetscCall(test::rewriteDatabase(small, q2, 16, 2));
  PetscCall(test::rewriteDatabase(small, q3, 16, 3));
  PetscCall(sameDatabase(v2, v3));
  PetscCall(sameDatabase(q2, q3));
  PetscCall(roundOffColumn());
  if (rank == 0) {
    sameStoredFrames(v2, v3, 400);
    sameStoredFrames(q2, q3, 400);
    const h5::File a = h5::File::openRead(small, MPI_COMM_NULL), b = h5::File::openRead(v2, MPI_COMM_NULL);
    RCFD_CHECK(a.readAttrString("/", "content_hash") == b.readAttrString("/", "content_hash"));
    RCFD_CHECK(fs::file_size(v3) < fs::file_size(v2));
    RCFD_CHECK(fs::file_size(q3) < fs::file_size(v3));
  }
  brokenFramesRefused(v3, q3);
  PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
  const int result = RCFD_TEST_RESULT();
  PetscCall(PetscFinalize());
  return result;
}
