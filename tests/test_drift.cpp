// Drift and dispersion face swaps against exact answers: complete
// separation of two fractions in a column, -drift_every against longer
// steps, the steady drift-dispersion profile of the semi-discrete balance
// with first-order convergence in time,
// a column along another axis with gravity along it giving the same answer,
// and bulk/fraction conservation and positivity under stress (2, 5 and 20
// fractions, k_d 100x the paper's, near-empty and near-packed cells, and no
// alpha_s floor next to empty cells), and drift scaled by the bed's agitation
// (exponent 0 equal to the unscaled drift bit for bit, a uniform field to
// round-off, the factor of the frame being applied), and the operator
// against a straightforward implementation written here, along the frames of
// small.h5 with each option that changes the kernel's path, and the state's
// bound on where mass can be as the shift and the drift keep it; the size
// laws against hand values (fixed and local d32), the drag law's zero net
// volume, a user-registered law, and a fixed agitation reference that makes
// two beds at different agitation drift alike per unit agitation, and the
// excess-gas scale against u_sup - u_mf worked out by hand.
// Runs at 1 and 2 ranks.  Every PETSc call is checked with PetscCallAbort:
// an error (a database that does not load, a set-up or step that fails)
// stops the test with PETSc's message and a non-zero exit, never a silent pass.
#include "check.hpp"
#include "box_meshes.hpp"
#include "fraction_sets.hpp"
#include "registry_helpers.hpp"
#include "scoped_options.hpp"
#include "rcfd/agitation.hpp"
#include "rcfd/swaps.hpp"
#include "state_access.hpp"

#include <cmath>
#include <functional>
#include <map>
#include <random>
#include <stdexcept>

using namespace rcfd;
using rcfd::test::gatherNatural;
using rcfd::test::setNatural;

namespace {

std::string dir, dataDir;
int counter = 0;

BoxSpec column(int axis, int n, double length) {
  BoxSpec s;
  s.nx = s.ny = s.nz = 1;
  s.length = {0.01, 0.01, 0.01};
  (axis == 0 ? s.nx : axis == 1 ? s.ny : s.nz) = n;
  s.length[axis] = length;
  return s;
}

std::unique_ptr<Database> identityDb(const BoxSpec &spec, const std::vector<double> &alpha,
                                     const Vec3 &gravity) {
  const std::string path = dir + "/drift_" + std::to_string(counter++) + ".h5";
  DatabaseMetadata meta;
  meta.gravity = gravity;
  const Mesh mesh = rcfd::test::boxMesh(spec);
  rcfd::test::writeIdentityDatabase(path, mesh, alpha, meta);
  std::unique_ptr<Database> db;
  PetscCallAbort(PETSC_COMM_WORLD, Database::load(PETSC_COMM_WORLD, path, DatabaseLoadOptions{}, &db));
  return db;
}

// An operator configured from an options string under a fresh prefix.
template <typename Op> std::unique_ptr<Op> makeOperator(const std::string &options) {
  auto op = std::make_unique<Op>();
  const std::string prefix = "t" + std::to_string(counter++) + "_";
  std::string withPrefix;
  for (size_t p = 0; p < options.size();) { // "-a 1 -b 2" -> "-tN_a 1 -tN_b 2"
    if (options[p] == '-' && (p == 0 || options[p - 1] == ' ')) withPrefix += "-" + prefix, ++p;
    else withPrefix += options[p++];
  }
  PetscCallAbort(PETSC_COMM_WORLD, PetscOptionsInsertString(nullptr, withPrefix.c_str()));
  op->setOptionsPrefix(prefix);
  PetscCallAbort(PETSC_COMM_WORLD, op->setFromOptions(PETSC_COMM_WORLD));
  return op;
}

std::vector<double> uniformState(const Mesh &mesh, const std::vector<double> &alpha,
                                 const FractionSet &set) {
  std::vector<double> m;
  for (int c = 0; c < mesh.numCells(); ++c)
    for (int i = 0; i < set.size(); ++i)
      m.push_back(set.massShare(i) * 1440.0 * alpha[c] * mesh.cellVolume[c]);
  return m;
}

void step(std::vector<Operator *> ops, FractionState &st, double dt, long n) {
  StepInfo info;
  info.dt = dt;
  for (long s = 0; s < n; ++s)
    for (Operator *op : ops) PetscCallAbort(PETSC_COMM_WORLD, op->apply(info, st));
}

void completeSeparation() {
  const BoxSpec spec = column(2, 20, 0.2);
  const std::vector<double> alpha(20, 0.5);
  auto db = identityDb(spec, alpha, {0, 0, -9.81});
  FractionSet set = rcfd::test::fractionSet({1e-3, 3e-3}, {0.5, 0.5});
  RunContext ctx{*db, set, 1440.0};
  auto drift = makeOperator<DriftOperator>("-model constant -velocities 0.02,-0.02");
  RCFD_CHECK(drift->needed(ctx));
  PetscCallAbort(PETSC_COMM_WORLD, drift->setUp(ctx));
  FractionState st;
  PetscCallAbort(PETSC_COMM_WORLD, st.create(db->layout(), 2));
  const auto start = uniformState(db->mesh(), alpha, set);
  setNatural(*db, st, start);
  step({drift.get()}, st, 5e-3, 8000);
  const auto m = gatherNatural(*db, st.masses(), 2);
  // Equal volumes of the two fractions: the lower ten cells hold only large
  // particles, the upper ten only small ones, each cell keeping its bulk.
  double worstMix = 0.0, worstBulk = 0.0;
  for (int k = 0; k < 20; ++k) {
    const double bulk = m[2 * k] + m[2 * k + 1], wrong = k < 10 ? m[2 * k] : m[2 * k + 1];
    worstMix = std::fmax(worstMix, wrong / bulk);
    worstBulk = std::fmax(worstBulk, std::fabs(bulk / (start[2 * k] + start[2 * k + 1]) - 1.0));
  }
  PetscPrintf(PETSC_COMM_WORLD, "separation: largest wrong-fraction share %.2e, bulk change %.2e\n",
              worstMix, worstBulk);
  RCFD_CHECK(worstMix < 1e-6);
  RCFD_CHECK(worstBulk < 1e-13);
}

// -drift_every N applies the drift of N steps at the end of every N-th step:
// nothing changes before the 4th step, and 12 steps of dt with N = 4 give
// the state of 3 steps of 4 dt bit for bit.
void driftEvery() {
  const std::vector<double> alpha(20, 0.5);
  auto db = identityDb(column(2, 20, 0.2), alpha, {0, 0, -9.81});
  FractionSet set = rcfd::test::fractionSet({1e-3, 3e-3}, {0.5, 0.5});
  RunContext ctx{*db, set, 1440.0};
  auto every4 = makeOperator<DriftOperator>("-model constant -velocities 0.02,-0.02 -every 4");
  auto each = makeOperator<DriftOperator>("-model constant -velocities 0.02,-0.02");
  PetscCallAbort(PETSC_COMM_WORLD, every4->setUp(ctx));
  PetscCallAbort(PETSC_COMM_WORLD, each->setUp(ctx));
  FractionState a, b;
  PetscCallAbort(PETSC_COMM_WORLD, a.create(db->layout(), 2));
  PetscCallAbort(PETSC_COMM_WORLD, b.create(db->layout(), 2));
  const auto start = uniformState(db->mesh(), alpha, set);
  setNatural(*db, a, start);
  setNatural(*db, b, start);
  StepInfo info;
  info.dt = 5e-3;
  for (long s = 0; s < 12; ++s) {
    info.step = s;
    PetscCallAbort(PETSC_COMM_WORLD, every4->apply(info, a));
    if (s == 2) RCFD_CHECK(gatherNatural(*db, a.masses(), 2) == start);
  }
  info.dt = 2e-2;
  for (long s = 0; s < 3; ++s) {
    info.step = s;
    PetscCallAbort(PETSC_COMM_WORLD, each->apply(info, b));
  }
  const auto ma = gatherNatural(*db, a.masses(), 2), mb = gatherNatural(*db, b.masses(), 2);
  RCFD_CHECK(ma == mb);
  RCFD_CHECK(ma != start);
  RCFD_CHECK(every4->stepsTaken() == 3);
}

// Steady state of the semi-discrete balance across each face k|k+1 for a
// small fraction (share y) drifting up at u against dispersion D in a column
// of uniform bulk: u y_k (1 - y_k+1) = D (y_k+1 - y_k) / dz.  y_0 is found
// by bisection so that the column holds the given mean share.
std::vector<double> steadyProfile(int n, double u, double D, double dz, double mean) {
  auto profile = [&](double y0) {
    std::vector<double> y(n, y0);
    for (int k = 0; k + 1 < n; ++k) y[k + 1] = y[k] * (u + D / dz) / (u * y[k] + D / dz);
    return y;
  };
  double lo = 0.0, hi = mean;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    double sum = 0.0;
    for (double y : profile(mid)) sum += y;
    (sum / n > mean ? hi : lo) = mid;
  }
  return profile(0.5 * (lo + hi));
}

