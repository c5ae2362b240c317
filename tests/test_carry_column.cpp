// The `column` carry kind (src/operator/swap/carry_column.cpp) on a box of
// 4 x 2 x 12 cells whose frames are a bed with a bubble, the same bed two
// cells higher, and a bed whose bubble sits in another column:
//  - a state that already has the target's bulk comes back bit for bit, and a
//    step without a jump changes nothing;
//  - a layered state carried onto the shifted copy of its own bulk keeps its
//    layers: every cell holds what the cell two below held;
//  - across columns (the bubble moved): every fraction's total kept to 1e-14,
//    no negative mass, the bulk of the next frame matched to 1e-12, delta z
//    kept to 2 %;
//  - the state carried on the ranks of the test equals, bit for bit, the one
//    carried on one rank (the database loaded on PETSC_COMM_SELF);
//  - one carry, jump after jump onto lower, shifted and higher beds: the
//    state's bound said (only the occupied rows gathered and computed) or
//    not, the same bits, every row above the bound it leaves empty;
//  - gravity along no axis of the mesh is refused with one sentence;
//  - OccupiedGather follows a layout made again in the same object (another
//    partition at the same address, as at a database switch).
// Runs at 1 and 2 ranks.
#include "check.hpp"
#include "box_meshes.hpp"
#include "fraction_sets.hpp"
#include "registry_helpers.hpp"
#include "rcfd/run.hpp"
#include "scoped_options.hpp"
#include "state_access.hpp"
#include "base/petsc_compat.hpp"
#include "database/database_file_writer.hpp"

#include <cmath>

using namespace rcfd;
using rcfd::test::gatherNatural;
using rcfd::test::setNatural;

namespace {

std::string dir;
constexpr double kRho = 1440.0;
constexpr int kNf = 2;

const BoxSpec kBox = [] {
  BoxSpec s;
  s.nx = 4;
  s.ny = 2;
  s.nz = 12;
  s.length = {0.04, 0.02, 0.12};
  return s;
}();

int level(const Vec3 &x) { return static_cast<int>(x[2] / 0.01); }

// alpha 0.55 in the rows [bottom, bottom + 8), a bubble (0.05) at (bi, bj, bottom + bk).
std::vector<double> bed(const Mesh &mesh, int bottom, int bi, int bj, int bk) {
  std::vector<double> alpha(mesh.numCells(), 0.0);
  for (int c = 0; c < mesh.numCells(); ++c) {
    const Vec3 &x = mesh.cellCentre[c];
    const int i = static_cast<int>(x[0] / 0.01), j = static_cast<int>(x[1] / 0.01), k = level(x);
    if (k >= bottom && k < bottom + 8) alpha[c] = (i == bi && j == bj && k == bottom + bk) ? 0.05 : 0.55;
  }
  return alpha;
}

const std::vector<std::vector<double>> frames(const Mesh &mesh) {
  return {bed(mesh, 0, 1, 0, 3), bed(mesh, 2, 1, 0, 3), bed(mesh, 0, 3, 1, 5)};
}

std::unique_ptr<Database> load(MPI_Comm comm, const std::string &name, const Vec3 &gravity) {
  const std::string path = dir + "/" + name + ".h5";
  const Mesh mesh = rcfd::test::boxMesh(kBox);
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0 && comm == PETSC_COMM_WORLD) {
    DatabaseMetadata meta;
    meta.gravity = gravity;
    DatabaseFileWriter w(path, mesh, meta);
    for (const auto &alpha : frames(mesh)) {
      FrameRecord f;
      f.alphaS = alpha;
      f.shift = shiftFromTransfers(mesh.numCells(), {}, {}, {});
      w.append(f);
    }
    w.finish();
  }
  MPI_Barrier(PETSC_COMM_WORLD);
  std::unique_ptr<Database> db;
  PetscCallAbort(PETSC_COMM_WORLD, Database::load(comm, path, DatabaseLoadOptions{}, &db));
  return db;
}

// Frame `alpha`'s bulk with the fine share `fine(height level)`.
template <class Share>
std::vector<double> composed(const Mesh &mesh, const std::vector<double> &alpha, Share fine) {
  std::vector<double> m;
  for (int c = 0; c < mesh.numCells(); ++c) {
    const double M = kRho * alpha[c] * mesh.cellVolume[c], y = fine(level(mesh.cellCentre[c]));
    m.push_back(y * M);
    m.push_back(M - y * M);
  }
  return m;
}

