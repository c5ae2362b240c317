// Recurrence matrix: hand-computed norms, a brute-force reference for sizes
// that do not fit the kernel's tiles and panels, the distributed route
// (partials of two "ranks" combined by hand), and the error paths.
#include "check.hpp"
#include "path/recurrence.hpp"

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

using namespace rcfd;

namespace {

const RecurrenceNorm kNorms[] = {RecurrenceNorm::SqrDiff, RecurrenceNorm::Euclidean,
                                 RecurrenceNorm::AbsDiff, RecurrenceNorm::Max};

std::vector<const double *> pointers(const std::vector<std::vector<double>> &f,
                                     std::size_t offset = 0) {
  std::vector<const double *> p;
  for (const auto &x : f) p.push_back(x.data() + offset);
  return p;
}

template <class F> bool throwsInvalid(F f) {
  try {
    f();
  } catch (const std::invalid_argument &e) {
    return std::string(e.what()).size() > 20; // a sentence, not a code
  }
  return false;
}

// Straight from the definitions, no blocking.
std::vector<double> bruteForce(RecurrenceNorm norm, const std::vector<std::vector<double>> &f,
                               const std::vector<double> &V) {
  const std::size_t K = f.size();
  std::vector<double> m(K * K, 0.0);
  for (std::size_t i = 0; i < K; ++i)
    for (std::size_t j = 0; j < K; ++j) {
      double s = 0.0;
      for (std::size_t c = 0; c < V.size(); ++c) {
        const double d = f[i][c] - f[j][c];
        switch (norm) {
        case RecurrenceNorm::SqrDiff:
        case RecurrenceNorm::Euclidean: s += V[c] * d * d; break;
        case RecurrenceNorm::AbsDiff: s += V[c] * std::fabs(d); break;
        case RecurrenceNorm::Max: s = std::fmax(s, std::fabs(d)); break;
        }
      }
      m[i * K + j] = norm == RecurrenceNorm::Euclidean ? std::sqrt(s) : s;
    }
  double largest = 0.0;
  for (double v : m) largest = std::fmax(largest, v);
  for (double &v : m) v /= largest;
  return m;
}

// Deterministic pseudo-random fields in [0, 0.6).
std::vector<std::vector<double>> makeFrames(int K, std::size_t n, std::uint64_t seed) {
  std::vector<std::vector<double>> f(K, std::vector<double>(n));
  for (int k = 0; k < K; ++k)
    for (std::size_t c = 0; c < n; ++c) {
      seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
      f[k][c] = 0.6 * static_cast<double>(seed >> 11) * 0x1.0p-53;
    }
  return f;
}

void testHandComputed() {
  // Three frames on four cells of unequal volume.
  const std::vector<double> V{1.0, 2.0, 0.5, 3.0};
  const std::vector<std::vector<double>> f{
      {0.1, 0.2, 0.3, 0.4}, {0.3, 0.2, 0.1, 0.4}, {0.0, 0.5, 0.3, 0.1}};
  // Differences a_i - a_j per cell:
  //   (0,1): -0.2  0    0.2  0
  //   (0,2):  0.1 -0.3  0    0.3
  //   (1,2):  0.3 -0.3 -0.2  0.3
  // sqrDiff: (0,1) 1*.04 + .5*.04 = .06; (0,2) .01 + 2*.09 + 3*.09 = .46;
  //          (1,2) .09 + .18 + .02 + .27 = .56
  // absDiff: (0,1) .2 + .1 = .3; (0,2) .1 + .6 + .9 = 1.6; (1,2) .3 + .6 + .1 + .9 = 1.9
  // max:     (0,1) .2; (0,2) .3; (1,2) .3
  struct Expect {
    RecurrenceNorm norm;
    double raw[3]; // partial (0,1), (0,2), (1,2)
    double fin[3]; // finished
  };
  const double e01 = std::sqrt(0.06), e02 = std::sqrt(0.46), e12 = std::sqrt(0.56);
  const Expect expect[] = {
      {RecurrenceNorm::SqrDiff, {0.06, 0.46, 0.56}, {0.06 / 0.56, 0.46 / 0.56, 1.0}},
      {RecurrenceNorm::Euclidean, {0.06, 0.46, 0.56}, {e01 / e12, e02 / e12, 1.0}},
      {RecurrenceNorm::AbsDiff, {0.3, 1.6, 1.9}, {0.3 / 1.9, 1.6 / 1.9, 1.0}},
      {RecurrenceNorm::Max, {0.2, 0.3, 0.3}, {0.2 / 0.3, 1.0, 1.0}},
  };
  for (const auto &e : expect) {
    std::vector<double> p;
    recurrencePartial(e.norm, pointers(f), V.data(), V.size(), p);
    RCFD_CHECK(p.size() == 9);
    const int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
    for (int q = 0; q < 3; ++q) {
      const int i = pairs[q][0], j = pairs[q][1];
      RCFD_CHECK_CLOSE(p[i * 3 + j], e.raw[q], 1e-14);
      RCFD_CHECK_CLOSE(p[j * 3 + i], e.raw[q], 1e-14);
    }
    for (int i = 0; i < 3; ++i) RCFD_CHECK(p[i * 3 + i] == 0.0);

    const auto m = recurrenceMatrix(e.norm, pointers(f), V.data(), V.size());
    for (int q = 0; q < 3; ++q) {
      const int i = pairs[q][0], j = pairs[q][1];
      RCFD_CHECK_CLOSE(m[i * 3 + j], e.fin[q], 1e-14);
      RCFD_CHECK(m[i * 3 + j] == m[j * 3 + i]); // exactly symmetric
    }
    for (int i = 0; i < 3; ++i) RCFD_CHECK(m[i * 3 + i] == 0.0);
  }
}

void testAgainstBruteForce() {
  // Sizes that leave partial tiles and a partial cell panel.
  for (int K : {2, 5, 13, 37, 261}) { // 261 spans two blocks of j tiles
    const std::size_t n = 601;
    const auto f = makeFrames(K, n, 7 + K);
    std::vector<double> V(n);
    for (std::size_t c = 0; c < n; ++c) V[c] = 1e-6 * (1.0 + static_cast<double>(c % 5));
    for (RecurrenceNorm norm : kNorms) {
      const auto ref = bruteForce(norm, f, V);
      const auto m = recurrenceMatrix(norm, pointers(f), V.data(), n);
      double worst = 0.0;
      for (std::size_t e = 0; e < ref.size(); ++e) worst = std::fmax(worst, std::fabs(m[e] - ref[e]));
      RCFD_CHECK(worst < 1e-12);
    }
  }
}

void testTwoRanks() {
  const int K = 23;
  const std::size_t n = 1000, n0 = 517; // "rank 0" holds cells [0, n0), "rank 1" the rest
  const auto f = makeFrames(K, n, 99);
  std::vector<double> V(n);
  for (std::size_t c = 0; c < n; ++c) V[c] = 0.5 + 0.001 * static_cast<double>(c % 17);
  for (RecurrenceNorm norm : kNorms) {
    const auto whole = recurrenceMatrix(norm, pointers(f), V.data(), n);
    std::vector<double> p0, p1, pEmpty;
    recurrencePartial(norm, pointers(f), V.data(), n0, p0);
    recurrencePartial(norm, pointers(f, n0), V.data() + n0, n - n0, p1);
    recurrencePartial(norm, pointers(f), V.data(), 0, pEmpty); // a rank without cells
    const bool useMax = recurrenceNeedsMaxReduction(norm);
    std::vector<double> reduced(p0.size());
    for (std::size_t e = 0; e < reduced.size(); ++e) {
      reduced[e] = useMax ? std::fmax(p0[e], p1[e]) : p0[e] + p1[e];
      reduced[e] = useMax ? std::fmax(reduced[e], pEmpty[e]) : reduced[e] + pEmpty[e];
    }
    recurrenceFinish(norm, K, reduced);
    double worst = 0.0;
    for (std::size_t e = 0; e < whole.size(); ++e)
      worst = std::fmax(worst, std::fabs(reduced[e] - whole[e]));
    RCFD_CHECK(worst < 1e-13);
  }
}

void testNamesAndReductions() {
  for (RecurrenceNorm norm : kNorms)
    RCFD_CHECK(parseRecurrenceNorm(recurrenceNormName(norm)) == norm);
  RCFD_CHECK(recurrenceNeedsMaxReduction(RecurrenceNorm::Max));
  RCFD_CHECK(!recurrenceNeedsMaxReduction(RecurrenceNorm::SqrDiff));
  RCFD_CHECK(!recurrenceNeedsMaxReduction(RecurrenceNorm::Euclidean));
  RCFD_CHECK(!recurrenceNeedsMaxReduction(RecurrenceNorm::AbsDiff));
}

void testEdgeCasesAndErrors() {
  // Identical frames: the matrix stays zero instead of dividing by zero.
  const std::vector<std::vector<double>> same{{0.2, 0.3}, {0.2, 0.3}, {0.2, 0.3}};
  const std::vector<double> V{1.0, 1.0};
  for (RecurrenceNorm norm : kNorms) {
    const auto m = recurrenceMatrix(norm, pointers(same), V.data(), 2);
    bool allZero = true;
    for (double v : m) allZero = allZero && v == 0.0;
    RCFD_CHECK(allZero);
  }
  // The max norm ignores the volumes and accepts none.
  const auto mMax = recurrenceMatrix(RecurrenceNorm::Max, pointers(same), nullptr, 2);
  RCFD_CHECK(mMax.size() == 9);

  auto nan = same;
  nan[1][1] = std::nan("");
  for (RecurrenceNorm norm : kNorms)
    RCFD_CHECK(throwsInvalid([&] { recurrenceMatrix(norm, pointers(nan), V.data(), 2); }));
  auto inf = same;
  inf[2][0] = HUGE_VAL;
  RCFD_CHECK(throwsInvalid([&] { recurrenceMatrix(RecurrenceNorm::Max, pointers(inf), V.data(), 2); }));

  const std::vector<double> badV{1.0, 0.0};
  RCFD_CHECK(throwsInvalid(
      [&] { recurrenceMatrix(RecurrenceNorm::SqrDiff, pointers(same), badV.data(), 2); }));
  RCFD_CHECK(throwsInvalid(
      [&] { recurrenceMatrix(RecurrenceNorm::AbsDiff, pointers(same), nullptr, 2); }));
  RCFD_CHECK(throwsInvalid([] { parseRecurrenceNorm("euclid"); }));
  std::vector<double> wrong(8, 0.0);
  RCFD_CHECK(throwsInvalid([&] { recurrenceFinish(RecurrenceNorm::SqrDiff, 3, wrong); }));
  std::vector<double> negative{0.0, -1.0, -1.0, 0.0};
  RCFD_CHECK(throwsInvalid([&] { recurrenceFinish(RecurrenceNorm::SqrDiff, 2, negative); }));
}

} // namespace

int main() {
  testHandComputed();
  testAgainstBruteForce();
  testTwoRanks();
  testNamesAndReductions();
  testEdgeCasesAndErrors();
  return RCFD_TEST_RESULT();
}