void driftAgainstDispersion() {
  const int n = 20;
  const double dz = 0.01, u = 0.05, D = 4e-3, share = 0.05;
  const BoxSpec spec = column(2, n, n * dz);
  const std::vector<double> alpha(n, 0.5);
  auto db = identityDb(spec, alpha, {0, 0, -9.81});
  FractionSet set = rcfd::test::fractionSet({1e-3, 2e-3}, {share, 1 - share});
  RunContext ctx{*db, set, 1440.0};
  const auto exact = steadyProfile(n, u, D, dz, share);
  auto runTo = [&](double tEnd, double dt) {
    auto drift = makeOperator<DriftOperator>("-model constant -velocities 0.05,0");
    auto disp = makeOperator<DispersionOperator>("-coefficient 4e-3");
    PetscCallAbort(PETSC_COMM_WORLD, drift->setUp(ctx));
    PetscCallAbort(PETSC_COMM_WORLD, disp->setUp(ctx));
    FractionState st;
    PetscCallAbort(PETSC_COMM_WORLD, st.create(db->layout(), 2));
    setNatural(*db, st, uniformState(db->mesh(), alpha, set));
    step({drift.get(), disp.get()}, st, dt, std::lround(tEnd / dt));
    const auto m = gatherNatural(*db, st.masses(), 2);
    std::vector<double> y(n);
    for (int k = 0; k < n; ++k) y[k] = m[2 * k] / (m[2 * k] + m[2 * k + 1]);
    return y;
  };
  auto maxRelDiff = [](const std::vector<double> &a, const std::vector<double> &b) {
    double w = 0.0;
    for (size_t k = 0; k < a.size(); ++k) w = std::fmax(w, std::fabs(a[k] - b[k]) / b[k]);
    return w;
  };
  // Steady state: the operator-split scheme approaches the exact balance at
  // first order in the step.
  const double e1 = maxRelDiff(runTo(40.0, 4e-3), exact);
  const double e2 = maxRelDiff(runTo(40.0, 2e-3), exact);
  PetscPrintf(PETSC_COMM_WORLD,
              "steady drift-dispersion profile (top/bottom share %.1f): error %.3e (dt 4 ms), %.3e (dt 2 ms)\n",
              exact[n - 1] / exact[0], e1, e2);
  RCFD_CHECK(exact[n - 1] / exact[0] > 5.0); // the profile is far from flat
  RCFD_CHECK(e2 < 1.5e-2);
  RCFD_CHECK(e1 / e2 > 1.7 && e1 / e2 < 2.3);
  // Transient: the state at t = 1 s converges at first order as the step is refined.
  const auto reference = runTo(1.0, 6.25e-5);
  const double t1 = maxRelDiff(runTo(1.0, 2e-3), reference);
  const double t2 = maxRelDiff(runTo(1.0, 1e-3), reference);
  const double t3 = maxRelDiff(runTo(1.0, 5e-4), reference);
  PetscPrintf(PETSC_COMM_WORLD, "transient at t = 1 s: errors %.3e, %.3e, %.3e (ratios %.2f, %.2f)\n",
              t1, t2, t3, t1 / t2, t2 / t3);
  RCFD_CHECK(t1 / t2 > 1.6 && t1 / t2 < 2.5);
  RCFD_CHECK(t2 / t3 > 1.6 && t2 / t3 < 2.5);
}

// A column along x with gravity along -x gives the same answer as a column
// along z with gravity along -z: the operator sees only area vectors and
// gravity, not the mesh's axes.
void otherAxis() {
  const int n = 16;
  std::vector<double> alpha(n);
  for (int k = 0; k < n; ++k) alpha[k] = 0.3 + 0.02 * k;
  FractionSet set = rcfd::test::fractionSet({1.5e-3, 2.5e-3, 4e-3}, {0.3, 0.4, 0.3});
  std::vector<std::vector<double>> result;
  for (int axis : {2, 0}) {
    Vec3 g{0, 0, 0};
    g[axis] = -9.81;
    auto db = identityDb(column(axis, n, 0.16), alpha, g);
    RunContext ctx{*db, set, 1440.0};
    auto drift = makeOperator<DriftOperator>("-model B -kd 5e4 -local_d32 -hindered");
    auto disp = makeOperator<DispersionOperator>("-coefficient 1e-4");
    PetscCallAbort(PETSC_COMM_WORLD, drift->setUp(ctx));
    PetscCallAbort(PETSC_COMM_WORLD, disp->setUp(ctx));
    FractionState st;
    PetscCallAbort(PETSC_COMM_WORLD, st.create(db->layout(), 3));
    setNatural(*db, st, uniformState(db->mesh(), alpha, set));
    step({drift.get(), disp.get()}, st, 5e-3, 400);
    result.push_back(gatherNatural(*db, st.masses(), 3));
  }
  double worst = 0.0, moved = 0.0;
  for (size_t k = 0; k < result[0].size(); ++k)
    worst = std::fmax(worst, std::fabs(result[0][k] - result[1][k]) / result[0][k]);
  const auto start = uniformState(rcfd::test::boxMesh(column(2, n, 0.16)), alpha, set);
  for (size_t k = 0; k < start.size(); ++k)
    moved = std::fmax(moved, std::fabs(result[0][k] - start[k]) / start[k]);
  PetscPrintf(PETSC_COMM_WORLD, "x column vs z column: largest relative difference %.2e (change %.2f)\n",
              worst, moved);
  RCFD_CHECK(worst < 1e-12);
  RCFD_CHECK(moved > 0.1);
}

// Random bed with near-empty and near-packed cells, strong drift: bulk per
// cell unchanged, fractions conserved, no negative or non-finite mass.
void stress(int nf, const std::string &options, bool expectSubsteps) {
  BoxSpec spec;
  spec.nx = 6;
  spec.ny = 3;
  spec.nz = 12;
  spec.length = {0.03, 0.015, 0.06};
  const int N = spec.numCells();
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<double> alpha(N);
  for (int c = 0; c < N; ++c) {
    const double r = U(rng);
    alpha[c] = r < 0.1 ? 0.0 : r < 0.2 ? 1e-4 * U(rng) : r < 0.3 ? 0.64 : 0.6 * U(rng);
  }
  auto db = identityDb(spec, alpha, {0, 0, -9.81});
  std::vector<double> d(nf), w(nf, 1.0 / nf);
  for (int i = 0; i < nf; ++i) d[i] = nf == 1 ? 2e-3 : 0.5e-3 + 5.5e-3 * i / (nf - 1);
  FractionSet set = rcfd::test::fractionSet(d, w);
  RunContext ctx{*db, set, 1440.0};
  auto drift = makeOperator<DriftOperator>(options);
  PetscCallAbort(PETSC_COMM_WORLD, drift->setUp(ctx));
  FractionState st;
  PetscCallAbort(PETSC_COMM_WORLD, st.create(db->layout(), nf));
  std::vector<double> m0;
  for (int c = 0; c < N; ++c) {
    std::vector<double> y(nf);
    double s = 0;
    for (double &v : y) s += (v = U(rng) * U(rng));
    for (int i = 0; i < nf; ++i) m0.push_back(1440.0 * alpha[c] * db->mesh().cellVolume[c] * y[i] / s);
  }
  setNatural(*db, st, m0);
  std::vector<double> before, after;
  PetscCallAbort(PETSC_COMM_WORLD, st.totals(&before));
  step({drift.get()}, st, 5e-3, 200);
  PetscCallAbort(PETSC_COMM_WORLD, st.totals(&after));
  const auto m = gatherNatural(*db, st.masses(), nf);
  double worstBulk = 0.0, worstTotal = 0.0, lowest = 0.0, cellMax = 0.0;
  bool finite = true;
  for (int c = 0; c < N; ++c) {
    double b0 = 0, b1 = 0;
    for (int i = 0; i < nf; ++i) {
      b0 += m0[c * nf + i];
      b1 += m[c * nf + i];
      lowest = std::fmin(lowest, m[c * nf + i]);
      finite = finite && std::isfinite(m[c * nf + i]);
    }
    cellMax = std::fmax(cellMax, b0);
    worstBulk = std::fmax(worstBulk, std::fabs(b1 - b0));
  }
  for (int i = 0; i < nf; ++i) worstTotal = std::fmax(worstTotal, std::fabs(after[i] / before[i] - 1));
  double composition = 0.0; // the composition did change
  for (size_t k = 0; k < m.size(); ++k) composition = std::fmax(composition, std::fabs(m[k] - m0[k]));
  PetscPrintf(PETSC_COMM_WORLD,
              "stress nf = %2d (%s): bulk change %.1e of the largest cell, fraction totals %.1e, "
              "smallest mass %.1e, sub-steps %ld over %ld steps\n",
              nf, options.c_str(), worstBulk / cellMax, worstTotal, lowest, drift->substepsTaken(),
              drift->stepsTaken());
  RCFD_CHECK(finite);
  RCFD_CHECK(worstBulk <= 1e-13 * cellMax);
  RCFD_CHECK(worstTotal < 1e-12);
  RCFD_CHECK(lowest >= 0.0);
  RCFD_CHECK(composition > 1e-3 * cellMax);
  RCFD_CHECK(!expectSubsteps || drift->maxSubsteps() > 1);
}