// What one carry of the state `start` from frame 0 onto frame `next` gives.
std::vector<double> carried(const Database &db, const std::vector<double> &start, int next, bool jump = true,
                            const std::string &kind = "column") {
  const FractionSet set = rcfd::test::fractionSet({1e-3, 3e-3}, {0.5, 0.5});
  const RunContext ctx{db, set, kRho};
  const OperatorRegistry registry = OperatorRegistry::withBuiltins();
  auto carry = created(registry, "carry");
  {
    ScopedOptions options("-carry_type " + kind);
    PetscCallAbort(PETSC_COMM_WORLD, carry->setFromOptions(db.layout().comm()));
  }
  PetscCallAbort(PETSC_COMM_WORLD, carry->setUp(ctx));
  FractionState st;
  PetscCallAbort(PETSC_COMM_WORLD, st.create(db.layout(), kNf));
  setNatural(db, st, start);
  StepInfo step;
  step.dt = 5e-3;
  step.nextFrame = next;
  step.jump = jump;
  PetscCallAbort(PETSC_COMM_WORLD, carry->apply(step, st));
  return gatherNatural(db, st.masses(), kNf);
}

double deltaZ(const Mesh &mesh, const std::vector<double> &m) {
  double mass[kNf] = {}, moment[kNf] = {};
  for (int c = 0; c < mesh.numCells(); ++c)
    for (int i = 0; i < kNf; ++i) mass[i] += m[c * kNf + i], moment[i] += m[c * kNf + i] * mesh.cellCentre[c][2];
  return moment[0] / mass[0] - moment[1] / mass[1];
}

// Relative change of the worst fraction total, the smallest mass, and the
// bulk mismatch against `alpha` (sum |M - rho alpha V| / sum rho alpha V).
struct Balance {
  double total = 0.0, lowest = 0.0, mismatch = 0.0;
};

Balance balance(const Mesh &mesh, const std::vector<double> &start, const std::vector<double> &m,
                const std::vector<double> &alpha) {
  Balance b;
  double before[kNf] = {}, after[kNf] = {}, off = 0.0, bulk = 0.0;
  for (int c = 0; c < mesh.numCells(); ++c) {
    double M = 0.0;
    for (int i = 0; i < kNf; ++i) {
      before[i] += start[c * kNf + i];
      after[i] += m[c * kNf + i];
      M += m[c * kNf + i];
      b.lowest = std::fmin(b.lowest, m[c * kNf + i]);
    }
    off += std::fabs(M - kRho * alpha[c] * mesh.cellVolume[c]);
    bulk += kRho * alpha[c] * mesh.cellVolume[c];
  }
  for (int i = 0; i < kNf; ++i) b.total = std::fmax(b.total, std::fabs(after[i] / before[i] - 1.0));
  b.mismatch = off / bulk;
  return b;
}

void matchingStateUnchanged() {
  auto db = load(PETSC_COMM_WORLD, "matching", {0.0, 0.0, -9.81});
  const auto alpha = frames(db->mesh());
  const auto start = composed(db->mesh(), alpha[0], [](int k) { return 0.2 + 0.07 * k; });
  RCFD_CHECK(carried(*db, start, 0) == start);        // onto its own bulk: the same bits
  RCFD_CHECK(carried(*db, start, 1, false) == start); // no jump: nothing
  const auto once = carried(*db, start, 2);
  RCFD_CHECK(once != start);
  RCFD_CHECK(carried(*db, once, 2) == once); // carried again onto the bulk it already has
}

void layersKept() {
  auto db = load(PETSC_COMM_WORLD, "layers", {0.0, 0.0, -9.81});
  const Mesh &mesh = db->mesh();
  const auto alpha = frames(mesh);
  const auto start = composed(mesh, alpha[0], [](int k) { return k < 4 ? 0.0 : 1.0; }); // coarse below fine
  const auto m = carried(*db, start, 1);
  double worst = 0.0;
  for (int c = 0; c < mesh.numCells(); ++c) {
    const int k = level(mesh.cellCentre[c]);
    for (int i = 0; i < kNf; ++i) {
      const double expected = k < 2 ? 0.0 : start[(c - 2 * kBox.nx * kBox.ny) * kNf + i]; // the cell two below
      worst = std::fmax(worst, std::fabs(m[c * kNf + i] - expected) / (kRho * 0.55 * mesh.cellVolume[c]));
    }
  }
  const Balance b = balance(mesh, start, m, alpha[1]);
  PetscPrintf(PETSC_COMM_WORLD, "layers two cells up: largest difference %.1e of a full cell, delta z %.6f -> %.6f m\n",
              worst, deltaZ(mesh, start), deltaZ(mesh, m));
  RCFD_CHECK(worst < 1e-13);
  RCFD_CHECK(b.total < 1e-14 && b.lowest >= 0.0 && b.mismatch < 1e-12);
}

