// The database as the solid's Markov chain (src/markov, docs/markov.md) on
// hand-made databases with analytic answers: a two-cell chain and a lazy ring
// of N cells give their eigenvalues, stationary distributions, mixing times and
// the distributions of the time per visit and away from a zone; absorbed plus
// left is 1; frames that do not conserve mass are refused; the chain over one
// period of the frames (their product) against hand products.  Runs at 1 and
// 2 ranks with the same numbers.
#include "check.hpp"
#include "box_meshes.hpp"
#include "database/database_file_writer.hpp"
#include "database_copies.hpp"
#include "markov/class_drift.hpp"
#include "markov/drift_matrices.hpp"
#include "markov/frame_chain.hpp"
#include "markov/pass_counts.hpp"
#include "markov/period_chain.hpp"
#include "markov/spectrum.hpp"
#include "markov/tracer_mixing.hpp"
#include "markov/wrap_carry.hpp"
#include "markov/zone_passages.hpp"
#include "rcfd/database.hpp"
#include "rcfd/zone.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>

using namespace rcfd;

namespace {

std::string dir;
int rank = 0;
constexpr double dt = 0.01;

// A row of n cells of 1 m, gravity along -z.
Mesh row(int n) {
  BoxSpec s;
  s.nx = n;
  s.ny = 1;
  s.nz = 1;
  s.length = {static_cast<double>(n), 1.0, 1.0};
  return rcfd::test::boxMesh(s);
}

// Frames with the shifts `shifts` and alpha_s `alpha` on `mesh`; rank 0 writes.
void writeChain(const std::string &path, const Mesh &mesh, const std::vector<double> &alpha,
                const std::vector<CsrMatrix> &shifts) {
  if (rank == 0) {
    DatabaseMetadata meta;
    meta.dtRec = dt;
    DatabaseFileWriter w(path, mesh, meta);
    for (const CsrMatrix &shift : shifts) {
      FrameRecord f;
      f.alphaS = alpha;
      f.shift = shift;
      w.append(f);
    }
    w.finish();
  }
  MPI_Barrier(PETSC_COMM_WORLD);
}

// The same on row(n).
void writeChain(const std::string &path, int n, const std::vector<double> &alpha, const std::vector<CsrMatrix> &shifts) {
  writeChain(path, row(n), alpha, shifts);
}

// Zone of the first cell (its centre is at x = 0.5).
Zone firstCell() { return Zone("first", Zone::Shape::Box, {0.0, 1.0, 0.0, 1.0, 0.0, 1.0}); }

struct Answers {
  ChainSpectrum spectrum;
  MixingResult mixing;
  std::vector<ZonePassages> zones;
};

// A database's chain and one zone on it.
struct Loaded {
  std::unique_ptr<Database> db;
  FrameChain chain;
  ZoneSet zones;
  const Zone *zone() const { return &zones.all()[0]; }
};

PetscErrorCode load(const std::string &path, const Zone &zone, Loaded *l) {
  PetscFunctionBeginUser;
  PetscCall(Database::load(PETSC_COMM_WORLD, path, DatabaseLoadOptions{}, &l->db));
  PetscCall(l->chain.setUp(*l->db));
  l->zones.add(zone);
  PetscCall(l->zones.setUp(l->db->mesh(), l->db->layout(), l->db->metadata().gravity));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode analyse(const std::string &path, const std::vector<int> &starts, Answers *a) {
  Loaded l;
  ChainEigensolver solver;
  PetscFunctionBeginUser;
  PetscCall(load(path, firstCell(), &l));
  const FrameChain &chain = l.chain;
  PetscCall(solver.setFromOptions(PETSC_COMM_WORLD, "markov_"));
  PetscCall(solver.solve(chain, FrameChain::Average::Mass, 0.0, &a->spectrum));
  MixingSettings mixing;
  mixing.starts = starts;
  mixing.horizon = 10.0;
  PetscCall(tracerMixing(chain, mixing, &a->mixing));
  PassageSettings passages;
  passages.horizon = 20.0; // 2000 steps
  passages.tail = 1e-13;
  passages.departures = {0};
  PetscCall(zonePassages(chain, {l.zone()}, passages, &a->zones));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// Whether `ierr` is success; prints PETSc's message when it is not.
bool succeeded(PetscErrorCode ierr) {
  if (ierr == 0) return true;
  char *text = nullptr;
  PetscErrorMessage(ierr, nullptr, &text);
  std::fprintf(stderr, "error: %s\n", text ? text : "?");
  return false;
}

// The probabilities sum to 1 with what is left; the check can fail: the sum is
// compared with 1 to 1e-12, as every mass balance.
void checkSumsToOne(const PassageDistribution &d) {
  double sum = d.tail;
  for (double p : d.probability) sum += p;
  RCFD_CHECK_CLOSE(sum, 1.0, 1e-12);
  RCFD_CHECK(d.conservation <= 1e-12);
  RCFD_CHECK(d.tail >= 0);
}

// ... and nothing is left after the horizon.
void checkAbsorption(const PassageDistribution &d) {
  checkSumsToOne(d);
  RCFD_CHECK(d.tail <= 1e-12);
}

// T = [[1 - a, b], [a, 1 - b]]: eigenvalues 1 and 1 - a - b, stationary
// (b, a) / (a + b); from cell 0 the deviation is |lambda|^n pi1 / pi0, from
// cell 1 |lambda|^n; a visit to cell 0 lasts n steps with a (1 - a)^(n-1), the
// time away is b (1 - b)^(n-1).
void twoCells() {
  const double a = 0.3, b = 0.1;
  const std::string path = dir + "/two_cells.h5";
  writeChain(path, 2, {0.2, 0.6}, {shiftFromTransfers(2, {0, 1, 0, 1}, {0, 0, 1, 1}, {1 - a, a, b, 1 - b})});
  Answers r;
  RCFD_CHECK(succeeded(analyse(path, {0, 1}, &r)));
  const double lambda = 1 - a - b;
  RCFD_CHECK_CLOSE(r.spectrum.lambda1, 1.0, 1e-10);
  RCFD_CHECK_CLOSE(r.spectrum.lambda2, lambda, 1e-10);
  RCFD_CHECK_CLOSE(r.spectrum.relaxationTime, -dt / std::log(lambda), 1e-9);
  RCFD_CHECK(r.spectrum.l1 < 1e-10); // the database's alpha is the stationary distribution
  RCFD_CHECK(r.spectrum.residual < 1e-15);
  const double pi0 = b / (a + b), pi1 = a / (a + b);
  const double n0 = std::ceil(std::log(0.05 / (pi1 / pi0)) / std::log(lambda));
  const double n1 = std::ceil(std::log(0.05) / std::log(lambda));
  RCFD_CHECK(r.mixing.time.size() == 2);
  if (r.mixing.time.size() == 2) {
    RCFD_CHECK_CLOSE(r.mixing.time[0], n0 * dt, 1e-12);
    RCFD_CHECK_CLOSE(r.mixing.time[1], n1 * dt, 1e-12);
    RCFD_CHECK_CLOSE(r.mixing.worstDeviation[0], lambda * pi1 / pi0, 1e-12);
    RCFD_CHECK_CLOSE(r.mixing.meanDeviation[4], 0.5 * (std::pow(lambda, 5) * pi1 / pi0 + std::pow(lambda, 5)), 1e-12);
  }
  RCFD_CHECK(r.zones.size() == 1);
  if (r.zones.size() != 1) return;
  const ZonePassages &z = r.zones[0];
  RCFD_CHECK_CLOSE(z.databaseShare, pi0, 1e-14);
  RCFD_CHECK(z.residence.probability.size() > 20 && z.away.probability.size() > 20);
  for (int n = 1; n <= 20; ++n) {
    RCFD_CHECK_CLOSE(z.residence.probability[n - 1], a * std::pow(1 - a, n - 1), 1e-14);
    RCFD_CHECK_CLOSE(z.away.probability[n - 1], b * std::pow(1 - b, n - 1), 1e-14);
  }
  RCFD_CHECK_CLOSE(z.residence.mean, dt / a, 1e-9);
  RCFD_CHECK_CLOSE(z.away.mean, dt / b, 1e-9);
  RCFD_CHECK_CLOSE(z.residence.flux, pi1 * b, 1e-14); // the mass share entering per step
  checkAbsorption(z.residence);
  checkAbsorption(z.away);
}

// A lazy ring: each step 1/4 of every cell moves to the next.  Eigenvalues
// 1 - p + p exp(2 pi i k / N); a visit to one cell lasts a geometric time, the
// time away is the time of N - 1 moves (negative binomial); the mixing time is
// the same from every cell, found here by propagating the tracer by hand.
CsrMatrix lazyRing(int N, double p) {
  std::vector<int32_t> dest, src;
  std::vector<double> w;
  for (int c = 0; c < N; ++c) {
    dest.insert(dest.end(), {c, (c + 1) % N});
    src.insert(src.end(), {c, c});
    w.insert(w.end(), {1 - p, p});
  }
  return shiftFromTransfers(N, dest, src, w);
}

// The ring's step count to mix by hand: x <- (1 - p) x + p shift(x) from cell
// 0 until max |N x_i - 1| <= 0.05.
int ringMixingSteps(int N, double p) {
  std::vector<double> x(N, 0.0), y(N);
  x[0] = 1.0;
  for (int n = 1; n < 1000; ++n) {
    for (int c = 0; c < N; ++c) y[(c + 1) % N] = p * x[c];
    for (int c = 0; c < N; ++c) x[c] = (1 - p) * x[c] + y[c];
    double d = 0.0;
    for (double v : x) d = std::max(d, std::fabs(N * v - 1.0));
    if (d <= 0.05) return n;
  }
  return -1;
}

void ring() {
  const int N = 8;
  const double p = 0.25;
  const std::string path = dir + "/ring.h5";
  writeChain(path, N, std::vector<double>(N, 0.5), {lazyRing(N, p)});
  std::vector<int> all(N);
  for (int c = 0; c < N; ++c) all[c] = c;
  Answers r;
  RCFD_CHECK(succeeded(analyse(path, all, &r)));
  const double lambda2 = std::abs(std::complex<double>(1 - p) + p * std::polar(1.0, 2 * M_PI / N));
  RCFD_CHECK_CLOSE(r.spectrum.lambda2, lambda2, 1e-10);
  RCFD_CHECK_CLOSE(std::fabs(r.spectrum.lambda2Im), p * std::sin(2 * M_PI / N), 1e-10);
  RCFD_CHECK(r.spectrum.max < 1e-10);
  const int mixedAt = ringMixingSteps(N, p);
  RCFD_CHECK(mixedAt > 10);
  RCFD_CHECK(r.mixing.time.size() == static_cast<size_t>(N));
  for (double t : r.mixing.time) RCFD_CHECK_CLOSE(t, mixedAt * dt, 1e-12);
  RCFD_CHECK(r.zones.size() == 1);
  if (r.zones.size() != 1) return;
  const ZonePassages &z = r.zones[0];
  RCFD_CHECK_CLOSE(z.databaseShare, 1.0 / N, 1e-14);
  for (int m = 1; m <= 60; ++m) {
    RCFD_CHECK_CLOSE(z.residence.probability[m - 1], p * std::pow(1 - p, m - 1), 1e-14);
    // C(m - 1, N - 2) p^(N-1) (1 - p)^(m - N + 1) for m >= N - 1, else 0.
    const double expected =
        m < N - 1 ? 0.0
                  : std::exp(std::lgamma(m) - std::lgamma(N - 1) - std::lgamma(m - N + 2)) * std::pow(p, N - 1) *
                        std::pow(1 - p, m - N + 1);
    RCFD_CHECK_CLOSE(z.away.probability[m - 1], expected, 1e-13);
  }
  RCFD_CHECK_CLOSE(z.residence.mean, dt / p, 1e-9);
  RCFD_CHECK_CLOSE(z.away.mean, (N - 1) * dt / p, 1e-9);
  // Kac: the share of time in the zone is E[visit] / (E[visit] + E[away]) = 1/N.
  RCFD_CHECK_CLOSE(z.residence.mean / (z.residence.mean + z.away.mean), 1.0 / N, 1e-9);
  checkAbsorption(z.residence);
  checkAbsorption(z.away);
}

// A tracer started as the solid of a zone (-markov_mix_zone) is the cells'
// tracers weighted by their solid: the first cell's zone on the ring is the
// start in cell 0, to the bit.
void zoneStart() {
  Loaded l;
  MixingResult r;
  auto run = [&]() -> PetscErrorCode {
    PetscFunctionBeginUser;
    PetscCall(load(dir + "/ring.h5", firstCell(), &l));
    MixingSettings m;
    m.starts = {0};
    m.startZone = l.zone()->localCells();
    m.zoneStart = true;
    m.horizon = 10.0;
    PetscCall(tracerMixing(l.chain, m, &r));
    PetscFunctionReturn(PETSC_SUCCESS);
  };
  RCFD_CHECK(succeeded(run()));
  RCFD_CHECK(r.time.size() == 2 && r.time[0] == r.time[1] && !std::isnan(r.time[0]));
  RCFD_CHECK(r.zoneDeviation == r.worstDeviation);
}

// Two frames: the lazy ring, then the identity.  The averaged chain is
// (T + I) / 2, |lambda2| = |1 - p/2 + p/2 exp(2 pi i / N)|; the tracer moves on
// the odd steps only, so it first reaches the tolerance at step 2 m - 1 (m the
// ring's steps) and stays there through the identity step: the mixing time
// counts from that first step, not from the end of the K steps it must stay.
void ringWithPauses() {
  const int N = 8;
  const double p = 0.25;
  const std::string path = dir + "/ring_pauses.h5";
  writeChain(path, N, std::vector<double>(N, 0.5), {lazyRing(N, p), shiftFromTransfers(N, {}, {}, {})});
  Answers r;
  RCFD_CHECK(succeeded(analyse(path, {0, 3}, &r)));
  const double lambda2 = std::abs(std::complex<double>(1 - p / 2) + p / 2 * std::polar(1.0, 2 * M_PI / N));
  RCFD_CHECK_CLOSE(r.spectrum.lambda2, lambda2, 1e-10);
  RCFD_CHECK(r.mixing.confirm == 2);
  const int m = ringMixingSteps(N, p);
  RCFD_CHECK(r.mixing.time.size() == 2);
  for (double t : r.mixing.time) RCFD_CHECK_CLOSE(t, (2 * m - 1) * dt, 1e-12);
  for (const ZonePassages &z : r.zones) {
    checkAbsorption(z.residence);
    checkAbsorption(z.away);
    // Half the steps move nothing: a visit lasts twice as long on average.
    RCFD_CHECK_CLOSE(z.residence.mean, 2 * dt / p, 1e-6);
  }
}

// The two-cell chain with a third cell that never holds solid and keeps
// what it has (a freeboard): the chain holds the two cells only, and every
// number is the two-cell chain's to the bit.
void freeboardLeftOut() {
  const double a = 0.3, b = 0.1;
  const std::string path = dir + "/two_cells_freeboard.h5";
  writeChain(path, 3, {0.2, 0.6, 0.0}, {shiftFromTransfers(3, {0, 1, 0, 1}, {0, 0, 1, 1}, {1 - a, a, b, 1 - b})});
  Answers with, without;
  RCFD_CHECK(succeeded(analyse(path, {0, 1}, &with)));
  RCFD_CHECK(succeeded(analyse(dir + "/two_cells.h5", {0, 1}, &without)));
  std::unique_ptr<Database> db;
  FrameChain chain;
  RCFD_CHECK(Database::load(PETSC_COMM_WORLD, path, DatabaseLoadOptions{}, &db) == 0 && chain.setUp(*db) == 0);
  RCFD_CHECK(chain.numChainCellsGlobal() == 2);
  RCFD_CHECK(with.mixing.time == without.mixing.time);
  RCFD_CHECK(with.mixing.worstDeviation == without.mixing.worstDeviation);
  RCFD_CHECK(with.zones.size() == 1 && without.zones.size() == 1);
  if (with.zones.size() != 1 || without.zones.size() != 1) return;
  RCFD_CHECK(with.zones[0].residence.probability == without.zones[0].residence.probability);
  RCFD_CHECK(with.zones[0].away.probability == without.zones[0].away.probability);
  RCFD_CHECK(with.spectrum.residual == without.spectrum.residual);
  RCFD_CHECK_CLOSE(with.spectrum.lambda2, without.spectrum.lambda2, 1e-12);
}

// A column of cells 1 cm high, gravity along -z: each step a quarter of every
// cell moves to each neighbour (half stays; the end cells keep what would
// leave the column), the top cell is empty and keeps what it has (a
// freeboard).  Two size classes drift by law B; the zone is the highest cell
// holding solid.
constexpr int kColumn = 8;

Mesh column() {
  BoxSpec s;
  s.nx = 1;
  s.ny = 1;
  s.nz = kColumn + 1;
  s.length = {0.01, 0.01, 0.01 * (kColumn + 1)};
  return rcfd::test::boxMesh(s);
}

// With `deadBottom` the bottom cell's solid never moves and none reaches it
// (a dead corner): the walk is over the cells above.
CsrMatrix columnWalk(bool deadBottom = false) {
  std::vector<int32_t> dest, src;
  std::vector<double> w;
  for (int c = 0; c < kColumn; ++c) {
    double stay = 0.5;
    if (deadBottom && c == 0) {
      dest.push_back(c), src.push_back(c), w.push_back(1.0);
      continue;
    }
    for (int to : {c - 1, c + 1}) {
      if (to < 0 || to >= kColumn || (deadBottom && to == 0)) {
        stay += 0.25;
        continue;
      }
      dest.push_back(to), src.push_back(c), w.push_back(0.25);
    }
    dest.push_back(c), src.push_back(c), w.push_back(stay);
  }
  return shiftFromTransfers(kColumn + 1, dest, src, w);
}

// Two classes (1 and 3 mm, half each) drifting by law B with -drift_kd kd.
PetscErrorCode columnDrift(const char *kd, FractionSet *fractions, ClassDrift *drift) {
  PetscFunctionBeginUser;
  PetscCall(FractionSet::create({1e-3, 3e-3}, {0.5, 0.5}, fractions));
  PetscCall(PetscOptionsSetValue(nullptr, "-drift_model", "B"));
  PetscCall(PetscOptionsSetValue(nullptr, "-drift_kd", kd));
  PetscCall(drift->setFromOptions(PETSC_COMM_WORLD));
  PetscCall(PetscOptionsClearValue(nullptr, "-drift_model"));
  PetscCall(PetscOptionsClearValue(nullptr, "-drift_kd"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

struct ClassRun {
  std::vector<ZonePassages> bulk;
  std::vector<std::vector<ZonePassages>> classes;
  MixingResult bulkMixing;
  std::vector<MixingResult> classMixing;
};

// The bulk's and every class's zone passages and mixing with the drift of
// -drift_kd kd (law B, 1 and 3 mm, half each).
PetscErrorCode classChains(const std::string &path, const char *kd, ClassRun *out) {
  Loaded l;
  FractionSet fractions;
  ClassDrift drift;
  PetscFunctionBeginUser;
  PetscCall(load(path, Zone("top", Zone::Shape::Box, {0.0, 0.01, 0.0, 0.01, 0.01 * (kColumn - 1), 0.01 * kColumn}), &l));
  const FrameChain &chain = l.chain;
  PetscCall(columnDrift(kd, &fractions, &drift));
  PetscCall(drift.setUp(chain, fractions, 1440.0));
  PassageSettings passages;
  passages.horizon = 20.0;
  passages.tail = 1e-13;
  passages.departures = {0};
  MixingSettings mixing;
  mixing.starts = {0, kColumn - 1};
  mixing.horizon = 10.0;
  const std::vector<const Zone *> list{l.zone()};
  PetscCall(zonePassages(chain, list, passages, &out->bulk));
  PetscCall(tracerMixing(chain, mixing, &out->bulkMixing));
  for (int i = 0; i < fractions.size(); ++i) {
    drift.setClass(i);
    out->classes.emplace_back();
    out->classMixing.emplace_back();
    PetscCall(zonePassages(chain, list, passages, &out->classes.back(), {&drift}));
    PetscCall(tracerMixing(chain, mixing, &out->classMixing.back(), {&drift}));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

// With k_d = 0 every class's chain is the bulk's, to the bit; with k_d > 0
// the small class (drifting up) stays longer per visit in the top zone and
// spends a larger share of its time there (Kac) than the bulk, and the large
// class less; every distribution's absorbed plus left is 1.
void sizeClasses() {
  const std::string path = dir + "/column.h5";
  std::vector<double> alpha(kColumn + 1, 0.3);
  alpha[kColumn] = 0.0;
  writeChain(path, column(), alpha, {columnWalk()});
  ClassRun still, drifting;
  RCFD_CHECK(succeeded(classChains(path, "0", &still)));
  RCFD_CHECK(still.classes.size() == 2);
  for (size_t i = 0; i < still.classes.size(); ++i) {
    RCFD_CHECK(still.classes[i].at(0).residence.probability == still.bulk.at(0).residence.probability);
    RCFD_CHECK(still.classes[i].at(0).away.probability == still.bulk.at(0).away.probability);
    RCFD_CHECK(still.classMixing[i].time == still.bulkMixing.time);
    RCFD_CHECK(still.classMixing[i].worstDeviation == still.bulkMixing.worstDeviation);
  }
  RCFD_CHECK(succeeded(classChains(path, "1e5", &drifting)));
  RCFD_CHECK(drifting.classes.size() == 2);
  if (drifting.classes.size() != 2) return;
  auto kac = [](const ZonePassages &z) { return z.residence.mean / (z.residence.mean + z.away.mean); };
  const ZonePassages &bulk = drifting.bulk.at(0), &small = drifting.classes[0].at(0), &large = drifting.classes[1].at(0);
  // The walk alone: 1/8 of the time in the top cell (Kac), a visit of 4 steps.
  RCFD_CHECK_CLOSE(kac(bulk), 1.0 / kColumn, 1e-9);
  RCFD_CHECK_CLOSE(bulk.residence.mean, 4 * dt, 1e-9);
  RCFD_CHECK(small.residence.mean > 1.1 * bulk.residence.mean);
  RCFD_CHECK(large.residence.mean < bulk.residence.mean / 1.1);
  RCFD_CHECK(kac(small) > 1.5 * kac(bulk));
  RCFD_CHECK(kac(large) < kac(bulk) / 1.5);
  // (The large class's time away has a tail after 20 s: it rarely climbs.)
  for (const auto &zones : drifting.classes)
    for (const ZonePassages &z : zones) {
      checkSumsToOne(z.residence);
      checkSumsToOne(z.away);
    }
  RCFD_CHECK(small.away.tail < 1e-12 && large.away.tail > 1e-9);
  if (rank == 0)
    std::printf("column, top cell: bulk visit %.4g s, share %.4f; small %.4g s, %.4f; large %.4g s, %.4f\n",
                bulk.residence.mean, kac(bulk), small.residence.mean, kac(small), large.residence.mean, kac(large));
}

// The wrap carried as a run carries its state (-markov_wrap carry).  One
// frame on a column of 3 cells holding alpha (0.3, 0.3, 0): the bottom cell
// keeps half and sends half up, the middle cell sends half down and half into
// the empty top cell (a splash), so the frame's shift leaves (0.3, 0.15,
// 0.15), not frame 0's bed.  Periodic, the top cell keeps what reaches it
// (its column is the identity's: it holds no solid in frame 0), so half of a
// visit's leavers never come back.  Carried by height onto (0.3, 0.3, 0), the
// splash lands in the middle cell again: the chain is two cells exchanging
// half each step, a visit to the middle cell and the time away last n steps
// with probability 2^-n, and a tracer is mixed after one step.
void wrapCarried() {
  const std::string path = dir + "/splash.h5";
  BoxSpec b;
  b.nx = 1;
  b.ny = 1;
  b.nz = 3;
  b.length = {0.01, 0.01, 0.03};
  writeChain(path, rcfd::test::boxMesh(b), {0.3, 0.3, 0.0},
             {shiftFromTransfers(3, {0, 1, 0, 2}, {0, 0, 1, 1}, {0.5, 0.5, 0.5, 0.5})});
  const Zone middle("middle", Zone::Shape::Box, {0.0, 0.01, 0.0, 0.01, 0.01, 0.02});
  for (bool carry : {false, true}) {
    Loaded l;
    WrapCarry wrap;
    std::vector<ZonePassages> zones;
    MixingResult mixing;
    auto run = [&]() -> PetscErrorCode {
      PetscFunctionBeginUser;
      PetscCall(load(path, middle, &l));
      std::vector<ChainStep *> steps;
      if (carry) {
        PetscCall(wrap.setFromOptions(PETSC_COMM_WORLD));
        PetscCall(wrap.setUp(l.chain, 1440.0));
        steps.push_back(&wrap);
      }
      PassageSettings passages;
      passages.horizon = 1.0; // 100 steps
      passages.tail = 1e-13;
      passages.departures = {0};
      PetscCall(zonePassages(l.chain, {l.zone()}, passages, &zones, steps));
      MixingSettings m;
      m.starts = {0};
      m.horizon = 0.5;
      PetscCall(tracerMixing(l.chain, m, &mixing, steps));
      PetscFunctionReturn(PETSC_SUCCESS);
    };
    RCFD_CHECK(succeeded(run()));
    RCFD_CHECK(zones.size() == 1 && mixing.time.size() == 1);
    if (zones.size() != 1 || mixing.time.size() != 1) continue;
    const ZonePassages &z = zones[0];
    checkSumsToOne(z.residence);
    checkSumsToOne(z.away);
    if (!carry) {
      RCFD_CHECK_CLOSE(z.away.tail, 0.5, 1e-12); // half of the leavers splash into the top cell for ever
      continue;
    }
    checkAbsorption(z.residence);
    checkAbsorption(z.away);
    for (int n = 1; n <= 20; ++n) {
      RCFD_CHECK_CLOSE(z.residence.probability[n - 1], std::pow(0.5, n), 1e-14);
      RCFD_CHECK_CLOSE(z.away.probability[n - 1], std::pow(0.5, n), 1e-14);
    }
    RCFD_CHECK_CLOSE(mixing.time[0], dt, 1e-14);
  }
}

// Frames that lose mass are no Markov chain: a file with a column summing to
// 0.9 is refused by the load, and a chain made in memory whose shift loses 1e-9
// of every column by the chain itself before anything is computed; 1e-14 is
// round-off and passes.
void nonConserving() {
  const std::string path = dir + "/losing.h5";
  CsrMatrix T = shiftFromTransfers(2, {0, 1, 0, 1}, {0, 0, 1, 1}, {0.7, 0.3, 0.1, 0.9});
  T.val[0] = 0.6; // column 0 sums to 0.9
  writeChain(path, 2, {0.2, 0.6}, {T});
  const std::string refusal = rcfd::test::loadRefusal(path);
  RCFD_CHECK(refusal.find("sum") != std::string::npos);
  const std::string good = dir + "/two_cells.h5";
  std::unique_ptr<Database> db;
  RCFD_CHECK(Database::load(PETSC_COMM_WORLD, good, DatabaseLoadOptions{}, &db) == 0);
  if (!db) return;
  for (double loss : {1e-9, 1e-14}) {
    std::vector<OwnedVec> alpha(1);
    std::vector<OwnedMat> shifts(1);
    VecDuplicate(db->alphaS(0), alpha[0].put());
    VecCopy(db->alphaS(0), alpha[0]);
    db->shiftMatrix(0, &shifts[0]);
    MatScale(shifts[0], 1.0 - loss);
    std::unique_ptr<Database> made;
    RCFD_CHECK(Database::fromFrames(*db, "losing", std::move(alpha), std::move(shifts), &made) == 0);
    FrameChain chain;
    const PetscErrorCode ierr = chain.setUp(*made);
    char *text = nullptr;
    PetscErrorMessage(ierr, nullptr, &text);
    if (loss > 1e-12)
      RCFD_CHECK(ierr != 0 && text && std::string(text).find("does not conserve mass") != std::string::npos);
    else
      RCFD_CHECK(ierr == 0 && chain.columnError() <= FrameChain::kColumnTolerance);
  }
}

// The number of entries into the first cell within n steps, from the
// pass-counter chain.  Two cells from the stationary share (pi0, pi1): in two
// steps at most one entry (1 -> 0 at the first or at the second step), P(1) =
// pi1 b + (pi0 a + pi1 (1 - b)) b = 2 pi1 b; in three, two entries only by
// 1 -> 0 -> 1 -> 0, P(2) = pi1 b a b, and the mean is 3 pi1 b.  A rotating
// ring of N cells (each step all of a cell moves on) from the uniform share:
// in n = q N + r steps a particle enters q or q + 1 times, q + 1 from the r
// cells within r steps of the zone.
PetscErrorCode countPasses(const std::string &path, double time, int maxPasses, std::vector<double> *p,
                           double *mean, double *conservation) {
  Loaded l;
  PetscFunctionBeginUser;
  PetscCall(load(path, firstCell(), &l));
  PassCountSettings settings;
  settings.time = time;
  settings.maxPasses = maxPasses;
  settings.departures = {0};
  std::vector<PassCounts> out;
  PetscCall(passCounts(l.chain, {l.zone()}, settings, &out));
  *p = out.at(0).probability;
  *mean = out[0].mean;
  *conservation = out[0].conservation;
  PetscFunctionReturn(PETSC_SUCCESS);
}

void passes() {
  const double a = 0.3, b = 0.1, pi1 = a / (a + b);
  std::vector<double> p;
  double mean = 0, conservation = 1;
  RCFD_CHECK(succeeded(countPasses(dir + "/two_cells.h5", 2 * dt, 5, &p, &mean, &conservation)));
  RCFD_CHECK(p.size() == 6);
  if (p.size() == 6) {
    RCFD_CHECK_CLOSE(p[1], 2 * pi1 * b, 1e-15);
    RCFD_CHECK_CLOSE(p[0], 1 - 2 * pi1 * b, 1e-15);
    for (int j = 2; j < 6; ++j) RCFD_CHECK(p[j] == 0.0);
  }
  RCFD_CHECK(conservation <= 1e-14);
  RCFD_CHECK(succeeded(countPasses(dir + "/two_cells.h5", 3 * dt, 5, &p, &mean, &conservation)));
  if (p.size() == 6) {
    RCFD_CHECK_CLOSE(p[2], pi1 * b * a * b, 1e-15);
    RCFD_CHECK_CLOSE(mean, 3 * pi1 * b, 1e-15);
    RCFD_CHECK_CLOSE(p[0] + p[1] + p[2], 1.0, 1e-14);
  }
  // The rotating ring: 8 cells, 20 steps = 2 * 8 + 4.
  const int N = 8;
  const std::string path = dir + "/rotation.h5";
  writeChain(path, N, std::vector<double>(N, 0.5), {lazyRing(N, 1.0)});
  RCFD_CHECK(succeeded(countPasses(path, 20 * dt, 4, &p, &mean, &conservation)));
  RCFD_CHECK(p.size() == 5);
  if (p.size() == 5) {
    RCFD_CHECK_CLOSE(p[2], 0.5, 1e-15);
    RCFD_CHECK_CLOSE(p[3], 0.5, 1e-15);
    RCFD_CHECK(p[0] == 0.0 && p[1] == 0.0 && p[4] == 0.0);
  }
  RCFD_CHECK_CLOSE(mean, 2.5, 1e-14);
  RCFD_CHECK(conservation <= 1e-14);
  // The last counter keeps "that many or more": capped at 2, all of it.
  RCFD_CHECK(succeeded(countPasses(path, 20 * dt, 2, &p, &mean, &conservation)));
  if (p.size() == 3) RCFD_CHECK_CLOSE(p[2], 1.0, 1e-15);
  RCFD_CHECK(p.size() == 3);
  // The lazy ring (1/4 moves): the mean number of entries is the flux into
  // the zone per step, (1/8)(1/4), times the steps.
  RCFD_CHECK(succeeded(countPasses(dir + "/ring.h5", 100 * dt, 60, &p, &mean, &conservation)));
  RCFD_CHECK_CLOSE(mean, 100.0 / 32.0, 1e-12);
  RCFD_CHECK(conservation <= 1e-13);
}

// The period chain of a loaded database with `steps` after each frame: its
// numbers and its stationary distribution per cell (natural order).
struct PeriodRun {
  PeriodNumbers numbers;
  std::vector<double> share, frame0;
  double height = 0.0;
};

PetscErrorCode periodOf(Loaded &l, const std::vector<ChainStep *> &steps, PeriodRun *out) {
  ChainEigensolver solver;
  ChainSpectrum average;
  PeriodChain period;
  PeriodSpectrum p;
  PetscFunctionBeginUser;
  PetscCall(solver.setFromOptions(PETSC_COMM_WORLD, "markov_"));
  PetscCall(solver.solve(l.chain, FrameChain::Average::Mass, 0.0, &average)); // its absorbing cells
  PetscCall(period.setUp(l.chain, average.absorbingLocal));
  PetscCall(period.solve(solver, steps, "the test's period chain", &p));
  out->numbers = p;
  PetscCall(l.db->layout().gatherToAll(1, p.stationary, &out->share));
  PetscCall(l.db->layout().gatherToAll(1, l.chain.massShare(0), &out->frame0));
  out->height = centreHeight(l.db->mesh(), l.db->metadata().gravity, out->share);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode periodOf(const std::string &path, PeriodRun *out) {
  Loaded l;
  PetscFunctionBeginUser;
  PetscCall(load(path, firstCell(), &l));
  PetscCall(periodOf(l, {}, out));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// Two cells, two different frames T0 = [[1 - a, b], [a, 1 - b]] and T1 the
// same with (c, d): the period chain is P = T1 T0 (by hand), its eigenvalues 1
// and tr P - 1, its stationary distribution (P01, P10) / (P01 + P10), the
// relaxation time -2 dt / ln |lambda2|.  With c / d = a / b both frames keep
// the database's alpha: the database is consistent and the stationary
// distribution is frame 0's share, exactly.
void periodTwoCells() {
  const double a = 0.3, b = 0.1;
  for (const auto &[c, d] : {std::pair<double, double>{0.5, 0.4}, {0.6, 0.2}}) {
    const std::string path = dir + "/two_frames_" + std::to_string(static_cast<int>(10 * c)) + ".h5";
    writeChain(path, 2, {0.2, 0.6},
               {shiftFromTransfers(2, {0, 1, 0, 1}, {0, 0, 1, 1}, {1 - a, a, b, 1 - b}),
                shiftFromTransfers(2, {0, 1, 0, 1}, {0, 0, 1, 1}, {1 - c, c, d, 1 - d})});
    const double T0[2][2] = {{1 - a, b}, {a, 1 - b}}, T1[2][2] = {{1 - c, d}, {c, 1 - d}};
    double P[2][2];
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) P[i][j] = T1[i][0] * T0[0][j] + T1[i][1] * T0[1][j];
    const double lambda2 = P[0][0] + P[1][1] - 1, pi0 = P[0][1] / (P[0][1] + P[1][0]);
    PeriodRun r;
    RCFD_CHECK(succeeded(periodOf(path, &r)));
    RCFD_CHECK(r.numbers.states == 2);
    RCFD_CHECK_CLOSE(r.numbers.lambda1, 1.0, 1e-12);
    RCFD_CHECK_CLOSE(r.numbers.lambda2, std::abs(lambda2), 1e-12);
    RCFD_CHECK_CLOSE(r.numbers.relaxationTime, -2 * dt / std::log(std::abs(lambda2)), 1e-12);
    RCFD_CHECK(r.share.size() == 2);
    if (r.share.size() != 2) continue;
    RCFD_CHECK_CLOSE(r.share[0], pi0, 1e-12);
    RCFD_CHECK_CLOSE(r.share[1], 1 - pi0, 1e-12);
    RCFD_CHECK_CLOSE(r.numbers.l1, 2 * std::abs(pi0 - 0.25), 1e-12); // frame 0's share is (1/4, 3/4)
    // |P m0 - m0|_1 = 2 |(P m0)_0 - 1/4|
    RCFD_CHECK_CLOSE(r.numbers.residual, 2 * std::abs(P[0][0] * 0.25 + P[0][1] * 0.75 - 0.25), 1e-15);
    if (c / d == a / b) { // consistent: m0 is stationary
      RCFD_CHECK(r.numbers.residual < 1e-15);
      RCFD_CHECK(r.numbers.l1 < 1e-12);
      RCFD_CHECK_CLOSE(r.share[0], 0.25, 1e-12);
    }
  }
}

// The consistent two frames with a dead corner: a third cell holding solid
// that never moves.  It is an absorbing state (an eigenvector of P of
// eigenvalue 1 of its own) and is left out: the chain's states are the two
// cells, their stationary distribution frame 0's share over them.
void periodDeadCorner() {
  const double a = 0.3, b = 0.1, c = 0.6, d = 0.2;
  const std::string path = dir + "/two_frames_dead.h5";
  writeChain(path, 3, {0.2, 0.6, 0.1},
             {shiftFromTransfers(3, {0, 1, 0, 1, 2}, {0, 0, 1, 1, 2}, {1 - a, a, b, 1 - b, 1}),
              shiftFromTransfers(3, {0, 1, 0, 1, 2}, {0, 0, 1, 1, 2}, {1 - c, c, d, 1 - d, 1})});
  PeriodRun r;
  RCFD_CHECK(succeeded(periodOf(path, &r)));
  RCFD_CHECK(r.numbers.states == 2);
  RCFD_CHECK_CLOSE(r.numbers.leftOut, 1.0 / 9.0, 1e-15);
  RCFD_CHECK(r.share.size() == 3);
  if (r.share.size() == 3) {
    RCFD_CHECK_CLOSE(r.share[0], 0.25, 1e-12);
    RCFD_CHECK(r.share[2] == 0.0);
  }
  RCFD_CHECK(r.numbers.l1 < 1e-12);
  RCFD_CHECK_CLOSE(r.numbers.lambda2, std::abs((1 - a - b) * (1 - c - d)), 1e-12);
}

// A lazy ring (a quarter of every cell moves on) followed by a rotation (all
// of it moves on): both circulant, P = R L has the eigenvalues
// w^k (1 - p + p w^k), w = exp(2 pi i / N); the largest after 1 is k = +-1.
// The uniform alpha is stationary: the stationary distribution is 1/N.
void periodRing() {
  const int N = 8;
  const double p = 0.25;
  const std::string path = dir + "/ring_rotation.h5";
  writeChain(path, N, std::vector<double>(N, 0.5), {lazyRing(N, p), lazyRing(N, 1.0)});
  PeriodRun r;
  RCFD_CHECK(succeeded(periodOf(path, &r)));
  const std::complex<double> w = std::polar(1.0, 2 * M_PI / N), lambda2 = w * (1 - p + p * w);
  RCFD_CHECK(r.numbers.states == N);
  RCFD_CHECK_CLOSE(r.numbers.lambda1, 1.0, 1e-12);
  RCFD_CHECK_CLOSE(r.numbers.lambda2, std::abs(lambda2), 1e-12);
  RCFD_CHECK_CLOSE(r.numbers.lambda2Re, lambda2.real(), 1e-12);
  RCFD_CHECK_CLOSE(std::abs(r.numbers.lambda2Im), std::abs(lambda2.imag()), 1e-12);
  for (double x : r.share) RCFD_CHECK_CLOSE(x, 1.0 / N, 1e-12);
  RCFD_CHECK(r.numbers.l1 < 1e-12 && r.numbers.residual < 1e-15);
  if (rank == 0)
    std::printf("period chain, ring then rotation: |lambda2| %.12f (hand %.12f), %d restarts, %lld products\n",
                r.numbers.lambda2, std::abs(lambda2), r.numbers.iterations, r.numbers.products);
}

// The size classes' period chains on the drifting column (sizeClasses):
// with k_d = 0 every class's numbers and distribution are the bulk's; with
// k_d > 0 the small class's stationary distribution lies higher than the
// bulk's and the large class's lower.
PetscErrorCode classPeriods(const std::string &path, const char *kd, PeriodRun *bulk, std::vector<PeriodRun> *classes) {
  Loaded l;
  FractionSet fractions;
  ClassDrift drift;
  PetscFunctionBeginUser;
  PetscCall(load(path, firstCell(), &l));
  PetscCall(columnDrift(kd, &fractions, &drift));
  PetscCall(drift.setUp(l.chain, fractions, 1440.0));
  PetscCall(periodOf(l, {}, bulk));
  classes->clear();
  for (int i = 0; i < fractions.size(); ++i) {
    drift.setClass(i);
    classes->emplace_back();
    PetscCall(periodOf(l, {&drift}, &classes->back()));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

void periodClasses() {
  const std::string path = dir + "/column.h5"; // written by sizeClasses
  PeriodRun bulk;
  std::vector<PeriodRun> classes;
  RCFD_CHECK(succeeded(classPeriods(path, "0", &bulk, &classes)));
  RCFD_CHECK(classes.size() == 2);
  // The walk keeps the uniform column: the bulk's stationary distribution is frame 0's.
  RCFD_CHECK(bulk.numbers.l1 < 1e-12);
  for (const PeriodRun &c : classes) {
    RCFD_CHECK_CLOSE(c.numbers.lambda1, bulk.numbers.lambda1, 1e-12);
    RCFD_CHECK_CLOSE(c.numbers.lambda2, bulk.numbers.lambda2, 1e-12);
    RCFD_CHECK(c.share.size() == bulk.share.size());
    for (size_t i = 0; i < std::min(c.share.size(), bulk.share.size()); ++i)
      RCFD_CHECK_CLOSE(c.share[i], bulk.share[i], 1e-12);
  }
  RCFD_CHECK(succeeded(classPeriods(path, "1e5", &bulk, &classes)));
  RCFD_CHECK(classes.size() == 2);
  if (classes.size() != 2) return;
  // Every class's chain keeps its distributions on the column: lambda1 = 1.
  for (const PeriodRun &c : classes) {
    RCFD_CHECK_CLOSE(c.numbers.lambda1, 1.0, 1e-12);
    double sum = 0.0;
    for (double x : c.share) sum += x;
    RCFD_CHECK_CLOSE(sum, 1.0, 1e-12);
  }
  RCFD_CHECK(classes[0].height > bulk.height + 0.005);
  RCFD_CHECK(classes[1].height < bulk.height - 0.005);
  // A dead bottom cell: the bulk's chain keeps it for ever (no state), but
  // the drift swaps the classes with it, so it is a state of each class's
  // chain, which keeps its distributions (lambda1 = 1); with k_d = 0 it is
  // kept for ever by every class's chain too.
  const std::string dead = dir + "/column_dead.h5";
  std::vector<double> alpha(kColumn + 1, 0.3);
  alpha[kColumn] = 0.0;
  writeChain(dead, column(), alpha, {columnWalk(true)});
  PeriodRun deadBulk;
  std::vector<PeriodRun> deadClasses;
  RCFD_CHECK(succeeded(classPeriods(dead, "1e5", &deadBulk, &deadClasses)));
  RCFD_CHECK(deadBulk.numbers.states == kColumn - 1 && deadBulk.numbers.absorbing == 1);
  RCFD_CHECK(deadClasses.size() == 2);
  for (const PeriodRun &c : deadClasses) {
    RCFD_CHECK(c.numbers.states == kColumn && c.numbers.absorbing == 0);
    RCFD_CHECK_CLOSE(c.numbers.lambda1, 1.0, 1e-12);
  }
  RCFD_CHECK(succeeded(classPeriods(dead, "0", &deadBulk, &deadClasses)));
  for (const PeriodRun &c : deadClasses) RCFD_CHECK(c.numbers.states == kColumn - 1 && c.numbers.absorbing == 1);
  if (rank == 0)
    std::printf("column, period chain's stationary centre: bulk %.4f m, small %.4f m, large %.4f m; |lambda2| %.6f, "
                "%.6f, %.6f\n",
                bulk.height, classes[0].height, classes[1].height, bulk.numbers.lambda2, classes[0].numbers.lambda2,
                classes[1].numbers.lambda2);
}

struct MatrixCheck {
  double difference = 0.0; // largest |D_k x - drift(x)| over max |drift(x)|, all frames and classes
  double columnError = 0.0; // largest |column sum - 1| of any D_k
  double lowest = 0.0;      // smallest entry of any D_k
  int reach = 0;            // the most sub-steps a frame took
};

// Each class's drift as matrices (DriftMatrices) against the drift operator
// on three interleaved distributions at every frame of the database at path.
PetscErrorCode matricesAgainstOperator(const std::string &path, const char *kd, MatrixCheck *out) {
  Loaded l;
  FractionSet fractions;
  ClassDrift drift;
  constexpr PetscInt W = 3;
  PetscFunctionBeginUser;
  PetscCall(load(path, firstCell(), &l));
  const FrameChain &chain = l.chain;
  PetscCall(columnDrift(kd, &fractions, &drift));
  PetscCall(drift.setUp(chain, fractions, 1440.0));
  const std::vector<PetscInt> &rows = chain.chainRowsAll();
  const PetscInt first = static_cast<PetscInt>(
      std::lower_bound(rows.begin(), rows.end(), l.db->layout().rowStart()) - rows.begin());
  *out = MatrixCheck{};
  out->lowest = 1.0;
  for (int i = 0; i < fractions.size(); ++i) {
    drift.setClass(i);
    DriftMatrices matrices;
    PetscCall(matrices.setUp(chain, drift));
    out->reach = std::max(out->reach, matrices.reach());
    for (int k = 0; k < chain.numFrames(); ++k) {
      OwnedVec x, y;
      PetscCall(chain.blockVector(W, x.put()));
      PetscScalar *px;
      PetscCall(VecGetArray(x, &px));
      for (PetscInt c = 0; c < chain.numChainCells(); ++c)
        for (PetscInt s = 0; s < W; ++s) px[c * W + s] = std::fmod(0.618034 * static_cast<double>((first + c) * (s + 2) + k), 1.0);
      PetscCall(VecRestoreArray(x, &px));
      PetscCall(VecDuplicate(x, y.put()));
      PetscCall(VecCopy(x, y));
      PetscCall(matrices.apply(k, x, W));
      PetscCall(drift.apply(k, y, W));
      PetscReal scale, diff;
      PetscCall(VecNorm(y, NORM_INFINITY, &scale));
      PetscCall(VecAXPY(x, -1.0, y));
      PetscCall(VecNorm(x, NORM_INFINITY, &diff));
      out->difference = std::max(out->difference, diff / scale);
      const Mat D = matrices.matrix(k);
      OwnedVec ones, sums;
      PetscCall(MatCreateVecs(D, ones.put(), sums.put()));
      PetscCall(VecSet(ones, 1.0));
      PetscCall(MatMultTranspose(D, ones, sums));
      PetscCall(VecShift(sums, -1.0));
      PetscReal e;
      PetscCall(VecNorm(sums, NORM_INFINITY, &e));
      out->columnError = std::max(out->columnError, static_cast<double>(e));
      PetscInt r0, r1;
      PetscCall(MatGetOwnershipRange(D, &r0, &r1));
      double low = 1.0;
      for (PetscInt r = r0; r < r1; ++r) {
        PetscInt n;
        const PetscScalar *v;
        PetscCall(MatGetRow(D, r, &n, nullptr, &v));
        for (PetscInt j = 0; j < n; ++j) low = std::min(low, static_cast<double>(v[j]));
        PetscCall(MatRestoreRow(D, r, &n, nullptr, &v));
      }
      PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &low, 1, MPI_DOUBLE, MPI_MIN, PETSC_COMM_WORLD));
      out->lowest = std::min(out->lowest, low);
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The class drift read off as one matrix per frame moves the distributions
// as the drift operator does (to round-off), every matrix keeps each
// distribution's sum and has no negative entry; a drift strong enough to take
// several sub-steps per frame (the cells coloured again, further apart) too.
// On the synthetic bed (3-d, cells of one colour in every column) and on 2
// ranks, where the columns are cut between the ranks.
void driftMatrices(const std::string &small) {
  for (const char *kd : {"5e4", "2e6"}) {
    MatrixCheck m;
    RCFD_CHECK(succeeded(matricesAgainstOperator(small, kd, &m)));
    RCFD_CHECK(m.difference < 1e-13);
    RCFD_CHECK(m.columnError < 1e-14);
    RCFD_CHECK(m.lowest >= 0.0);
    if (rank == 0)
      std::printf("drift matrices, k_d %s: reach %d faces, |D x - drift(x)| %.2e, column sums %.2e, lowest entry %.3g\n",
                  kd, m.reach, m.difference, m.columnError, m.lowest);
    if (std::string(kd) == "2e6") RCFD_CHECK(m.reach > 1);
  }
}

} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  int size = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  dir = (argc > 1 ? argv[1] : std::string(".")) + "/markov_np" + std::to_string(size);
  if (rank == 0 && std::system(("mkdir -p '" + dir + "'").c_str()) != 0) return 1;
  twoCells();
  ring();
  ringWithPauses();
  nonConserving();
  passes();
  freeboardLeftOut();
  sizeClasses();
  wrapCarried();
  zoneStart();
  periodTwoCells();
  periodDeadCorner();
  periodRing();
  periodClasses();
  driftMatrices(std::string(argc > 1 ? argv[1] : ".") + "/small.h5");
  PetscPopErrorHandler();
  PetscCall(PetscFinalize());
  return RCFD_TEST_RESULT();
}