// Steps `drift` on `db` from masses m0, with step k using frame k mod K; the masses after.
std::vector<double> stepFrames(const Database &db, DriftOperator &drift, const std::vector<double> &m0,
                               int nf, int steps) {
  FractionState st;
  PetscCallAbort(PETSC_COMM_WORLD, st.create(db.layout(), nf));
  setNatural(db, st, m0);
  for (int k = 0; k < steps; ++k) {
    StepInfo info;
    info.step = k;
    info.dt = db.metadata().dtRec;
    info.frame = k % db.numFrames();
    PetscCallAbort(PETSC_COMM_WORLD, drift.apply(info, st));
  }
  return gatherNatural(db, st.masses(), nf);
}

double largestRelativeDifference(const std::vector<double> &a, const std::vector<double> &b) {
  double worst = 0.0, scale = 0.0;
  for (size_t k = 0; k < a.size(); ++k) scale = std::fmax(scale, std::fabs(a[k]));
  for (size_t k = 0; k < a.size(); ++k) worst = std::fmax(worst, std::fabs(a[k] - b[k]));
  return worst / scale;
}

// Drift scaled by (a/a_bar)^n on the synthetic small.h5 (real shifts, so a
// real agitation field): n = 0 gives the unscaled drift bit for bit, a
// uniform field gives it to round-off, n = 2 gives something else.
void agitationScaling() {
  std::unique_ptr<Database> db;
  PetscCallAbort(PETSC_COMM_WORLD,
                 Database::load(PETSC_COMM_WORLD, dataDir + "/small.h5", DatabaseLoadOptions{}, &db));
  FractionSet set = rcfd::test::fractionSet({1.459e-3, 4.075e-3}, {0.564, 0.436});
  RunContext ctx{*db, set, 1440.0};
  const int N = db->mesh().numCells();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(0.05, 1.0);
  std::vector<double> m0;
  for (int c = 0; c < N; ++c) {
    const double bulk = 1440.0 * 0.4 * db->mesh().cellVolume[c], y = U(rng);
    m0.push_back(bulk * y);
    m0.push_back(bulk * (1.0 - y));
  }
  auto run = [&](const std::string &options, std::shared_ptr<const AgitationField> field = nullptr) {
    auto drift = makeOperator<DriftOperator>(options);
    if (field) drift->useAgitation(field);
    PetscCallAbort(PETSC_COMM_WORLD, drift->setUp(ctx));
    auto masses = stepFrames(*db, *drift, m0, 2, 40);
    return std::make_pair(masses, drift->substepsTaken());
  };
  const std::string law = "-model B -kd 2e5";
  const auto plain = run(law);
  const auto zero = run(law + " -agitation leaving -agitation_exponent 0");
  const auto zeroDispersion = run(law + " -agitation dispersion -agitation_exponent 0");
  const auto two = run(law + " -agitation leaving -agitation_exponent 2");
  RCFD_CHECK(plain.first == zero.first && plain.second == zero.second);
  RCFD_CHECK(plain.first == zeroDispersion.first);
  const double changed = largestRelativeDifference(plain.first, two.first);
  RCFD_CHECK(changed > 1e-3);
  RCFD_CHECK(two.second > plain.second); // the field's maximum sets the sub-steps
  // A uniform field: a / a_bar is 1 up to the round-off of the mean.
  auto uniform = std::make_shared<AgitationField>();
  PetscCallAbort(PETSC_COMM_WORLD,
                 uniform->setValues(*db, AgitationMeasure::LeavingShare,
                                    std::vector<std::vector<double>>(
                                        db->numFrames(), std::vector<double>(db->layout().numLocal(), 0.37))));
  const auto flat = run(law + " -agitation_exponent 3", uniform);
  const double roundOff = largestRelativeDifference(plain.first, flat.first);
  PetscPrintf(PETSC_COMM_WORLD,
              "agitation: exponent 0 bit for bit; uniform field differs by %.1e; exponent 2 by %.1e "
              "(sub-steps %ld against %ld)\n",
              roundOff, changed, two.second, plain.second);
  RCFD_CHECK(roundOff < 1e-12);
}

// The factor is that of the frame being applied: a field 2 in frame 0 and 0
// in frame 1 (a_bar = 1) moves nothing in frame 1 and drifts twice as fast
// in frame 0.
void agitationOfTheFrame() {
  const BoxSpec spec = column(2, 10, 0.1);
  const std::vector<double> alpha(10, 0.5);
  const std::string path = dir + "/drift_" + std::to_string(counter++) + ".h5";
  DatabaseMetadata meta;
  rcfd::test::writeIdentityDatabase(path, rcfd::test::boxMesh(spec), alpha, meta, 2);
  std::unique_ptr<Database> db;
  PetscCallAbort(PETSC_COMM_WORLD, Database::load(PETSC_COMM_WORLD, path, DatabaseLoadOptions{}, &db));
  FractionSet set = rcfd::test::fractionSet({1e-3, 3e-3}, {0.5, 0.5});
  RunContext ctx{*db, set, 1440.0};
  const PetscInt n = db->layout().numLocal();
  auto field = std::make_shared<AgitationField>();
  PetscCallAbort(PETSC_COMM_WORLD, field->setValues(*db, AgitationMeasure::Dispersion,
                                                    {std::vector<double>(n, 2.0), std::vector<double>(n, 0.0)}));
  RCFD_CHECK_CLOSE(field->solidWeightedMean(), 1.0, 1e-15);
  const auto m0 = uniformState(db->mesh(), alpha, set);
  auto scaled = makeOperator<DriftOperator>("-model B -kd 5e4 -agitation_exponent 1");
  scaled->useAgitation(field);
  PetscCallAbort(PETSC_COMM_WORLD, scaled->setUp(ctx));
  auto doubled = makeOperator<DriftOperator>("-model B -kd 1e5");
  PetscCallAbort(PETSC_COMM_WORLD, doubled->setUp(ctx));
  const auto one = stepFrames(*db, *scaled, m0, 2, 1), reference = stepFrames(*db, *doubled, m0, 2, 1);
  RCFD_CHECK(largestRelativeDifference(one, reference) < 1e-14);
  RCFD_CHECK(largestRelativeDifference(one, m0) > 1e-4);
  FractionState st; // a step with frame 1 changes nothing at all
  PetscCallAbort(PETSC_COMM_WORLD, st.create(db->layout(), 2));
  setNatural(*db, st, m0);
  StepInfo info;
  info.dt = 5e-3;
  info.frame = 1;
  PetscCallAbort(PETSC_COMM_WORLD, scaled->apply(info, st));
  RCFD_CHECK(gatherNatural(*db, st.masses(), 2) == m0);
}

