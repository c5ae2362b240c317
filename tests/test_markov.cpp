// The database as the solid's Markov chain (src/markov, docs/markov.md) on
// hand-made databases with analytic answers: a two-cell chain and a lazy ring
// of N cells give their eigenvalues, stationary distributions, mixing times and
// the distributions of the time per visit and away from a zone; absorbed plus
// left is 1; frames that do not conserve mass are refused.  Runs at 1 and 2
// ranks with the same numbers.
#include "check.hpp"
#include "box_meshes.hpp"
#include "database/database_file_writer.hpp"
#include "database_copies.hpp"
#include "markov/frame_chain.hpp"
#include "markov/pass_counts.hpp"
#include "markov/spectrum.hpp"
#include "markov/tracer_mixing.hpp"
#include "markov/zone_passages.hpp"
#include "rcfd/database.hpp"
#include "rcfd/zone.hpp"

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

// Frames with the shifts `shifts` and alpha_s `alpha` on row(n); rank 0 writes.
void writeChain(const std::string &path, int n, const std::vector<double> &alpha, const std::vector<CsrMatrix> &shifts) {
  if (rank == 0) {
    DatabaseMetadata meta;
    meta.dtRec = dt;
    DatabaseFileWriter w(path, row(n), meta);
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

// Zone of the first cell (its centre is at x = 0.5).
Zone firstCell() { return Zone("first", Zone::Shape::Box, {0.0, 1.0, 0.0, 1.0, 0.0, 1.0}); }

struct Answers {
  ChainSpectrum spectrum;
  MixingResult mixing;
  std::vector<ZonePassages> zones;
};

PetscErrorCode analyse(const std::string &path, const std::vector<int> &starts, Answers *a) {
  std::unique_ptr<Database> db;
  FrameChain chain;
  ChainEigensolver solver;
  ZoneSet zones;
  PetscFunctionBeginUser;
  PetscCall(Database::load(PETSC_COMM_WORLD, path, DatabaseLoadOptions{}, &db));
  PetscCall(chain.setUp(*db));
  PetscCall(solver.setFromOptions(PETSC_COMM_WORLD, "markov_"));
  PetscCall(solver.solve(chain, FrameChain::Average::Mass, 0.0, &a->spectrum));
  MixingSettings mixing;
  mixing.starts = starts;
  mixing.horizon = 10.0;
  PetscCall(tracerMixing(chain, mixing, &a->mixing));
  zones.add(firstCell());
  PetscCall(zones.setUp(db->mesh(), db->layout(), db->metadata().gravity));
  PassageSettings passages;
  passages.horizon = 20.0; // 2000 steps
  passages.tail = 1e-13;
  passages.departures = {0};
  PetscCall(zonePassages(chain, {&zones.all()[0]}, passages, &a->zones));
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
void checkAbsorption(const PassageDistribution &d) {
  double sum = d.tail;
  for (double p : d.probability) sum += p;
  RCFD_CHECK_CLOSE(sum, 1.0, 1e-12);
  RCFD_CHECK(d.conservation <= 1e-12);
  RCFD_CHECK(d.tail >= 0 && d.tail <= 1e-12);
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
  std::unique_ptr<Database> db;
  FrameChain chain;
  ZoneSet zones;
  PetscFunctionBeginUser;
  PetscCall(Database::load(PETSC_COMM_WORLD, path, DatabaseLoadOptions{}, &db));
  PetscCall(chain.setUp(*db));
  zones.add(firstCell());
  PetscCall(zones.setUp(db->mesh(), db->layout(), db->metadata().gravity));
  PassCountSettings settings;
  settings.time = time;
  settings.maxPasses = maxPasses;
  settings.departures = {0};
  std::vector<PassCounts> out;
  PetscCall(passCounts(chain, {&zones.all()[0]}, settings, &out));
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
  PetscPopErrorHandler();
  PetscCall(PetscFinalize());
  return RCFD_TEST_RESULT();
}