void acrossColumns() {
  auto db = load(PETSC_COMM_WORLD, "across", {0.0, 0.0, -9.81});
  const Mesh &mesh = db->mesh();
  const auto alpha = frames(mesh);
  const auto start = composed(mesh, alpha[0], [](int k) { return 0.1 + 0.1 * k; });
  const auto m = carried(*db, start, 2), remapped = carried(*db, start, 2, true, "remap");
  const Balance b = balance(mesh, start, m, alpha[2]), r = balance(mesh, start, remapped, alpha[2]);
  const double dz0 = deltaZ(mesh, start), dz = deltaZ(mesh, m), dzRemap = deltaZ(mesh, remapped);
  PetscPrintf(PETSC_COMM_WORLD,
              "bubble to another column: totals %.1e, smallest %.1e, bulk mismatch %.1e (remap %.1e); "
              "delta z %.6f -> %.6f m (remap %.6f)\n", b.total, b.lowest, b.mismatch, r.mismatch, dz0, dz, dzRemap);
  RCFD_CHECK(b.total < 1e-14);
  RCFD_CHECK(b.lowest >= 0.0);
  RCFD_CHECK(b.mismatch < 1e-12);
  RCFD_CHECK(std::fabs(dz / dz0 - 1.0) < 0.02); // 1.1 %: the column that lost its bubble settles

  // One rank: the database on PETSC_COMM_SELF, the same carry.
  auto self = load(PETSC_COMM_SELF, "across", {0.0, 0.0, -9.81});
  RCFD_CHECK(carried(*self, start, 2) == m);
}

// One carry, jump after jump (its buffers kept between jumps): onto a lower
// bed, across columns, onto a higher bed.  The state's bound said before each
// jump (only the occupied rows travel) or not (every row): the same bits;
// after each jump every own row at or above the bound the carry says is empty.
std::vector<std::vector<double>> jumps(const Database &db, const std::vector<double> &start, bool sayBound,
                                       bool *emptyAbove) {
  const FractionSet set = rcfd::test::fractionSet({1e-3, 3e-3}, {0.5, 0.5});
  const RunContext ctx{db, set, kRho};
  auto carry = created(OperatorRegistry::withBuiltins(), "carry");
  {
    ScopedOptions options("-carry_type column");
    PetscCallAbort(PETSC_COMM_WORLD, carry->setFromOptions(db.layout().comm()));
  }
  PetscCallAbort(PETSC_COMM_WORLD, carry->setUp(ctx));
  FractionState st;
  PetscCallAbort(PETSC_COMM_WORLD, st.create(db.layout(), kNf));
  setNatural(db, st, start);
  std::vector<std::vector<double>> out;
  for (int next : {0, 2, 1}) {
    const PetscScalar *m;
    PetscInt end = db.layout().numLocal();
    PetscCallAbort(PETSC_COMM_WORLD, VecGetArrayRead(st.masses(), &m));
    while (sayBound && end > 0 && m[(end - 1) * kNf] == 0.0 && m[(end - 1) * kNf + 1] == 0.0) --end;
    PetscCallAbort(PETSC_COMM_WORLD, VecRestoreArrayRead(st.masses(), &m));
    PetscCallAbort(PETSC_COMM_WORLD, st.setOccupiedEnd(end));
    StepInfo step;
    step.dt = 5e-3;
    step.nextFrame = next;
    step.jump = true;
    PetscCallAbort(PETSC_COMM_WORLD, carry->apply(step, st));
    PetscCallAbort(PETSC_COMM_WORLD, st.occupiedEnd(&end));
    PetscCallAbort(PETSC_COMM_WORLD, VecGetArrayRead(st.masses(), &m));
    for (PetscInt k = end * kNf; k < db.layout().numLocal() * kNf; ++k) *emptyAbove = *emptyAbove && m[k] == 0.0;
    PetscCallAbort(PETSC_COMM_WORLD, VecRestoreArrayRead(st.masses(), &m));
    out.push_back(gatherNatural(db, st.masses(), kNf));
  }
  return out;
}