// Each side of a face sends with its own factor: two cells, a = (1, 0) in
// frame 0 and (1, 1) in frame 1, so a_bar = 3/4 and frame 0's factors are
// (4/3, 0).  Fractions at +-u: the lower cell sends (4/3) m u dt A/V of the
// rising fraction, the upper cell none of the sinking one and tops up with
// its 50/50 mixture, so the rising fraction's net flux is half of that.
void agitationOfTheSendingCell() {
  const BoxSpec spec = column(2, 2, 0.02);
  const std::vector<double> alpha(2, 0.5);
  const std::string path = dir + "/drift_" + std::to_string(counter++) + ".h5";
  rcfd::test::writeIdentityDatabase(path, rcfd::test::boxMesh(spec), alpha, DatabaseMetadata{}, 2);
  std::unique_ptr<Database> db;
  PetscCallAbort(PETSC_COMM_WORLD, Database::load(PETSC_COMM_WORLD, path, DatabaseLoadOptions{}, &db));
  FractionSet set = rcfd::test::fractionSet({1e-3, 3e-3}, {0.5, 0.5});
  RunContext ctx{*db, set, 1440.0};
  std::vector<std::vector<double>> values(2);
  for (PetscInt i = 0; i < db->layout().numLocal(); ++i) {
    const int cell = db->layout().naturalCell(db->layout().rowStart() + i);
    values[0].push_back(cell == 0 ? 1.0 : 0.0);
    values[1].push_back(1.0);
  }
  auto field = std::make_shared<AgitationField>();
  PetscCallAbort(PETSC_COMM_WORLD, field->setValues(*db, AgitationMeasure::LeavingShare, values));
  auto drift = makeOperator<DriftOperator>("-model constant -velocities 0.01,-0.01 -agitation_exponent 1");
  drift->useAgitation(field);
  PetscCallAbort(PETSC_COMM_WORLD, drift->setUp(ctx));
  const auto m0 = uniformState(db->mesh(), alpha, set);
  const auto m = stepFrames(*db, *drift, m0, 2, 1);
  const double expected = 0.5 * (4.0 / 3.0) * m0[0] * 0.01 * 5e-3 / 0.01; // A/V = 1/(0.01 m)
  RCFD_CHECK_CLOSE(m[2] - m0[2], expected, 1e-12 * m0[2]);
  RCFD_CHECK_CLOSE(m0[0] - m[0], expected, 1e-12 * m0[0]);
}

// A drift set up again on another database (a run that switches databases)
// makes its agitation field for that database: it then drifts as one set up
// on it from the start, bit for bit.  The other database: small.h5's frames
// in reverse order (the same a_bar, other factors per frame).
void agitationFollowsTheDatabase() {
  std::unique_ptr<Database> db, reversed;
  PetscCallAbort(PETSC_COMM_WORLD,
                 Database::load(PETSC_COMM_WORLD, dataDir + "/small.h5", DatabaseLoadOptions{}, &db));
  const int K = db->numFrames();
  std::vector<OwnedVec> alpha(K);
  std::vector<OwnedMat> shifts(K);
  for (int k = 0; k < K; ++k) {
    PetscCallAbort(PETSC_COMM_WORLD, VecDuplicate(db->alphaS(K - 1 - k), alpha[k].put()));
    PetscCallAbort(PETSC_COMM_WORLD, VecCopy(db->alphaS(K - 1 - k), alpha[k]));
    PetscCallAbort(PETSC_COMM_WORLD, db->shiftMatrix(K - 1 - k, &shifts[k]));
  }
  PetscCallAbort(PETSC_COMM_WORLD,
                 Database::fromFrames(*db, "reversed", std::move(alpha), std::move(shifts), &reversed));
  FractionSet set = rcfd::test::fractionSet({1.459e-3, 4.075e-3}, {0.564, 0.436});
  const std::string law = "-model B -kd 2e5 -agitation leaving -agitation_exponent 2";
  auto switched = makeOperator<DriftOperator>(law), fresh = makeOperator<DriftOperator>(law);
  PetscCallAbort(PETSC_COMM_WORLD, switched->setUp(RunContext{*db, set, 1440.0}));
  PetscCallAbort(PETSC_COMM_WORLD, switched->setUp(RunContext{*reversed, set, 1440.0}));
  PetscCallAbort(PETSC_COMM_WORLD, fresh->setUp(RunContext{*reversed, set, 1440.0}));
  RCFD_CHECK(switched->agitationField()->databaseIdentity() == "reversed");
  std::vector<double> m0;
  for (int c = 0; c < reversed->mesh().numCells(); ++c) {
    const double bulk = 1440.0 * 0.4 * reversed->mesh().cellVolume[c];
    m0.push_back(0.3 * bulk);
    m0.push_back(0.7 * bulk);
  }
  RCFD_CHECK(stepFrames(*reversed, *switched, m0, 2, 20) == stepFrames(*reversed, *fresh, m0, 2, 20));
}

// The drift written the straightforward way, face by face on the whole mesh
// in natural order (every rank computes all of it): what the operator's
// kernel must give to round-off.
struct ReferenceDrift {
  char model = 'B'; // 'A', 'B', 'c' (constant) or 'L' (law)
  double kd = 5e3, alphaMin = 1e-3, alphaMax = 0.65, maxShare = 0.5, exponent = 1.0;
  bool localD32 = false, hindered = false;
  std::vector<double> velocities;
  std::function<double(double d, double d32)> law; // u of model 'L', k included
  std::vector<std::vector<double>> agitation; // per frame, natural order (empty: unscaled)

  std::vector<double> run(const Database &db, const FractionSet &set, std::vector<double> m, int steps,
                          long *substeps) const {
    const Mesh &mesh = db.mesh();
    const int nf = set.size(), N = mesh.numCells();
    const double rho = 1440.0, d32 = set.inventorySauterDiameter();
    std::vector<double> d(nf);
    for (int i = 0; i < nf; ++i) d[i] = set.diameter(i);
    auto velocity = [&](int i, double s) {
      return model == 'A' ? -kd * (d[i] * d[i] - s * s)
             : model == 'B' ? -kd * (d[i] - s) * std::fabs(d[i] - s)
             : model == 'L' ? law(d[i], s) : velocities[i];
    };
    struct Face { int lower, upper; double area; };
    std::vector<Face> faces;
    std::vector<double> sentUp(N, 0.0), sentDown(N, 0.0), count(N, 0.0);
    const Vec3 g = db.metadata().gravity;
    const double gn = std::hypot(g[0], g[1], g[2]);
    for (int f = 0; f < mesh.numFaces(); ++f) {
      const Vec3 &S = mesh.faceArea[f];
      const double area = std::hypot(S[0], S[1], S[2]);
      const double along = -(S[0] * g[0] + S[1] * g[1] + S[2] * g[2]) / gn;
      if (std::fabs(along) <= 1e-9 * area) continue;
      int lo = mesh.faceOwner[f], up = mesh.faceNeighbour[f];
      if (along < 0) std::swap(lo, up);
      faces.push_back({lo, up, std::fabs(along)});
      sentUp[lo] += std::fabs(along) / mesh.cellVolume[lo];
      sentDown[up] += std::fabs(along) / mesh.cellVolume[up];
      count[lo] += 1, count[up] += 1;
    }
    double maxAoverV = 0.0, maxFaces = 0.0, umax = 0.0;
    for (int c = 0; c < N; ++c) maxAoverV = std::max({maxAoverV, sentUp[c], sentDown[c]}), maxFaces = std::max(maxFaces, count[c]);
    const double dmin = *std::min_element(d.begin(), d.end()), dmax = *std::max_element(d.begin(), d.end());
    for (int i = 0; i < nf; ++i)
      umax = localD32 ? std::max({umax, std::fabs(velocity(i, dmin)), std::fabs(velocity(i, dmax))})
                      : std::max(umax, std::fabs(velocity(i, d32)));
    const double faceShare = 0.999 * (1.0 - maxShare) / maxFaces;
    for (int k = 0; k < steps; ++k) {
      const int frame = k % db.numFrames();
      const double dt = db.metadata().dtRec;
      std::vector<double> scale(N, 1.0);
      double largest = 1.0;
      if (!agitation.empty()) {
        largest = 0.0;
        for (int c = 0; c < N; ++c) largest = std::max(largest, scale[c] = std::pow(agitation[frame][c], exponent));
      }
      const int n = std::max(1, static_cast<int>(std::ceil(umax * largest * maxAoverV * dt / maxShare)));
      *substeps += n;
      for (int s = 0; s < n; ++s) {
        std::vector<double> change(m.size(), 0.0), uL(nf), uU(nf), pL(nf), pU(nf);
        for (const Face &f : faces) {
          const double *mL = &m[f.lower * nf], *mU = &m[f.upper * nf];
          const double VL = mesh.cellVolume[f.lower], VU = mesh.cellVolume[f.upper];
          double ML = 0.0, MU = 0.0;
          for (int i = 0; i < nf; ++i) ML += mL[i], MU += mU[i];
          if (!(ML > 0.0 && MU > 0.0) || ML < alphaMin * rho * VL || MU < alphaMin * rho * VU) continue;
          double cL = f.area / VL * (dt / n) * scale[f.lower], cU = f.area / VU * (dt / n) * scale[f.upper];
          if (hindered) {
            cL *= std::max(0.0, 1.0 - ML / (rho * VL * alphaMax));
            cU *= std::max(0.0, 1.0 - MU / (rho * VU * alphaMax));
          }
          auto sauter = [&](const double *mc, double total) {
            double sum = 0.0;
            for (int i = 0; i < nf; ++i) sum += mc[i] / d[i];
            return sum > 0 ? total / sum : d32;
          };
          const double sL = localD32 ? sauter(mL, ML) : d32, sU = localD32 ? sauter(mU, MU) : d32;
          double up = 0.0, down = 0.0;
          for (int i = 0; i < nf; ++i) {
            uL[i] = velocity(i, sL), uU[i] = velocity(i, sU);
            up += pL[i] = uL[i] > 0 ? mL[i] * uL[i] * cL : 0.0;
            down += pU[i] = uU[i] < 0 ? -mU[i] * uU[i] * cU : 0.0;
          }
          const double X = std::max(up, down);
          if (X <= 0.0) continue;
          const double lambda = std::min({1.0, faceShare / X * ML, faceShare / X * MU});
          const double topL = (X - up) / ML, topU = (X - down) / MU;
          for (int i = 0; i < nf; ++i) {
            const double net = lambda * (pL[i] + topL * mL[i]) - lambda * (pU[i] + topU * mU[i]);
            change[f.lower * nf + i] -= net;
            change[f.upper * nf + i] += net;
          }
        }
        for (size_t j = 0; j < m.size(); ++j) m[j] += change[j];
      }
    }
    return m;
  }
};

