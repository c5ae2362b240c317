// Operators around the physics (test_drift.cpp checks the swap kernels):
//  - carry with -carry_type level after a jump: every fraction's total kept,
//    no negative mass, and the bulk mismatch with the next frame reduced;
//  - a carry kind a user registers by name is the one -carry_type selects,
//    and an unknown kind is refused with the known names;
//  - -drift_view ascii:FILE and -shift_view ascii:FILE write each view to its
//    file, with the drift velocities of the model;
//  - a face-swap operator written from the public headers (SwapOperator,
//    FaceExchange) conserves and mixes, through ghost cells at 2 ranks;
//  - the mass ledger stops a run whose pipeline holds a ShellOperator that
//    loses mass, with its sentence, while a conservative one, or one that
//    declares its loss, runs through.
// Runs at 1 and 2 ranks.  PETSc calls that must succeed use PetscCallAbort.
#include "check.hpp"
#include "box_meshes.hpp"
#include "fraction_sets.hpp"
#include "registry_helpers.hpp"
#include "rcfd/run.hpp"
#include "rcfd/swaps.hpp"
#include "scoped_options.hpp"
#include "state_access.hpp"
#include "base/petsc_compat.hpp"
#include "database/database_file_writer.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

using namespace rcfd;
using rcfd::test::gatherNatural;
using rcfd::test::setNatural;

