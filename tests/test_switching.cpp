// Several databases in one run, by hand on 1 and 2 ranks: one partition for a
// set and a mesh mismatch refused; blended frames column-stochastic and
// consistent (T alpha_k V = alpha_{k+1} V of the blend) to round-off, a
// database blended with itself its own shifts; the hysteresis band rule on a
// constructed signal; the schedule, blend and markov rules' choices, and the
// markov rule continued from its saved state.
#include "check.hpp"
#include "base/petsc_compat.hpp"
#include "scoped_options.hpp"
#include "state_access.hpp"

#include "builders/synthetic/synthetic_bed.hpp"
#include "rcfd/database_set.hpp"
#include "rcfd/switching.hpp"

#include <cmath>

using namespace rcfd;

namespace {

void writeBed(const std::string &path, int nz, double rate, std::uint64_t seed) {
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0) {
    SyntheticBedOptions o;
    o.box.nx = 10;
    o.box.ny = 2;
    o.box.nz = nz;
    o.numFrames = 12;
    o.warmUpTime = 0.1;
    o.nucleationRate = rate;
    o.seed = seed;
    DatabaseWriter w(path, Mesh::box(o.box), DatabaseMetadata{});
    generateSyntheticBed(o, [&](const FrameRecord &f) { w.append(f); });
    w.finish();
  }
  MPI_Barrier(PETSC_COMM_WORLD);
}