// The operator against ReferenceDrift along 90 frames of small.h5 (a bed
// with its freeboard, bubbles made in it and cells below alpha_min), for the
// default law and each option that changes the kernel's path: to 1e-13 of
// the largest mass, the same sub-steps, every fraction's total to 1e-12 and
// no negative mass.
void againstReference() {
  std::unique_ptr<Database> db;
  PetscCallAbort(PETSC_COMM_WORLD,
                 Database::load(PETSC_COMM_WORLD, dataDir + "/small.h5", DatabaseLoadOptions{}, &db));
  const Mesh &mesh = db->mesh();
  const int N = mesh.numCells(), K = db->numFrames();
  std::vector<double> alpha;
  db->layout().gatherToAll(1, db->alphaS(0), &alpha);
  // An agitation field known per natural cell and frame, a_bar taken from it.
  auto field = std::make_shared<AgitationField>();
  std::vector<std::vector<double>> natural(K, std::vector<double>(N)), local(K);
  for (int k = 0; k < K; ++k) {
    for (int c = 0; c < N; ++c) natural[k][c] = 0.2 + 0.8 * std::fabs(std::sin(0.37 * c + 0.11 * k));
    for (PetscInt r = 0; r < db->layout().numLocal(); ++r)
      local[k].push_back(natural[k][db->layout().naturalCell(db->layout().rowStart() + r)]);
  }
  PetscCallAbort(PETSC_COMM_WORLD, field->setValues(*db, AgitationMeasure::LeavingShare, local));
  int checked = 0;
  auto compare = [&](const std::vector<double> &d, const std::vector<double> &w, const std::string &options,
                     ReferenceDrift reference) {
    FractionSet set = rcfd::test::fractionSet(d, w);
    const int nf = set.size();
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    std::vector<double> m0;
    for (int c = 0; c < N; ++c) {
      const double r = U(rng);
      const double a = r < 0.05 ? 0.0 : r < 0.1 ? 2e-4 * alpha[c] : alpha[c]; // bubbles, dilute cells
      std::vector<double> y(nf);
      double s = 0.0;
      for (double &v : y) s += (v = 0.05 + U(rng));
      for (int i = 0; i < nf; ++i) m0.push_back(1440.0 * a * mesh.cellVolume[c] * y[i] / s);
    }
    auto drift = makeOperator<DriftOperator>(options);
    if (!reference.agitation.empty()) {
      drift->useAgitation(field);
      for (auto &frame : reference.agitation)
        for (double &v : frame) v /= field->solidWeightedMean();
    }
    PetscCallAbort(PETSC_COMM_WORLD, drift->setUp(RunContext{*db, set, 1440.0}));
    long substeps = 0;
    const auto expected = reference.run(*db, set, m0, 90, &substeps);
    const auto got = stepFrames(*db, *drift, m0, nf, 90);
    double lowest = 0.0, worstTotal = 0.0;
    for (double v : got) lowest = std::fmin(lowest, v);
    for (int i = 0; i < nf; ++i) {
      double before = 0.0, after = 0.0;
      for (int c = 0; c < N; ++c) before += m0[c * nf + i], after += got[c * nf + i];
      worstTotal = std::fmax(worstTotal, std::fabs(after / before - 1.0));
    }
    const double difference = largestRelativeDifference(expected, got), moved = largestRelativeDifference(m0, got);
    PetscPrintf(PETSC_COMM_WORLD,
                "against the reference, nf = %d (%s): difference %.1e of the largest mass (drift moved %.1e), "
                "sub-steps %ld (reference %ld), totals %.1e, smallest mass %.1e\n",
                nf, options.c_str(), difference, moved, drift->substepsTaken(), substeps, worstTotal, lowest);
    RCFD_CHECK(difference < 1e-13);
    RCFD_CHECK(moved > 1e-6);
    RCFD_CHECK(drift->substepsTaken() == substeps);
    RCFD_CHECK(worstTotal < 1e-12);
    RCFD_CHECK(lowest >= 0.0);
    ++checked;
    return drift->substepsTaken();
  };
  const std::vector<double> penta = {1.783e-3, 1.998e-3, 2.284e-3, 2.855e-3, 3.426e-3},
                            pentaShares = {0.100, 0.205, 0.445, 0.150, 0.100};
  compare(penta, pentaShares, "-model B -kd 5e3", {});
  RCFD_CHECK(compare({1.459e-3, 4.075e-3}, {0.564, 0.436}, "-model B -kd 3e6", {'B', 3e6}) > 90); // sub-steps
  ReferenceDrift localD32{'A', 5e4};
  localD32.localD32 = true;
  compare(penta, pentaShares, "-model A -kd 5e4 -local_d32", localD32);
  ReferenceDrift hindered{'B', 1e5};
  hindered.hindered = true;
  hindered.alphaMax = 0.6;
  compare(penta, pentaShares, "-model B -kd 1e5 -hindered -alpha_max 0.6", hindered);
  ReferenceDrift floorless{'B', 5e4};
  floorless.alphaMin = 0.0;
  floorless.maxShare = 0.3;
  compare(penta, pentaShares, "-model B -kd 5e4 -alpha_min 0 -max_share 0.3", floorless);
  ReferenceDrift constant{'c'};
  constant.velocities = {0.02, -0.01, 0.0};
  compare({1e-3, 2e-3, 3e-3}, {0.3, 0.3, 0.4}, "-model constant -velocities 0.02,-0.01,0", constant);
  ReferenceDrift scaled{'B', 5e4};
  scaled.agitation = natural;
  scaled.exponent = 2.0;
  compare(penta, pentaShares, "-model B -kd 5e4 -agitation_exponent 2", scaled);
  // Seven fractions: the kernel's general path (no unrolled instance).
  ReferenceDrift seven{'A', 5e3};
  seven.localD32 = seven.hindered = true;
  compare({1e-3, 1.5e-3, 2e-3, 2.5e-3, 3e-3, 3.5e-3, 4e-3}, std::vector<double>(7, 1.0 / 7.0),
          "-model A -kd 5e3 -local_d32 -hindered", seven);
  // The dimensionless size laws (k in m/s), each with the local d32 (its
  // sub-step bound from the smallest and the largest diameter) and once with
  // the inventory's, scaled and hindered.
  ReferenceDrift drag{'L'};
  drag.localD32 = true;
  drag.law = [](double d, double s) { return 0.05 * (s / d - 1.0); };
  compare(penta, pentaShares, "-size_law drag -kd 0.05 -local_d32", drag);
  ReferenceDrift logLaw{'L'};
  logLaw.localD32 = true;
  logLaw.law = [](double d, double s) { return 0.05 * std::log(s / d); };
  compare(penta, pentaShares, "-size_law log -kd 0.05 -local_d32", logLaw);
  ReferenceDrift power{'L'};
  power.localD32 = true;
  power.law = [](double d, double s) { return 3.0 * (std::pow(s / d, 2.5) - 1.0); };
  RCFD_CHECK(compare(penta, pentaShares, "-size_law power -size_law_exponent 2.5 -kd 3 -local_d32", power) > 90);
  ReferenceDrift powerScaled{'L'};
  powerScaled.hindered = true;
  powerScaled.agitation = natural;
  powerScaled.exponent = 2.0;
  powerScaled.law = [](double d, double s) { return 0.05 * (std::pow(s / d, 0.6) - 1.0); };
  compare(penta, pentaShares, "-size_law power -size_law_exponent 0.6 -kd 0.05 -hindered -agitation_exponent 2",
          powerScaled);
  RCFD_CHECK(checked == 12);
}

