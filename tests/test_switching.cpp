// Several databases in one run, by hand on 1 and 2 ranks: one partition for a
// set and a mesh mismatch refused; blended frames column-stochastic and
// consistent (T alpha_k V = alpha_{k+1} V of the blend) to round-off, a
// database blended with itself its own shifts; the hysteresis band rule on a
// constructed signal; the schedule, blend and markov rules' choices, and the
// markov rule continued from its saved state; a blend paired by recurrence,
// whose second database wraps inside it (a frame without a follower);
// databases of different lengths (a blend with a truncated copy); the
// monitors following a switch; the umf_usup signal the same number as
// bottom.csv's u_mf/u_sup.
#include "check.hpp"
#include "box_meshes.hpp"
#include "registry_helpers.hpp"
#include "base/petsc_compat.hpp"
#include "scoped_options.hpp"
#include "state_access.hpp"
#include "synthetic_beds.hpp"

#include "base/csv.hpp"
#include "base/h5.hpp"
#include "builders/synthetic/synthetic_bed.hpp"
#include "rcfd/database_set.hpp"
#include "rcfd/run.hpp"
#include "rcfd/switching.hpp"
#include "database/database_file_writer.hpp"

#include <cmath>
#include <cstdio>
#include <map>

using namespace rcfd;
using rcfd::test::writeBed;