namespace {

std::string dir;
constexpr double kRho = 1440.0;

bool contains(const std::string &text, const std::string &part) {
  return text.find(part) != std::string::npos;
}

std::string readFile(const std::string &path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A box of 4 x 1 x 12 cells, 1 cm each, filled to alpha 0.55 below the top
// two rows, with a bubble (alpha 0.05) in column x = 1 at height `bubble`.
const BoxSpec kBox = [] {
  BoxSpec s;
  s.nx = 4;
  s.ny = 1;
  s.nz = 12;
  s.length = {0.04, 0.01, 0.12};
  return s;
}();

std::vector<double> bedWithBubble(const Mesh &mesh, int bubble) {
  std::vector<double> alpha(mesh.numCells());
  for (int c = 0; c < mesh.numCells(); ++c) {
    const Vec3 &x = mesh.cellCentre[c];
    const int i = static_cast<int>(x[0] / 0.01), k = static_cast<int>(x[2] / 0.01);
    alpha[c] = k >= 10 ? 0.0 : (i == 1 && k == bubble) ? 0.05 : 0.55;
  }
  return alpha;
}

// Frames 0 and 1 of identity shifts whose bubble rises by one cell.
std::unique_ptr<Database> risingBubbleDb(const std::string &name) {
  const std::string path = dir + "/" + name + ".h5";
  const Mesh mesh = rcfd::test::boxMesh(kBox);
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0) {
    DatabaseFileWriter w(path, mesh, DatabaseMetadata{});
    for (int bubble : {4, 5}) {
      FrameRecord f;
      f.alphaS = bedWithBubble(mesh, bubble);
      f.shift = shiftFromTransfers(mesh.numCells(), {}, {}, {});
      w.append(f);
    }
    w.finish();
  }
  MPI_Barrier(PETSC_COMM_WORLD);
  std::unique_ptr<Database> db;
  PetscCallAbort(PETSC_COMM_WORLD, Database::load(PETSC_COMM_WORLD, path, DatabaseLoadOptions{}, &db));
  return db;
}

// Frame 0's bulk, with fine particles more common higher up.
std::vector<double> layeredMasses(const Mesh &mesh, const std::vector<double> &alpha) {
  std::vector<double> m;
  for (int c = 0; c < mesh.numCells(); ++c) {
    const double y = 0.2 + 0.6 * mesh.cellCentre[c][2] / 0.12, M = kRho * alpha[c] * mesh.cellVolume[c];
    for (double share : {y * 0.5, y * 0.5, 1.0 - y}) m.push_back(share * M);
  }
  return m;
}

// The given bulk with the inventory's composition everywhere.
std::vector<double> uniformMasses(const Mesh &mesh, const FractionSet &set, const std::vector<double> &alpha) {
  std::vector<double> m;
  for (int c = 0; c < mesh.numCells(); ++c)
    for (int i = 0; i < set.size(); ++i) m.push_back(set.massShare(i) * kRho * alpha[c] * mesh.cellVolume[c]);
  return m;
}

// Sum over cells of |M - rho alpha V|, relative to the bed's mass.
double bulkMismatch(const Mesh &mesh, const std::vector<double> &m, const std::vector<double> &alpha, int nf) {
  double off = 0.0, total = 0.0;
  for (int c = 0; c < mesh.numCells(); ++c) {
    double M = 0.0;
    for (int i = 0; i < nf; ++i) M += m[c * nf + i];
    const double target = kRho * alpha[c] * mesh.cellVolume[c];
    off += std::fabs(M - target);
    total += target;
  }
  return off / total;
}

std::vector<double> fractionTotals(const std::vector<double> &m, int nf) {
  std::vector<double> t(nf, 0.0);
  for (size_t k = 0; k < m.size(); ++k) t[k % nf] += m[k];
  return t;
}

StepInfo jumpStep() {
  StepInfo s;
  s.dt = 5e-3;
  s.frame = 0;
  s.nextFrame = 1;
  s.jump = true;
  return s;
}

// -carry_type level after the bubble rose: fraction totals to round-off, no
// negative mass, the mismatch with frame 1's bulk cut to a small part; a step
// without a jump changes nothing.
void carryLevel() {
  auto db = risingBubbleDb("carry_level");
  const Mesh &mesh = db->mesh();
  const FractionSet set = rcfd::test::fractionSet({1e-3, 1.5e-3, 3e-3}, {0.3, 0.3, 0.4});
  const RunContext ctx{*db, set, kRho};
  const OperatorRegistry registry = OperatorRegistry::withBuiltins();
  auto carry = created(registry, "carry");
  {
    ScopedOptions options("-carry_type level -carry_sweeps 40");
    PetscCallAbort(PETSC_COMM_WORLD, carry->setFromOptions(PETSC_COMM_WORLD));
  }
  RCFD_CHECK(carry->needed(ctx));
  PetscCallAbort(PETSC_COMM_WORLD, carry->setUp(ctx));
  FractionState st;
  PetscCallAbort(PETSC_COMM_WORLD, st.create(db->layout(), 3));
  const std::vector<double> alpha0 = bedWithBubble(mesh, 4), alpha1 = bedWithBubble(mesh, 5);
  const auto start = layeredMasses(mesh, alpha0);
  setNatural(*db, st, start);

  StepInfo plain = jumpStep();
  plain.jump = false;
  plain.nextFrame = 0;
  PetscCallAbort(PETSC_COMM_WORLD, carry->apply(plain, st));
  RCFD_CHECK(gatherNatural(*db, st.masses(), 3) == start);

  PetscCallAbort(PETSC_COMM_WORLD, carry->apply(jumpStep(), st));
  const auto m = gatherNatural(*db, st.masses(), 3);
  const auto before = fractionTotals(start, 3), after = fractionTotals(m, 3);
  double worstTotal = 0.0, lowest = 0.0;
  for (int i = 0; i < 3; ++i) worstTotal = std::fmax(worstTotal, std::fabs(after[i] / before[i] - 1.0));
  for (double v : m) lowest = std::fmin(lowest, v);
  const double mismatchBefore = bulkMismatch(mesh, start, alpha1, 3);
  const double mismatchAfter = bulkMismatch(mesh, m, alpha1, 3);
  PetscPrintf(PETSC_COMM_WORLD,
              "carry level: bulk mismatch %.4f -> %.4f, fraction totals %.1e, smallest mass %.1e\n",
              mismatchBefore, mismatchAfter, worstTotal, lowest);
  // Two cells off by 0.5 rho V each, of 39 cells at 0.55 and the bubble at 0.05.
  RCFD_CHECK_CLOSE(mismatchBefore, 2 * 0.5 / (39 * 0.55 + 0.05), 1e-12);
  RCFD_CHECK(mismatchAfter < 0.15 * mismatchBefore); // 0.125 of it after 40 sweeps
  RCFD_CHECK(worstTotal < 1e-14);
  RCFD_CHECK(lowest >= 0.0);
}

// A user's carry kind: it holds the state and counts what it was given.
struct Tally {
  int calls = 0, jumps = 0, fractions = 0;
};

class HoldCarry : public CarryKind {
public:
  explicit HoldCarry(Tally &t) : tally(t) {}
  std::string type() const override { return "hold"; }
  PetscErrorCode apply(const CarryContext &ctx, const StepInfo &step, FractionState &) override {
    ++tally.calls;
    tally.jumps += step.jump;
    tally.fractions = ctx.numFractions;
    return PETSC_SUCCESS;
  }
  PetscErrorCode view(PetscViewer viewer) const override {
    return PetscViewerASCIIPrintf(viewer, "carry: held at %d jumps\n", tally.jumps);
  }

private:
  Tally &tally;
};

void userCarryKind() {
  auto db = risingBubbleDb("carry_user");
  const FractionSet set = rcfd::test::fractionSet({1e-3, 3e-3}, {0.5, 0.5});
  const RunContext ctx{*db, set, kRho};
  Tally tally;
  OperatorRegistry registry = OperatorRegistry::withBuiltins();
  registered(registry.carryKinds(), "hold", [&tally] { return std::make_unique<HoldCarry>(tally); },
                            "keeps the state as it is");
  auto run = [&](const std::string &kind, std::vector<double> *result) {
    auto carry = created(registry, "carry");
    {
      ScopedOptions options("-carry_type " + kind);
      PetscCallAbort(PETSC_COMM_WORLD, carry->setFromOptions(PETSC_COMM_WORLD));
    }
    PetscCallAbort(PETSC_COMM_WORLD, carry->setUp(ctx));
    FractionState st;
    PetscCallAbort(PETSC_COMM_WORLD, st.create(db->layout(), 2));
    const auto start = uniformMasses(db->mesh(), set, bedWithBubble(db->mesh(), 4));
    setNatural(*db, st, start);
    StepInfo step = jumpStep();
    for (long s = 0; s < 3; ++s) {
      step.step = s;
      step.jump = s == 1;
      PetscCallAbort(PETSC_COMM_WORLD, carry->apply(step, st));
    }
    *result = gatherNatural(*db, st.masses(), 2);
    return start;
  };
  std::vector<double> held, remapped;
  const auto start = run("hold", &held);
  RCFD_CHECK(tally.calls == 3 && tally.jumps == 1 && tally.fractions == 2);
  RCFD_CHECK(held == start);
  run("remap", &remapped); // the built-in kind does act on this jump
  RCFD_CHECK(remapped != start);
  RCFD_CHECK(tally.calls == 3);

  auto carry = created(registry, "carry");
  ScopedOptions options("-carry_type hlod");
  ErrorCapture error;
  const PetscErrorCode code = carry->setFromOptions(PETSC_COMM_WORLD);
  RCFD_CHECK(code == PETSC_ERR_USER_INPUT);
  RCFD_CHECK(contains(error.message(), "-carry_type hlod is not a known carry kind; known kinds: column, hold, level, remap"));
}

// -drift_view ascii:FILE and -shift_view ascii:FILE, through a pipeline made
// from the registry: each view in its own file, the velocities of model B.
void viewsToFiles() {
  auto db = risingBubbleDb("views");
  const FractionSet set = rcfd::test::fractionSet({1e-3, 3e-3}, {0.5, 0.5});
  const std::string driftFile = dir + "/drift.txt", shiftFile = dir + "/shift.txt";
  const OperatorRegistry registry = OperatorRegistry::withBuiltins();
  Pipeline pipeline;
  PetscCallAbort(PETSC_COMM_WORLD, pipeline.add(created(registry, "shift")));
  PetscCallAbort(PETSC_COMM_WORLD, pipeline.add(created(registry, "drift")));
  {
    ScopedOptions options("-drift_model B -drift_kd 5e3 -drift_view ascii:" + driftFile +
                          " -shift_view ascii:" + shiftFile);
    PetscCallAbort(PETSC_COMM_WORLD, pipeline.setFromOptions(PETSC_COMM_WORLD));
  }
  PetscCallAbort(PETSC_COMM_WORLD, pipeline.setUp(RunContext{*db, set, kRho}));
  FractionState st;
  PetscCallAbort(PETSC_COMM_WORLD, st.create(db->layout(), 2));
  setNatural(*db, st, uniformMasses(db->mesh(), set, bedWithBubble(db->mesh(), 4)));
  StepInfo step;
  step.dt = 5e-3;
  for (long s = 0; s < 2; ++s) {
    step.step = s;
    PetscCallAbort(PETSC_COMM_WORLD, pipeline.apply(step, st));
  }
  PetscCallAbort(PETSC_COMM_WORLD, pipeline.viewRequested());
  MPI_Barrier(PETSC_COMM_WORLD);
  const std::string drift = readFile(driftFile), shift = readFile(shiftFile);
  PetscPrintf(PETSC_COMM_WORLD, "-drift_view ascii:FILE wrote:\n%s-shift_view ascii:FILE wrote:\n%s",
              drift.c_str(), shift.c_str());
  // d32 = 1 / (0.5 / 1 mm + 0.5 / 3 mm) = 1.5 mm; u = -kd (d - d32)|d - d32|.
  const double expected[2] = {5e3 * 0.5e-3 * 0.5e-3, -5e3 * 1.5e-3 * 1.5e-3};
  int found = 0;
  std::istringstream lines(drift);
  for (std::string line; std::getline(lines, line);) {
    int i;
    double d, u;
    if (std::sscanf(line.c_str(), " fraction %d (d = %lf mm): u_d = %lf m/s", &i, &d, &u) == 3 && i >= 0 && i < 2) {
      RCFD_CHECK_CLOSE(u / expected[i], 1.0, 1e-3); // printed with 4 significant digits
      ++found;
    }
  }
  RCFD_CHECK(found == 2);
  RCFD_CHECK(contains(drift, "d32 = 1.5 mm (inventory)"));
  RCFD_CHECK(contains(drift, "over 2 steps"));
  RCFD_CHECK(!contains(drift, "shift:"));
  RCFD_CHECK(contains(shift, "shift: moving rows only, 2 fractions at once"));
  RCFD_CHECK(!contains(shift, "drift:"));
}

// A face-swap operator written from the public headers alone (SwapOperator,
// FaceExchange): across every face both sides send the same bulk mass of
// their own mixture, which mixes composition and moves no bulk.  Through the
// exchange's ghost cells it must conserve every fraction and every cell's
// bulk at 2 ranks as at 1, and bring a layered bed to one composition.
class Mixing : public SwapOperator {
public:
  std::string type() const override { return "mixing"; }
  PetscErrorCode apply(const StepInfo &, FractionState &state) override {
    FaceExchange &x = exchange();
    const double share = 0.5 / x.maxFacesPerCell();
    countStep(1);
    return x.sweep(state.masses(), [&] {
      for (const SwapFace &f : x.faces()) {
        const PetscScalar *mL = x.massAt(f.lower), *mU = x.massAt(f.upper);
        double ML = 0.0, MU = 0.0;
        for (int i = 0; i < nf; ++i) ML += mL[i], MU += mU[i];
        if (!(ML > 0.0 && MU > 0.0)) continue;
        const double X = share * std::min(ML, MU);
        PetscScalar *dL = x.changeAt(f.lower), *dU = x.changeAt(f.upper);
        for (int i = 0; i < nf; ++i) {
          const double net = X * (mL[i] / ML - mU[i] / MU);
          dL[i] -= net;
          dU[i] += net;
        }
      }
    });
  }
};

void userSwapOperator() {
  auto db = risingBubbleDb("swap_user");
  const Mesh &mesh = db->mesh();
  const FractionSet set = rcfd::test::fractionSet({1e-3, 1.5e-3, 3e-3}, {0.3, 0.3, 0.4});
  OperatorRegistry registry = OperatorRegistry::withBuiltins();
  registered(registry, "mixing", [] { return std::make_unique<Mixing>(); }, "mixes composition across faces");
  auto op = created(registry, "mixing");
  PetscCallAbort(PETSC_COMM_WORLD, op->setUp(RunContext{*db, set, kRho}));
  FractionState st;
  PetscCallAbort(PETSC_COMM_WORLD, st.create(db->layout(), 3));
  const auto alpha = bedWithBubble(mesh, 4);
  const auto start = layeredMasses(mesh, alpha);
  setNatural(*db, st, start);
  StepInfo step;
  for (step.step = 0; step.step < 1500; ++step.step) PetscCallAbort(PETSC_COMM_WORLD, op->apply(step, st));
  const auto m = gatherNatural(*db, st.masses(), 3);
  const auto before = fractionTotals(start, 3), after = fractionTotals(m, 3);
  double worstTotal = 0.0, worstBulk = 0.0, lo = 1.0, hi = 0.0, lo0 = 1.0, hi0 = 0.0;
  for (int i = 0; i < 3; ++i) worstTotal = std::fmax(worstTotal, std::fabs(after[i] / before[i] - 1.0));
  for (int c = 0; c < mesh.numCells(); ++c) {
    const double M0 = start[3 * c] + start[3 * c + 1] + start[3 * c + 2], M = m[3 * c] + m[3 * c + 1] + m[3 * c + 2];
    if (M0 == 0.0) continue;
    worstBulk = std::fmax(worstBulk, std::fabs(M / M0 - 1.0));
    lo = std::fmin(lo, m[3 * c + 2] / M), hi = std::fmax(hi, m[3 * c + 2] / M);
    lo0 = std::fmin(lo0, start[3 * c + 2] / M0), hi0 = std::fmax(hi0, start[3 * c + 2] / M0);
  }
  PetscPrintf(PETSC_COMM_WORLD,
              "user swap operator: coarse share spread %.3f -> %.2e, bulk change %.1e, fraction totals %.1e\n",
              hi0 - lo0, hi - lo, worstBulk, worstTotal);
  RCFD_CHECK(op->type() == "mixing" && op->optionsPrefix() == "mixing_");
  RCFD_CHECK(static_cast<Mixing &>(*op).stepsTaken() == 1500);
  RCFD_CHECK(worstTotal < 1e-13);
  RCFD_CHECK(worstBulk < 1e-12);
  RCFD_CHECK(hi0 - lo0 > 0.4);
  RCFD_CHECK(hi - lo < 1e-3 * (hi0 - lo0));
}

// A run whose pipeline loses 1e-6 of fraction 0 per step stops at the
// ledger's first check (step 10) with its sentence; the same run goes
// through with a shell operator that changes nothing, or with the same loss
// declared (conservesMass() false: a discharge).
PetscErrorCode loseFraction0(const StepInfo &, FractionState &state) {
  PetscScalar *m;
  PetscInt n;
  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(state.masses(), &n));
  PetscCall(VecGetArray(state.masses(), &m));
  for (PetscInt k = 0; k < n; k += state.numFractions()) m[k] *= 1.0 - 1e-6;
  PetscCall(VecRestoreArray(state.masses(), &m));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode runWith(const std::string &op, const std::string &dbPath, std::string *message,
                       const std::string &tEnd = "0.125") {
  OperatorRegistry registry = OperatorRegistry::withBuiltins();
  registered(registry, "leak", [] { return std::make_unique<ShellOperator>("leak", loseFraction0); },
               "loses 1e-6 of fraction 0 per step");
  replaced(registry, "discharge", [] { return std::make_unique<ShellOperator>("discharge", loseFraction0, false); },
               "the same loss, declared");
  registered(registry, "keep", [] {
    return std::make_unique<ShellOperator>("keep", [](const StepInfo &, FractionState &) { return PETSC_SUCCESS; });
  }, "changes nothing");
  ScopedOptions options("-db " + dbPath + " -pipeline " + op + " -t_end " + tEnd + " -output_dir " + dir +
                        "/run_" + op + " -fields false -plot false -quiet");
  ErrorCapture error;
  Run run(PETSC_COMM_WORLD, registry);
  PetscErrorCode code = run.setFromOptions();
  if (!code) code = run.setUp();
  if (!code) code = run.solve();
  *message = error.message();
  return code;
}

void ledgerRefusesLeak() {
  auto db = risingBubbleDb("ledger"); // written and loaded once; the runs read the file
  const std::string path = dir + "/ledger.h5";
  std::string message;
  const PetscErrorCode leak = runWith("leak", path, &message);
  PetscPrintf(PETSC_COMM_WORLD, "leaking operator: error %d: %s\n", (int)leak, message.c_str());
  RCFD_CHECK(leak == PETSC_ERR_PLIB);
  RCFD_CHECK(contains(message, "Fraction 0 changed its mass by -1.000e-05 (relative) between steps 0 and 10"));
  RCFD_CHECK(contains(message, "an operator is not mass-conserving"));
  // A run that ends before the first regular check is checked at its end.
  std::string shortRun;
  RCFD_CHECK(runWith("leak", path, &shortRun, "0.02") == PETSC_ERR_PLIB);
  RCFD_CHECK(contains(shortRun, "an operator is not mass-conserving"));
  for (const std::string op : {"keep", "discharge"}) { // conservative, or a loss declared as such
    std::string none;
    RCFD_CHECK(runWith(op, path, &none) == 0);
    RCFD_CHECK(none.empty());
  }
}

} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  dir = rcfd::test::rankCountDirectory(argc, argv, "operators");
  if (dir.empty()) return 1;
  carryLevel();
  userCarryKind();
  viewsToFiles();
  userSwapOperator();
  ledgerRefusesLeak();
  const int total = rcfd::test::globalFailures();
  PetscCall(PetscFinalize());
  return total == 0 ? 0 : 1;
}