// The state's bound on where mass can be (FractionState::occupiedEnd): after
// every shift (given the exact bound before it) and every drift of 90 frames
// of small.h5 no own cell at or above it holds mass, the bound leaves cells
// out on some rank, a write that does not
// renew it (or a swap of the vectors) makes it unknown, and the run gives
// the same bits as one whose bound is made unknown after every operator.
void occupiedBound() {
  std::unique_ptr<Database> db;
  PetscCallAbort(PETSC_COMM_WORLD,
                 Database::load(PETSC_COMM_WORLD, dataDir + "/small.h5", DatabaseLoadOptions{}, &db));
  const FractionSet set = rcfd::test::fractionSet({1.783e-3, 1.998e-3, 2.284e-3, 2.855e-3, 3.426e-3}, {0.100, 0.205, 0.445, 0.150, 0.100});
  const int nf = set.size();
  const PetscInt nlocal = db->layout().numLocal();
  std::vector<double> alpha;
  db->layout().gatherToAll(1, db->alphaS(0), &alpha);
  const RunContext ctx{*db, set, 1440.0};
  long leftOut = 0, wrong = 0;
  auto boundHolds = [&](const FractionState &st) {
    PetscInt end;
    const PetscScalar *m;
    PetscCallAbort(PETSC_COMM_WORLD, st.occupiedEnd(&end));
    PetscCallAbort(PETSC_COMM_WORLD, VecGetArrayRead(st.masses(), &m));
    for (PetscInt k = end * nf; k < nlocal * nf; ++k) wrong += m[k] != 0.0;
    PetscCallAbort(PETSC_COMM_WORLD, VecRestoreArrayRead(st.masses(), &m));
    leftOut += nlocal - end;
  };
  auto exactly = [&](FractionState &st) { // the bound right above the last own cell holding mass
    const PetscScalar *m;
    PetscInt end = 0;
    PetscCallAbort(PETSC_COMM_WORLD, VecGetArrayRead(st.masses(), &m));
    for (PetscInt k = 0; k < nlocal * nf; ++k)
      if (m[k] != 0.0) end = k / nf + 1;
    PetscCallAbort(PETSC_COMM_WORLD, VecRestoreArrayRead(st.masses(), &m));
    PetscCallAbort(PETSC_COMM_WORLD, st.setOccupiedEnd(end));
  };
  auto forget = [&](FractionState &st) { // a write that says nothing of where the mass is
    PetscScalar *m;
    PetscCallAbort(PETSC_COMM_WORLD, VecGetArray(st.masses(), &m));
    PetscCallAbort(PETSC_COMM_WORLD, VecRestoreArray(st.masses(), &m));
    PetscInt end;
    PetscCallAbort(PETSC_COMM_WORLD, st.occupiedEnd(&end));
    RCFD_CHECK(end == nlocal);
  };
  auto run = [&](bool renew) {
    FractionState st;
    PetscCallAbort(PETSC_COMM_WORLD, st.create(db->layout(), nf));
    setNatural(*db, st, uniformState(db->mesh(), alpha, set));
    ShiftOperator shift;
    PetscCallAbort(PETSC_COMM_WORLD, shift.setUp(ctx));
    auto drift = makeOperator<DriftOperator>("-model B -kd 5e4");
    PetscCallAbort(PETSC_COMM_WORLD, drift->setUp(ctx));
    for (int k = 0; k < 90; ++k) {
      StepInfo info;
      info.step = k;
      info.dt = db->metadata().dtRec;
      info.frame = k % db->numFrames();
      info.nextFrame = (k + 1) % db->numFrames();
      if (renew) exactly(st); // so that the shift's own rows decide
      PetscCallAbort(PETSC_COMM_WORLD, shift.apply(info, st));
      if (renew) boundHolds(st);
      else forget(st);
      PetscCallAbort(PETSC_COMM_WORLD, drift->apply(info, st));
      if (renew) boundHolds(st);
      else forget(st);
    }
    PetscCallAbort(PETSC_COMM_WORLD, st.setOccupiedEnd(0));
    st.swap();
    PetscInt end;
    PetscCallAbort(PETSC_COMM_WORLD, st.occupiedEnd(&end));
    RCFD_CHECK(end == nlocal);
    st.swap();
    return gatherNatural(*db, st.masses(), nf);
  };
  const auto bounded = run(true), unknown = run(false);
  MPI_Allreduce(MPI_IN_PLACE, &leftOut, 1, MPI_LONG, MPI_SUM, PETSC_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, &wrong, 1, MPI_LONG, MPI_SUM, PETSC_COMM_WORLD);
  PetscPrintf(PETSC_COMM_WORLD, "occupied bound: %ld cell-steps left out, %ld masses above it, runs %s\n", leftOut,
              wrong, bounded == unknown ? "the same bits" : "DIFFERENT");
  RCFD_CHECK(leftOut > 90 * 20);
  RCFD_CHECK(wrong == 0);
  RCFD_CHECK(bounded == unknown);
}

void leftOutWhenNotNeeded() {
  auto db = identityDb(column(2, 4, 0.04), std::vector<double>(4, 0.5), {0, 0, -9.81});
  FractionSet one = rcfd::test::fractionSet({2e-3}, {1.0}), two = rcfd::test::fractionSet({1e-3, 2e-3}, {0.5, 0.5});
  RCFD_CHECK(!makeOperator<DriftOperator>("-model B")->needed(RunContext{*db, one, 1440.0}));
  RCFD_CHECK(!makeOperator<DriftOperator>("-model B -kd 0")->needed(RunContext{*db, two, 1440.0}));
  RCFD_CHECK(!makeOperator<DriftOperator>("-model none")->needed(RunContext{*db, two, 1440.0}));
  RCFD_CHECK(!makeOperator<DriftOperator>("-model constant -velocities 0,0")->needed(RunContext{*db, two, 1440.0}));
  RCFD_CHECK(makeOperator<DriftOperator>("-model A -kd 500")->needed(RunContext{*db, two, 1440.0}));
  RCFD_CHECK(!makeOperator<DispersionOperator>("")->needed(RunContext{*db, two, 1440.0}));
  Pipeline p;
  PetscCallAbort(PETSC_COMM_WORLD, p.add(makeOperator<DriftOperator>("-model B")));
  PetscCallAbort(PETSC_COMM_WORLD, p.setUp(RunContext{*db, one, 1440.0}));
  RCFD_CHECK(p.operators().empty() && p.skipped().size() == 1 && p.skipped()[0] == "drift");
}

} // namespace