/// max over cells of |column sum - 1| of T, and of |T m_k - m_{k+1}| / max(m) with m = alpha V.
PetscErrorCode frameErrors(const Database &db, int k, double *column, double *consistency) {
  PetscFunctionBeginUser;
  OwnedVec ones, sums, m, next, moved;
  OwnedMat T;
  PetscCall(db.shiftMatrix(k, &T));
  PetscCall(MatCreateVecs(T, ones.put(), sums.put()));
  PetscCall(VecSet(ones, 1.0));
  PetscCall(MatMultTranspose(T, ones, sums));
  PetscCall(VecShift(sums, -1.0));
  PetscCall(VecNorm(sums, NORM_INFINITY, column));
  for (OwnedVec *v : {&m, &next, &moved}) PetscCall(VecDuplicate(ones, v->put()));
  PetscScalar *pm, *pn;
  const PetscScalar *a, *b;
  PetscCall(VecGetArrayWrite(m, &pm));
  PetscCall(VecGetArrayWrite(next, &pn));
  PetscCall(VecGetArrayRead(db.alphaS(k), &a));
  PetscCall(VecGetArrayRead(db.alphaS((k + 1) % db.numFrames()), &b));
  for (std::size_t i = 0; i < db.localVolumes().size(); ++i) {
    pm[i] = a[i] * db.localVolumes()[i];
    pn[i] = b[i] * db.localVolumes()[i];
  }
  PetscCall(VecRestoreArrayRead(db.alphaS((k + 1) % db.numFrames()), &b));
  PetscCall(VecRestoreArrayRead(db.alphaS(k), &a));
  PetscCall(VecRestoreArrayWrite(next, &pn));
  PetscCall(VecRestoreArrayWrite(m, &pm));
  PetscReal largest;
  PetscCall(VecNorm(m, NORM_INFINITY, &largest));
  PetscCall(MatMult(T, m, moved));
  PetscCall(VecAXPY(moved, -1.0, next));
  PetscCall(VecNorm(moved, NORM_INFINITY, consistency));
  *consistency /= largest;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode blends(const std::string &dir) {
  PetscFunctionBeginUser;
  const std::string a = dir + "/a.h5", b = dir + "/b.h5", other = dir + "/other.h5";
  writeBed(a, 20, 1500.0, 1);
  writeBed(b, 20, 4000.0, 2);
  writeBed(other, 24, 2500.0, 3);
  std::unique_ptr<DatabaseSet> set;
  PetscCall(DatabaseSet::open(PETSC_COMM_WORLD, {a, b}, DatabaseLoadOptions{}, {1.1, 1.3}, &set));
  RCFD_CHECK(set->size() == 2 && set->entry(1).conditions.superficialVelocity == 1.3);
  {
    ErrorCapture capture;
    std::unique_ptr<DatabaseSet> refused;
    RCFD_CHECK(DatabaseSet::open(PETSC_COMM_WORLD, {a, other}, DatabaseLoadOptions{}, {}, &refused) != 0 && !refused);
    RCFD_CHECK(capture.message().find("Databases '" + a + "' and '" + other + "' are on different meshes") == 0);
  }

  std::shared_ptr<Database> da, db;
  PetscCall(set->get(0, &da));
  PetscCall(set->get(1, &db));
  RCFD_CHECK(set->numHeld() == 2 && set->numLoads() == 2);
  RCFD_CHECK(da->layout().rowStart() == db->layout().rowStart() && da->layout().rowEnd() == db->layout().rowEnd());
  const double w = 0.3;
  std::unique_ptr<Database> blend, self;
  PetscCall(blendDatabases(*da, *db, w, &blend));
  PetscCall(blendDatabases(*da, *da, 0.4, &self));
  RCFD_CHECK(blend->numFrames() == 12);
  double worstColumn = 0.0, worstBlend = 0.0, worstInputs = 0.0, worstSelf = 0.0;
  for (int k = 0; k + 1 < blend->numFrames(); ++k) {
    double column, consistency, ca, cb, columnA, columnB;
    PetscCall(frameErrors(*blend, k, &column, &consistency));
    PetscCall(frameErrors(*da, k, &columnA, &ca));
    PetscCall(frameErrors(*db, k, &columnB, &cb));
    worstColumn = std::max(worstColumn, column);
    worstBlend = std::max(worstBlend, consistency);
    worstInputs = std::max({worstInputs, ca, cb});
    OwnedMat difference, own; // a database blended with itself: its own shifts
    PetscCall(self->shiftMatrix(k, &difference));
    PetscCall(da->shiftMatrix(k, &own));
    PetscCall(MatAXPY(difference, -1.0, own, DIFFERENT_NONZERO_PATTERN));
    PetscReal norm;
    PetscCall(MatNorm(difference, NORM_INFINITY, &norm));
    worstSelf = std::max(worstSelf, norm);
  }
  RCFD_CHECK(worstColumn < 1e-13);
  RCFD_CHECK(worstInputs < 1e-12);         // the synthetic beds are consistent ...
  RCFD_CHECK(worstBlend < 1e-12);          // ... and so is their blend
  RCFD_CHECK(worstSelf < 1e-14);
  // Pairing by recurrence similarity: database a against its own frames started 7 frames later
  // (b_j = a_(j+7)): the lag found pairs every frame with itself, and the blend is a again.
  {
    const int K = da->numFrames(), shift = 7;
    std::vector<OwnedVec> alpha(K);
    std::vector<OwnedMat> shifts(K);
    for (int j = 0; j < K; ++j) {
      PetscCall(VecDuplicate(da->alphaS((j + shift) % K), alpha[j].put()));
      PetscCall(VecCopy(da->alphaS((j + shift) % K), alpha[j]));
      PetscCall(da->shiftMatrix((j + shift) % K, &shifts[j]));
    }
    std::unique_ptr<Database> later, paired, byIndex;
    PetscCall(Database::fromFrames(*da, "a, 7 frames later", std::move(alpha), std::move(shifts), &later));
    int lag = -1;
    PetscCall(pairingLag(*da, *later, &lag));
    RCFD_CHECK(lag == K - shift);
    PetscCall(blendDatabases(*da, *later, 0.4, &paired, lag));
    PetscCall(blendDatabases(*da, *later, 0.4, &byIndex));
    double worstPaired = 0.0, worstByIndex = 0.0;
    for (int k = 0; k < K; ++k) {
      OwnedMat own, p, q;
      PetscCall(da->shiftMatrix(k, &own));
      PetscCall(paired->shiftMatrix(k, &p));
      PetscCall(byIndex->shiftMatrix(k, &q));
      PetscReal np, nq;
      PetscCall(MatAXPY(p, -1.0, own, DIFFERENT_NONZERO_PATTERN));
      PetscCall(MatAXPY(q, -1.0, own, DIFFERENT_NONZERO_PATTERN));
      PetscCall(MatNorm(p, NORM_INFINITY, &np));
      PetscCall(MatNorm(q, NORM_INFINITY, &nq));
      worstPaired = std::max(worstPaired, np);
      worstByIndex = std::max(worstByIndex, nq);
    }
    RCFD_CHECK(worstPaired < 1e-14); // the same frames blended: a's own shifts
    RCFD_CHECK(worstByIndex > 1e-3); // frames 7 apart blended: another database
  }
  // Dropping: a database nobody else holds goes when another is loaded.
  da.reset();
  set->dropUnused();
  RCFD_CHECK(set->numHeld() == 1);
  PetscFunctionReturn(PETSC_SUCCESS);
}

void hysteresis() {
  // A signal dithering by 1 % around the threshold 1.0, then rising through it once.
  std::vector<double> signal;
  for (int k = 0; k < 200; ++k) signal.push_back(1.0 + 0.01 * std::sin(0.7 * k));
  for (int k = 0; k <= 100; ++k) signal.push_back(1.0 + 0.002 * k);
  auto switches = [&](double margin, double *when) {
    int band = 0, count = 0;
    for (std::size_t k = 0; k < signal.size(); ++k) {
      const int next = bandWithHysteresis({1.0}, margin, band, signal[k]);
      if (next != band && count++ == 0) *when = signal[k];
      band = next;
    }
    return count;
  };
  double first = 0.0;
  RCFD_CHECK(switches(0.0, &first) > 40); // without a margin it flickers: 44 crossings
  RCFD_CHECK(switches(0.05, &first) == 1 && first > 1.05 && first < 1.053);
  RCFD_CHECK(bandWithHysteresis({1.0, 2.0}, 0.1, 0, 2.5) == 2 && bandWithHysteresis({1.0, 2.0}, 0.1, 2, 0.5) == 0);
  RCFD_CHECK(bandWithHysteresis({1.0, 2.0}, 0.1, 1, 1.95) == 1 && bandWithHysteresis({1.0}, 0.1, 1, NAN) == 1);
}

PetscErrorCode rules() {
  PetscFunctionBeginUser;
  const SwitchRuleRegistry registry = SwitchRuleRegistry::withBuiltins();
  std::vector<OperatingConditions> c(3);
  c[0].superficialVelocity = 1.0;
  c[1].superficialVelocity = 1.4;
  c[2].superficialVelocity = 1.2;
  RCFD_CHECK(nearestDatabase(c, 1.25) == 2 && nearestDatabase(c, 0.5) == 0 && nearestDatabase(c, 9) == 1);
  {
    ScopedOptions o("-db_switch_type blend -db_switch_schedule 0:1.1,2:1.3,4:1.5");
    std::unique_ptr<SwitchRule> blend;
    PetscCall(registry.createFromOptions(PETSC_COMM_WORLD, &blend));
    PetscCall(blend->setUp(PETSC_COMM_WORLD, c));
    const SwitchDecision start = blend->initial(); // 1.1 between 1.0 (w 0.5) and 1.2
    RCFD_CHECK(start.database == 0 && start.partner == 2 && std::fabs(start.weight - 0.5) < 1e-12);
    SwitchSignals s;
    s.time = 2.0; // 1.3 between 1.2 (w 0.5) and 1.4
    const SwitchDecision mid = blend->decide(start, s);
    RCFD_CHECK(mid.database == 2 && mid.partner == 1 && std::fabs(mid.weight - 0.5) < 1e-12);
    s.time = 5.0; // above every database: the nearest alone
    const SwitchDecision above = blend->decide(mid, s);
    RCFD_CHECK(above.database == 1 && above.partner < 0);
  }
  {
    ScopedOptions o("-db_switch_type markov -db_switch_interval 0.5 -db_switch_seed 9 -db_switch_weights 1,2,1");
    std::unique_ptr<SwitchRule> first, second;
    PetscCall(registry.createFromOptions(PETSC_COMM_WORLD, &first));
    PetscCall(registry.createFromOptions(PETSC_COMM_WORLD, &second));
    PetscCall(first->setUp(PETSC_COMM_WORLD, c));
    PetscCall(second->setUp(PETSC_COMM_WORLD, c));
    SwitchDecision a = first->initial(), b;
    std::vector<int> drawn(3, 0);
    std::vector<double> saved;
    for (int k = 1; k <= 400; ++k) {
      SwitchSignals s;
      s.time = 0.25 * k;
      a = first->decide(a, s);
      if (k % 2 == 0) ++drawn[a.database];
      if (k == 200) {
        saved = first->saveState();
        b = a;
      }
      if (k > 200) { // continued from the saved state: the same draws
        if (k == 201) second->restoreState(saved);
        b = second->decide(b, s);
        RCFD_CHECK(b.database == a.database);
      }
    }
    RCFD_CHECK(drawn[1] > 75 && drawn[1] < 125 && drawn[0] > 25 && drawn[2] > 25); // weights 1:2:1 of 200 draws
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode run(const std::string &dir) {
  PetscFunctionBeginUser;
  PetscCall(blends(dir));
  hysteresis();
  PetscCall(rules());
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

int main(int argc, char **argv) { return test::rankTestMain(argc, argv, "switching", run); }