// Gravity along -z: a column's cells ascend in natural order with its levels;
// along +z they descend, so a column's levels reach cells above the bound.
void occupiedCellsOnly(const std::string &name, const Vec3 &gravity) {
  auto db = load(PETSC_COMM_WORLD, name, gravity);
  const auto alpha = frames(db->mesh());
  const auto start = composed(db->mesh(), alpha[1], [](int k) { return 0.05 + 0.08 * k; }); // the higher bed
  bool emptyAbove = true;
  const auto bounded = jumps(*db, start, true, &emptyAbove), full = jumps(*db, start, false, &emptyAbove);
  RCFD_CHECK(bounded == full);
  RCFD_CHECK(emptyAbove);
  RCFD_CHECK(bounded[0] != start && bounded[1] != bounded[0] && bounded[2] != bounded[1]);
  auto self = load(PETSC_COMM_SELF, name, gravity);
  RCFD_CHECK(jumps(*self, start, true, &emptyAbove) == full); // 1 rank == the ranks of the test
}

void tiltedGravityRefused() {
  auto db = load(PETSC_COMM_WORLD, "tilted", {1.0, 0.0, -9.81});
  const FractionSet set = rcfd::test::fractionSet({1e-3, 3e-3}, {0.5, 0.5});
  const RunContext ctx{*db, set, kRho};
  auto carry = created(OperatorRegistry::withBuiltins(), "carry");
  ScopedOptions options("-carry_type column");
  PetscCallAbort(PETSC_COMM_WORLD, carry->setFromOptions(PETSC_COMM_WORLD));
  PetscCallAbort(PETSC_COMM_WORLD, carry->setUp(ctx));
  FractionState st;
  PetscCallAbort(PETSC_COMM_WORLD, st.create(db->layout(), kNf));
  StepInfo step;
  step.nextFrame = 1;
  step.jump = true;
  ErrorCapture error;
  RCFD_CHECK(carry->apply(step, st) == PETSC_ERR_USER_INPUT);
  RCFD_CHECK(error.message() == "-carry_type column needs gravity along one of the mesh's axes; database '" + dir +
                                    "/tilted.h5' does not have it (choose -carry_type remap)");
}

} // namespace

// OccupiedGather after the layout it gathered for is made again in the same object (the same
// address, as a layout made at a database switch may be on some ranks): with another partition
// (METIS weighted by work) it must gather by the new one, every cell's value in its place.
void gatherFollowsLayoutContent() {
  const MPI_Comm comm = PETSC_COMM_WORLD;
  const Mesh mesh = rcfd::test::boxMesh(kBox);
  Layout layout;
  OccupiedGather gather;
  std::vector<PetscInt> firstStarts;
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<int> work(mesh.numCells(), 1);
    if (pass == 1) // the top half a hundred times the work: the ranks' shares move
      for (int c = 0; c < mesh.numCells(); ++c) work[c] = level(mesh.cellCentre[c]) >= 6 ? 100 : 1;
    PetscCallAbort(comm, Layout::create(comm, mesh, &layout, &work));
    if (pass == 0) firstStarts = layout.rowStarts();
    OwnedVec v;
    PetscCallAbort(comm, VecCreateMPI(comm, layout.numLocal(), layout.numCells(), v.put()));
    for (PetscInt r = layout.rowStart(); r < layout.rowEnd(); ++r)
      PetscCallAbort(comm, VecSetValue(v, r, static_cast<double>(layout.naturalCell(r) + 1), INSERT_VALUES));
    PetscCallAbort(comm, VecAssemblyBegin(v));
    PetscCallAbort(comm, VecAssemblyEnd(v));
    PetscCallAbort(comm, gather.gather(layout, 1, v, layout.numLocal()));
    int wrong = 0;
    for (PetscInt c = 0; c < mesh.numCells(); ++c) wrong += gather.values()[c] != static_cast<double>(c + 1);
    RCFD_CHECK(wrong == 0);
  }
  PetscMPIInt size;
  MPI_Comm_size(comm, &size);
  if (size > 1) RCFD_CHECK(firstStarts != layout.rowStarts()); // else the test proves nothing
}

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  dir = rcfd::test::rankCountDirectory(argc, argv, "carry_column");
  if (dir.empty()) return 1;
  matchingStateUnchanged();
  layersKept();
  acrossColumns();
  occupiedCellsOnly("bounds", {0.0, 0.0, -9.81});
  occupiedCellsOnly("bounds-up", {0.0, 0.0, 9.81});
  tiltedGravityRefused();
  gatherFollowsLayoutContent();
  const int total = rcfd::test::globalFailures();
  PetscCall(PetscFinalize());
  return total == 0 ? 0 : 1;
}