// A two-cell column (identity shifts, alpha 0.5, 1 cm cells) for one face.
std::unique_ptr<Database> twoCells(int frames = 1) {
  const std::string path = dir + "/drift_" + std::to_string(counter++) + ".h5";
  rcfd::test::writeIdentityDatabase(path, rcfd::test::boxMesh(column(2, 2, 0.02)), {0.5, 0.5}, DatabaseMetadata{}, frames);
  std::unique_ptr<Database> db;
  PetscCallAbort(PETSC_COMM_WORLD, Database::load(PETSC_COMM_WORLD, path, DatabaseLoadOptions{}, &db));
  return db;
}

// Each size law against values by hand for three classes of 1.5, 2 and 3 mm
// (mass shares 0.3, 0.4, 0.3: d32 = 2 mm), at the inventory's d32 and at
// 2.5 mm; then with -local_d32 on one face whose cells have other
// compositions (d32 1.765 and 2.4 mm): the exchange of one step of Eq. 6
// with the top-up, written here with each cell's own d32.
void sizeLawsByHand() {
  auto db = twoCells();
  const std::vector<double> d{1.5e-3, 2.0e-3, 3.0e-3};
  FractionSet set = rcfd::test::fractionSet(d, {0.3, 0.4, 0.3});
  RunContext ctx{*db, set, 1440.0};
  RCFD_CHECK_CLOSE(set.inventorySauterDiameter(), 2e-3, 1e-15);
  struct Case {
    std::string options;
    std::vector<double> atD32, at25; // u [m/s] of the three classes at d_ref = 2 and 2.5 mm
    std::function<double(double d, double s)> law;
  };
  const double k = 0.02, l43 = std::log(4.0 / 3.0), l53 = std::log(5.0 / 3.0);
  const std::vector<Case> cases{
      {"-size_law A -kd 5e3", {8.75e-3, 0.0, -0.025}, {0.02, 0.01125, -0.01375},
       [](double di, double s) { return -5e3 * (di * di - s * s); }},
      {"-model B -kd 5e3", {1.25e-3, 0.0, -5e-3}, {5e-3, 1.25e-3, -1.25e-3},
       [](double di, double s) { return -5e3 * (di - s) * std::fabs(di - s); }},
      {"-size_law drag -kd 0.02", {k / 3.0, 0.0, -k / 3.0}, {k * 2.0 / 3.0, k / 4.0, -k / 6.0},
       [k](double di, double s) { return k * (s / di - 1.0); }},
      {"-size_law log -kd 0.02", {k * l43, 0.0, k * (std::log(2.0) - std::log(3.0))},
       {k * l53, k * std::log(1.25), k * std::log(5.0 / 6.0)},
       [k](double di, double s) { return k * std::log(s / di); }},
      {"-size_law power -size_law_exponent 2 -kd 0.02", {k * 7.0 / 9.0, 0.0, -k * 5.0 / 9.0},
       {k * 16.0 / 9.0, k * 0.5625, -k * 11.0 / 36.0},
       [k](double di, double s) { return k * ((s / di) * (s / di) - 1.0); }},
  };
  const std::vector<double> yL{0.6, 0.2, 0.2}, yU{0.1, 0.3, 0.6};
  const double M = 1440.0 * 0.5 * 1e-6, dt = 5e-3, AoverV = 100.0; // 1 cm cube, alpha 0.5
  for (const Case &c : cases) {
    auto fixed = makeOperator<DriftOperator>(c.options);
    PetscCallAbort(PETSC_COMM_WORLD, fixed->setUp(ctx));
    double worst = 0.0;
    for (int i = 0; i < 3; ++i) {
      worst = std::fmax(worst, std::fabs(fixed->velocity(i, set.inventorySauterDiameter()) - c.atD32[i]));
      worst = std::fmax(worst, std::fabs(fixed->velocity(i, 2.5e-3) - c.at25[i]));
    }
    // The face with each cell's own d32.
    auto local = makeOperator<DriftOperator>(c.options + " -local_d32");
    PetscCallAbort(PETSC_COMM_WORLD, local->setUp(ctx));
    std::vector<double> m0;
    for (double y : yL) m0.push_back(M * y);
    for (double y : yU) m0.push_back(M * y);
    const auto m = stepFrames(*db, *local, m0, 3, 1);
    auto sauter = [&](const std::vector<double> &y) { return 1.0 / (y[0] / d[0] + y[1] / d[1] + y[2] / d[2]); };
    const double sL = sauter(yL), sU = sauter(yU);
    std::vector<double> pL(3), pU(3);
    double up = 0.0, down = 0.0;
    for (int i = 0; i < 3; ++i) {
      up += pL[i] = M * yL[i] * std::max(c.law(d[i], sL), 0.0) * AoverV * dt;
      down += pU[i] = M * yU[i] * std::max(-c.law(d[i], sU), 0.0) * AoverV * dt;
    }
    const double X = std::max(up, down);
    double worstFace = 0.0;
    for (int i = 0; i < 3; ++i) {
      const double net = pL[i] + (X - up) * yL[i] - pU[i] - (X - down) * yU[i];
      worstFace = std::fmax(worstFace, std::fabs(m[3 + i] - (m0[3 + i] + net)) / M);
      worstFace = std::fmax(worstFace, std::fabs(m[i] - (m0[i] - net)) / M);
    }
    PetscPrintf(PETSC_COMM_WORLD, "size law by hand (%s): u at d32 and 2.5 mm within %.1e m/s, the face with local d32 "
                                  "within %.1e of the cell mass (moved %.2e)\n",
                c.options.c_str(), worst, worstFace, std::fabs(m[3] - m0[3]) / M);
    RCFD_CHECK(worst < 1e-15);
    RCFD_CHECK(worstFace < 1e-15);
    RCFD_CHECK(std::fabs(m[3] - m0[3]) / M > 1e-4);
  }
}

// No net volume: with d32 = 1/sum(w_i/d_i) the drag law's sum_i w_i u_i is
// k (d32 sum w_i/d_i - 1) = 0 for any shares; the other laws carry volume.
// 200 random shares of five classes.
void noNetVolume() {
  const SizeLawRegistry laws = SizeLawRegistry::withBuiltins();
  const std::vector<double> d{1.4e-3, 1.75e-3, 2.3e-3, 2.9e-3, 3.6e-3};
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::map<std::string, double> largest; // of |sum w u| / max |u|
  for (int draw = 0; draw < 200; ++draw) {
    std::vector<double> w(5);
    double sum = 0.0;
    for (double &v : w) sum += (v = U(rng));
    double inverse = 0.0;
    for (int i = 0; i < 5; ++i) inverse += (w[i] /= sum) / d[i];
    for (const std::string name : {"drag", "A", "B", "log", "power"}) {
      auto law = created(laws, name);
      if (name == "power") law->setShapeParameter(2.0);
      std::vector<double> u(5);
      law->velocities(name == "A" || name == "B" ? 5e3 : 1.0, 1.0 / inverse, d.data(), 5, u.data());
      double net = 0.0, top = 0.0;
      for (int i = 0; i < 5; ++i) net += w[i] * u[i], top = std::fmax(top, std::fabs(u[i]));
      largest[name] = std::fmax(largest[name], std::fabs(net) / top);
    }
  }
  PetscPrintf(PETSC_COMM_WORLD, "no net volume: |sum w u| / max |u| at most drag %.1e, A %.2f, B %.2f, log %.2f, "
                                "power (m 2) %.2f\n",
              largest["drag"], largest["A"], largest["B"], largest["log"], largest["power"]);
  RCFD_CHECK(largest["drag"] < 1e-15);
  for (const char *name : {"A", "B", "log", "power"}) RCFD_CHECK(largest[name] > 0.02);
}

// A law a user registers in the operator registry reaches the drift:
// u = k (d32 - d)/d32, chosen by -drift_size_law, gives its velocities and
// moves the small class up; a drift made without that registry refuses it.
class LinearLaw : public SizeLaw {
public:
  std::string type() const override { return "linear"; }
  void velocities(double k, double dRef, const double *d, int n, double *u) const override {
    for (int i = 0; i < n; ++i) u[i] = k * (dRef - d[i]) / dRef;
  }
  const char *unitOfK() const override { return "m/s"; }
  std::string formula() const override { return "u = kd (d32 - d)/d32"; }
};