namespace {

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

// Databases of different lengths: a set of 12 and 8 frames opens; database a
// blended with its own first 8 frames (a truncated copy, read onto the set's
// layout) is as long as the shorter, column-stochastic, consistent (T alpha_k
// V = alpha_{k+1} V of the blend) to round-off up to its own wrap, and a's own
// shifts; either way round.
PetscErrorCode differentLengths(const std::string &dir, const DatabaseSet &set, const Database &da) {
  PetscFunctionBeginUser;
  const std::string shorter = dir + "/a8.h5";
  writeBed(shorter, 20, 1500.0, 1, 8);
  std::unique_ptr<DatabaseSet> mixed;
  PetscCall(DatabaseSet::open(PETSC_COMM_WORLD, {dir + "/a.h5", shorter}, DatabaseLoadOptions{}, {}, &mixed));
  RCFD_CHECK(mixed->entry(0).numFrames == 12 && mixed->entry(1).numFrames == 8);
  DatabaseLoadOptions firstEight;
  firstEight.lastFrame = 7;
  firstEight.layout = &set.layout();
  std::unique_ptr<Database> truncated;
  PetscCall(Database::load(PETSC_COMM_WORLD, dir + "/a.h5", firstEight, &truncated));
  RCFD_CHECK(truncated->numFrames() == 8);
  for (const bool longFirst : {true, false}) {
    std::unique_ptr<Database> blend;
    PetscCall(longFirst ? blendDatabases(da, *truncated, 0.3, &blend) : blendDatabases(*truncated, da, 0.3, &blend));
    RCFD_CHECK(blend->numFrames() == 8);
    double worstColumn = 0.0, worstConsistency = 0.0, worstOwn = 0.0;
    for (int k = 0; k < blend->numFrames(); ++k) {
      double column, consistency;
      PetscCall(frameErrors(*blend, k, &column, &consistency));
      worstColumn = std::max(worstColumn, column);
      if (k + 1 < blend->numFrames()) worstConsistency = std::max(worstConsistency, consistency);
      OwnedMat difference, own;
      PetscCall(blend->shiftMatrix(k, &difference));
      PetscCall(da.shiftMatrix(k, &own));
      PetscCall(MatAXPY(difference, -1.0, own, DIFFERENT_NONZERO_PATTERN));
      PetscReal norm;
      PetscCall(MatNorm(difference, NORM_INFINITY, &norm));
      worstOwn = std::max(worstOwn, norm);
    }
    RCFD_CHECK(worstColumn < 1e-13);
    RCFD_CHECK(worstConsistency < 1e-12);
    RCFD_CHECK(worstOwn < 1e-14);
  }
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
    // The lagged blend pairs a's frame K - 1 - lag = 6 with later's last and frame 7 with later's first:
    // later wraps inside it, so frame 7 does not follow frame 6 (a run steps it as a jump).  By index, and
    // in a loaded database, every frame but the last is followed by the next.
    for (int k = 0; k < K; ++k) {
      RCFD_CHECK(paired->nextFollows(k) == (k != K - 1 - lag && k + 1 < K));
      RCFD_CHECK(byIndex->nextFollows(k) == (k + 1 < K) && da->nextFollows(k) == (k + 1 < K));
    }
  }
  PetscCall(differentLengths(dir, *set, *da));
  // Dropping: a database nobody else holds goes when another is loaded.
  da.reset();
  set->dropUnused();
  RCFD_CHECK(set->numHeld() == 1 && set->maxHeld() == 2);
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
    PetscCall(blend->setUp(SwitchContext{PETSC_COMM_WORLD, c}));
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
    PetscCall(first->setUp(SwitchContext{PETSC_COMM_WORLD, c}));
    PetscCall(second->setUp(SwitchContext{PETSC_COMM_WORLD, c}));
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

/// sum over cells of (natural index + 1) alpha_s of frame k: a fingerprint of the field in natural order.
PetscErrorCode fingerprint(const Database &db, int k, double *sum) {
  const PetscScalar *a;
  PetscFunctionBeginUser;
  *sum = 0.0;
  PetscCall(VecGetArrayRead(db.alphaS(k), &a));
  const auto &owned = db.layout().ownedNatural();
  for (std::size_t c = 0; c < owned.size(); ++c) *sum += (owned[c] + 1.0) * a[c];
  PetscCall(VecRestoreArrayRead(db.alphaS(k), &a));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sum, 1, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The monitors follow the database in use.  A run on a (12 frames, 1.1 m/s)
// and b8 (8 frames, 1.3 m/s), switched by the schedule at 0.02 s: bottom.csv's
// u_sup is 1.1 m/s before the switch and 1.3 from it on, and the field file at
// 0.04 s (the path's frame 8: b8's frame 0) holds b8's frame 0, not a's frame 8.
PetscErrorCode monitorsFollow(const std::string &dir) {
  PetscMPIInt size;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  const std::string a = dir + "/a.h5", b8 = dir + "/b8.h5", out = dir + "/follow-np" + std::to_string(size);
  writeBed(b8, 20, 4000.0, 2, 8);
  int frameAt = -1; // the database frame the monitors see at 0.04 s
  {
    ScopedOptions o("-db " + a + "," + b8 + " -db_conditions 1.1,1.3 -db_switch_schedule 0:1.1,0.02:1.3 "
                    "-bottom_layer -fields_every 0.01 -t_end 0.05 -path_type replay");
    const OperatorRegistry registry = OperatorRegistry::withBuiltins();
    Run run(PETSC_COMM_WORLD, registry);
    PetscCall(run.setFromOptions());
    run.setQuiet(true);
    run.setOutputDirectory(out);
    PetscCall(run.addMonitor(
        [&](const MonitorContext &m) {
          if (std::fabs(m.time - 0.04) < 1e-9) frameAt = m.frame;
          return PETSC_SUCCESS;
        },
        1, "frame"));
    PetscCall(run.setUp());
    PetscCall(run.solve());
  }
  RCFD_CHECK(frameAt == 0);
  const csv::Table bottom = csv::Table::read(out + "/bottom.csv");
  const int t = bottom.find({"time_s"}), u = bottom.find({"usup_m_s"});
  int before = 0, after = 0;
  for (std::size_t r = 0; r < bottom.numRows(); ++r) {
    if (bottom.number(r, t) < 0.02 - 1e-9) before += bottom.number(r, u) == 1.1;
    else after += bottom.number(r, u) == 1.3;
  }
  RCFD_CHECK(before == 4 && after == 7); // 0 to 0.015 s, 0.02 to 0.05 s
  std::unique_ptr<Database> da, db;
  PetscCall(Database::load(PETSC_COMM_WORLD, a, DatabaseLoadOptions{}, &da));
  PetscCall(Database::load(PETSC_COMM_WORLD, b8, DatabaseLoadOptions{}, &db));
  double expected, other, written = 0.0;
  PetscCall(fingerprint(*db, 0, &expected));
  PetscCall(fingerprint(*da, 8, &other));
  const std::vector<double> field =
      h5::File::openRead(out + "/fields_000004.h5", MPI_COMM_NULL).read<double>("/alpha_s_database");
  for (std::size_t i = 0; i < field.size(); ++i) written += (i + 1.0) * field[i];
  RCFD_CHECK(std::fabs(written - expected) < 1e-12 * expected);
  RCFD_CHECK(std::fabs(other - expected) > 1e-6 * expected); // the check can tell the databases apart
  PetscFunctionReturn(PETSC_SUCCESS);
}

// Keeps every umf_usup the switcher hands it (the switcher's sample of its
// signal); starts on database 1 and moves to database 0 after step `at`.
class SignalRecorder final : public SwitchRule {
public:
  SignalRecorder(std::map<long, double> *seen, long at) : seen(seen), at(at) {}
  std::string type() const override { return "recorder"; }
  std::string describe() const override { return "umf_usup recorded"; }
  bool needsSignals() const override { return true; }
  std::vector<std::string> signalsUsed() const override { return {"umf_usup"}; }
  SwitchDecision initial() const override { return {1}; }
  SwitchDecision decide(const SwitchDecision &active, const SwitchSignals &s) override {
    (*seen)[s.step] = s.named("umf_usup");
    return {s.step == at ? 0 : active.database, s.named("umf_usup")};
  }

private:
  std::map<long, double> *seen;
  long at;
};

// The switcher's umf_usup is bottom.csv's u_mf/u_sup: the case's gas
// (-gas_density 0.8, -gas_kinematic_viscosity 3e-5) over the gases the
// databases recorded (1.2 and 1.0 kg/m^3), and the case's -umf_correlation
// over Wen-Yu.  A run on database 1 (1.3 m/s: u_mf/u_sup 0.95) that moves to
// database 0 (1.1 m/s: 1.13, de-fluidized) after step 20: at every step but
// the switch's (bottom.csv is written after a switch: the remapped state, the
// new database's u_sup) the signal equals bottom.csv's u_mf/u_sup to the 10
// digits the file holds, on both databases; switches.csv's trigger is the signal, and its
// validity warning comes at the first decision on database 0 with bottom.csv's
// value there (the bottom layer warned at the switch's own sample).
PetscErrorCode signalAgrees(const std::string &dir) {
  PetscMPIInt size;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  const std::string g0 = dir + "/gas0.h5", g1 = dir + "/gas1.h5", out = dir + "/signal-np" + std::to_string(size);
  writeBed(g0, 20, 1500.0, 1, 12, OperatingConditions{1.1, 1.2, 1.5e-5});
  writeBed(g1, 20, 4000.0, 2, 12, OperatingConditions{1.3, 1.0, 1.8e-5});
  const long switchedAt = 20;
  std::map<long, double> seen; // step -> umf_usup
  SwitchRuleRegistry rules = SwitchRuleRegistry::withBuiltins();
  registered(rules, "recorder", [&] { return std::make_unique<SignalRecorder>(&seen, switchedAt); }, "records umf_usup");
  {
    ScopedOptions o("-db " + g0 + "," + g1 + " -db_switch_type recorder -gas_density 0.8 "
                    "-gas_kinematic_viscosity 3e-5 -umf_correlation saxena-vogel -bottom_layer -t_end 0.3");
    const OperatorRegistry registry = OperatorRegistry::withBuiltins();
    Run run(PETSC_COMM_WORLD, registry);
    run.useSwitchRules(rules);
    PetscCall(run.setFromOptions());
    run.setQuiet(true);
    run.setOutputDirectory(out);
    PetscCall(run.setUp());
    PetscCall(run.solve());
  }
  const auto stepAt = [](double time) { return std::lround(time / DatabaseMetadata{}.dtRec); };
  const csv::Table switches = csv::Table::read(out + "/switches.csv");
  std::map<std::string, std::pair<long, double>> event; // switch / extrapolating -> step, value
  for (std::size_t r = 0; r < switches.numRows(); ++r)
    event[std::string(switches.field(r, switches.find({"event"})))] = {
        stepAt(switches.number(r, switches.find({"time_s"}))), switches.number(r, switches.find({"trigger"}))};
  RCFD_CHECK(switches.numRows() == 2 && event["switch"].first == switchedAt &&
             std::fabs(event["switch"].second / seen[switchedAt] - 1) < 1e-9); // written with %.10g
  const long warnedAt = event["extrapolating"].first;
  const csv::Table bottom = csv::Table::read(out + "/bottom.csv");
  const int t = bottom.find({"time_s"}), umf = bottom.find({"umf_m_s"}), usup = bottom.find({"usup_m_s"}),
            flag = bottom.find({"defluidized"});
  int compared = 0;
  long firstDefluidized = -1;
  double worst = 0.0;
  for (std::size_t r = 0; r < bottom.numRows(); ++r) {
    const long step = stepAt(bottom.number(r, t));
    const double ratio = bottom.numberOrNan(r, umf) / bottom.number(r, usup);
    if (firstDefluidized < 0 && bottom.number(r, flag) == 1) firstDefluidized = step;
    if (step == warnedAt) RCFD_CHECK(std::fabs(event["extrapolating"].second / ratio - 1) < 1e-9);
    if (!seen.count(step) || step == switchedAt) continue; // step 0: no decision
    const double difference = std::fabs(seen[step] / ratio - 1);
    if (!(difference <= worst)) worst = difference; // NaN on either side too
    compared += (step < switchedAt ? 0.9 < ratio && ratio < 1 : 1.1 < ratio && ratio < 1.2);
  }
  if (!(worst < 1e-9)) std::printf("umf_usup differs from bottom.csv's u_mf/u_sup by %.3g (relative)\n", worst);
  RCFD_CHECK(compared == 59);
  RCFD_CHECK(worst < 1e-9); // bottom.csv holds 10 digits
  RCFD_CHECK(firstDefluidized == switchedAt && warnedAt == switchedAt + 1);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode run(const std::string &dir) {
  PetscFunctionBeginUser;
  PetscCall(blends(dir));
  PetscCall(monitorsFollow(dir));
  PetscCall(signalAgrees(dir));
  hysteresis();
  PetscCall(rules());
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

int main(int argc, char **argv) { return test::rankTestMain(argc, argv, "switching", run); }