void userSizeLaw() {
  OperatorRegistry registry = OperatorRegistry::withBuiltins();
  registered(registry.sizeLaws(), "linear", [] { return std::make_unique<LinearLaw>(); }, "u = k (d32 - d)/d32");
  auto op = created(registry, "drift");
  const std::string prefix = "t" + std::to_string(counter++) + "_";
  PetscCallAbort(PETSC_COMM_WORLD,
                 PetscOptionsInsertString(nullptr, ("-" + prefix + "size_law linear -" + prefix + "kd 0.01").c_str()));
  op->setOptionsPrefix(prefix);
  PetscCallAbort(PETSC_COMM_WORLD, op->setFromOptions(PETSC_COMM_WORLD));
  auto *drift = dynamic_cast<DriftOperator *>(op.get());
  RCFD_CHECK(drift && drift->sizeLawName() == "linear");
  auto db = twoCells();
  FractionSet set = rcfd::test::fractionSet({1e-3, 3e-3}, {0.5, 0.5}); // d32 1.5 mm
  PetscCallAbort(PETSC_COMM_WORLD, drift->setUp(RunContext{*db, set, 1440.0}));
  RCFD_CHECK_CLOSE(drift->velocity(0, 1.5e-3), 0.01 / 3.0, 1e-15);
  RCFD_CHECK_CLOSE(drift->velocity(1, 1.5e-3), -0.01, 1e-15);
  const auto m0 = uniformState(db->mesh(), {0.5, 0.5}, set);
  const auto m = stepFrames(*db, *drift, m0, 2, 1);
  RCFD_CHECK(m[2] > m0[2] * (1.0 + 1e-4)); // the small class rose into the upper cell
  DriftOperator plain;                      // the built-in laws only
  RCFD_CHECK(plain.sizeLawName() == "B");
  ErrorCapture error;
  RCFD_CHECK(plain.setSizeLaw("linear") == PETSC_ERR_USER_INPUT);
  RCFD_CHECK(error.message().find("unknown size law 'linear'") != std::string::npos);
}

// Two beds at different agitation (uniform leaving shares 0.05 and 0.10 per
// 5 ms frame) drift alike per unit agitation with a fixed reference (-drift_
// agitation_reference 10 1/s: factors 1 and 2), but alike in absolute terms
// with each database's own a_bar (both factors 1), which hides the
// difference.
void agitationReference() {
  auto db = twoCells();
  FractionSet set = rcfd::test::fractionSet({1e-3, 3e-3}, {0.5, 0.5});
  RunContext ctx{*db, set, 1440.0};
  const auto m0 = uniformState(db->mesh(), {0.5, 0.5}, set);
  auto moved = [&](double a, const std::string &options, double *normaliser) {
    auto field = std::make_shared<AgitationField>();
    PetscCallAbort(PETSC_COMM_WORLD,
                   field->setValues(*db, AgitationMeasure::LeavingShare,
                                    {std::vector<double>(db->layout().numLocal(), a)}));
    auto drift = makeOperator<DriftOperator>("-model B -kd 5e4 -agitation_exponent 1 " + options);
    drift->useAgitation(field);
    PetscCallAbort(PETSC_COMM_WORLD, drift->setUp(ctx));
    *normaliser = drift->agitationNormaliser();
    const auto m = stepFrames(*db, *drift, m0, 2, 1);
    return m[2] - m0[2]; // small particles risen into the upper cell
  };
  double n1, n2, r1, r2;
  const double own1 = moved(0.05, "", &n1), own2 = moved(0.10, "", &n2);
  const double ref1 = moved(0.05, "-agitation_reference 10", &r1), ref2 = moved(0.10, "-agitation_reference 10", &r2);
  PetscPrintf(PETSC_COMM_WORLD, "agitation reference: bed 2 / bed 1 moved %.15f with the own a_bar (%g, %g), %.15f "
                                "with a_ref = 10 1/s (a_ref dt_rec %g)\n",
              own2 / own1, n1, n2, ref2 / ref1, r1);
  RCFD_CHECK(own1 > 0.0);
  RCFD_CHECK_CLOSE(own2 / own1, 1.0, 1e-14);
  RCFD_CHECK_CLOSE((ref2 / 0.10) / (ref1 / 0.05), 1.0, 1e-12); // per unit agitation
  RCFD_CHECK_CLOSE(r1, 10.0 * 5e-3, 1e-15);
  RCFD_CHECK_CLOSE(ref1, own1, 1e-12 * own1); // a = a_ref dt_rec: the factor is 1
}

// -drift_excess_gas: every velocity times u_sup - u_mf, u_mf by Wen & Yu
// at the inventory's d32 in the run's gas (worked out here by hand); two
// beds at 1.2 and 1.6 m/s move in that ratio, a bed below u_mf does not
// drift at all, and a run that knows no u_sup is refused.
void excessGas() {
  auto db = twoCells();
  FractionSet set = rcfd::test::fractionSet({1e-3, 3e-3}, {0.5, 0.5});
  const auto m0 = uniformState(db->mesh(), {0.5, 0.5}, set);
  const double d32 = 1.0 / (0.5 / 1e-3 + 0.5 / 3e-3), rhoG = 1.189, nu = 1e-5, mu = rhoG * nu;
  const Vec3 g = db->metadata().gravity;
  const double gravity = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  const double ar = gravity * d32 * d32 * d32 * rhoG * (1440.0 - rhoG) / (mu * mu);
  const double umf = (std::sqrt(33.7 * 33.7 + 0.0408 * ar) - 33.7) * mu / (rhoG * d32);
  auto run = [&](double usup, double *factor) {
    OperatingConditions c;
    c.superficialVelocity = usup;
    c.gasDensity = rhoG;
    c.gasKinematicViscosity = nu;
    RunContext ctx{*db, set, 1440.0, &c};
    auto drift = makeOperator<DriftOperator>("-size_law drag -kd 0.05 -excess_gas");
    PetscCallAbort(PETSC_COMM_WORLD, drift->setUp(ctx));
    *factor = drift->excessGasFactor();
    return stepFrames(*db, *drift, m0, 2, 1);
  };
  double f1, f2, f0;
  const auto m1 = run(1.2, &f1), m2 = run(1.6, &f2), still = run(0.5 * umf, &f0);
  PetscPrintf(PETSC_COMM_WORLD, "excess gas: u_mf %.6f m/s by hand; factors %.15g, %.15g; moved ratio %.15g\n", umf,
              f1, f2, (m2[2] - m0[2]) / (m1[2] - m0[2]));
  RCFD_CHECK_CLOSE(f1, 1.2 - umf, 1e-12);
  RCFD_CHECK_CLOSE(f2, 1.6 - umf, 1e-12);
  RCFD_CHECK(m1[2] > m0[2]);
  RCFD_CHECK_CLOSE((m2[2] - m0[2]) / (m1[2] - m0[2]), (1.6 - umf) / (1.2 - umf), 1e-12);
  RCFD_CHECK(f0 == 0.0 && still == m0);
  // No u_sup from the case or the database: refused, not the default 1.1 m/s.
  RunContext none{*db, set, 1440.0};
  auto drift = makeOperator<DriftOperator>("-size_law drag -kd 0.05 -excess_gas");
  PetscCallAbort(PETSC_COMM_WORLD, PetscPushErrorHandler(PetscReturnErrorHandler, nullptr));
  const PetscErrorCode refused = drift->setUp(none);
  PetscCallAbort(PETSC_COMM_WORLD, PetscPopErrorHandler());
  RCFD_CHECK(refused != 0);
}

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  dir = rcfd::test::rankCountDirectory(argc, argv, "drift");
  dataDir = argc > 1 ? argv[1] : ".";
  if (dir.empty()) return 1;
  completeSeparation();
  driftAgainstDispersion();
  otherAxis();
  driftEvery();
  stress(2, "-model B -kd 5e3", false);
  stress(5, "-model B -kd 5e5 -hindered", true);
  stress(20, "-model A -kd 5e4 -local_d32", true);
  // No alpha_s floor: faces next to the empty cells must still swap nothing
  // (this produced NaN before faces with an empty side were skipped).
  stress(5, "-model B -kd 5e4 -alpha_min 0", false);
  leftOutWhenNotNeeded();
  agitationScaling();
  agitationOfTheFrame();
  agitationOfTheSendingCell();
  agitationFollowsTheDatabase();
  againstReference();
  occupiedBound();
  sizeLawsByHand();
  noNetVolume();
  userSizeLaw();
  agitationReference();
  excessGas();
  const int total = rcfd::test::globalFailures();
  PetscCall(PetscFinalize());
  return total == 0 ? 0 : 1;
}
