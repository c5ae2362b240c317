// Frame paths: the rules of every kind over long runs, checked against a
// brute-force search of the recurrence matrix; seeds, save/restore, recorded
// paths and their files; bad parameters.
#include "check.hpp"
#include "path/frame_path.hpp"
#include "path/recurrence.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <numeric>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

using namespace rcfd;

namespace {

struct Step {
  int frame;
  bool jump;
};

std::vector<Step> run(FramePath &p, int n) {
  std::vector<Step> s;
  for (int k = 0; k < n; ++k) {
    const int f = p.next();
    s.push_back({f, p.lastWasJump()});
  }
  return s;
}

bool same(const std::vector<Step> &a, const std::vector<Step> &b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (a[k].frame != b[k].frame || a[k].jump != b[k].jump) return false;
  return true;
}

// A symmetric "recurrence matrix" with a zero diagonal and distinct values in
// (0, 1], from the test's own generator so it does not depend on the library.
std::vector<double> makeMatrix(int K, std::uint64_t seed) {
  std::vector<double> R(static_cast<std::size_t>(K) * K, 0.0);
  for (int i = 0; i < K; ++i)
    for (int j = i + 1; j < K; ++j) {
      seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
      const double v = (static_cast<double>(seed >> 11) + 1.0) * 0x1.0p-53;
      R[static_cast<std::size_t>(i) * K + j] = R[static_cast<std::size_t>(j) * K + i] = v;
    }
  return R;
}

/// Brute force: the allowed j (j <= K-2, allowed(i, j)) ordered by R[i][j],
/// ties to the smaller j; returns the first n.
std::vector<int> bestMatches(const std::vector<double> &R, int K, int i, int n,
                             const std::function<bool(int, int)> &allowed) {
  std::vector<int> best;
  std::vector<bool> taken(K, false);
  for (int r = 0; r < n; ++r) {
    int b = -1;
    for (int j = 0; j <= K - 2; ++j) {
      if (taken[j] || !allowed(i, j)) continue;
      if (b < 0 || R[static_cast<std::size_t>(i) * K + j] < R[static_cast<std::size_t>(i) * K + b])
        b = j;
    }
    if (b < 0) break;
    best.push_back(b);
    taken[b] = true;
  }
  return best;
}

struct Sequence {
  int start, length;
  bool endedByJump;
};

/// Checks the rules shared by every stitching kind and returns the sequences.
std::vector<Sequence> checkStitching(const std::vector<Step> &steps, const std::vector<double> &R,
                                     int K, int candidates,
                                     const std::function<bool(int, int)> &allowed) {
  std::vector<Sequence> seqs;
  bool inRange = true, advanceByOne = true, targetOk = true, firstNotJump = !steps[0].jump;
  seqs.push_back({steps[0].frame, 1, false});
  for (std::size_t k = 0; k < steps.size(); ++k) {
    const int f = steps[k].frame;
    inRange = inRange && f >= 0 && f < K;
    if (k == 0) continue;
    const int prev = steps[k - 1].frame;
    if (!steps[k].jump) {
      advanceByOne = advanceByOne && f == prev + 1;
      ++seqs.back().length;
      continue;
    }
    // A jump from prev starts the new sequence at j + 1, j among the best matches.
    const auto best = bestMatches(R, K, prev, candidates, allowed);
    bool found = false;
    for (int j : best) found = found || f == j + 1;
    targetOk = targetOk && found;
    seqs.back().endedByJump = true;
    seqs.push_back({f, 1, false});
  }
  RCFD_CHECK(firstNotJump);
  RCFD_CHECK(inRange);
  RCFD_CHECK(advanceByOne);
  RCFD_CHECK(targetOk);
  return seqs;
}

template <class E = std::invalid_argument, class F> bool throwsWith(F f, const std::string &word) {
  try {
    f();
  } catch (const E &e) {
    const std::string what = e.what();
    if (what.find(word) == std::string::npos)
      std::fprintf(stderr, "message without \"%s\": %s\n", word.c_str(), what.c_str());
    return what.find(word) != std::string::npos;
  }
  return false;
}

void testPrng() {
  // splitmix64 from 0 gives 0xe220a8397b1dcdaf first (the published sequence);
  // the generator's first state word is exactly that.
  Xoshiro256 g(0);
  RCFD_CHECK(g.state()[0] == 0xe220a8397b1dcdafULL);
  // below() and uniform() stay in range.
  bool ok = true;
  std::vector<int> hits(7, 0);
  for (int k = 0; k < 70000; ++k) {
    const auto b = g.below(7);
    ok = ok && b < 7;
    ++hits[b];
    const double u = g.uniform();
    ok = ok && u >= 0.0 && u < 1.0;
  }
  RCFD_CHECK(ok);
  for (int h : hits) RCFD_CHECK(std::abs(h - 10000) < 500);
  // Same seed, same stream; save and restore continue it.
  Xoshiro256 a(42), b(42);
  for (int k = 0; k < 10; ++k) RCFD_CHECK(a.next() == b.next());
  const auto s = a.state();
  const auto x = a.next();
  b.setState(s);
  RCFD_CHECK(b.next() == x);
  RCFD_CHECK(throwsWith([&] { b.setState({0, 0, 0, 0}); }, "all-zero"));
}

void testReplay() {
  const int K = 17;
  auto p = makeFramePath("replay", K, {});
  bool ok = true;
  for (int s = 0; s < 100; ++s) {
    const int f = p->next();
    ok = ok && f == s % K && p->lastWasJump() == (s > 0 && s % K == 0);
  }
  RCFD_CHECK(ok);
  RCFD_CHECK(p->steps() == 100);
  PathParams q;
  q.startFrame = 15;
  auto r = makeFramePath("replay", K, {}, q);
  RCFD_CHECK(r->next() == 15 && !r->lastWasJump());
  RCFD_CHECK(r->next() == 16 && !r->lastWasJump());
  RCFD_CHECK(r->next() == 0 && r->lastWasJump());
}

void testRandom() {
  const int K = 300;
  const auto R = makeMatrix(K, 1);
  // Defaults: minLength 15, maxLength 60, band 30.
  auto p = makeFramePath("random", K, R);
  const auto steps = run(*p, 100000);
  const int Lmin = 15, Lmax = 60, band = 30;
  const auto seqs = checkStitching(steps, R, K, 1,
                                   [&](int i, int j) { return std::abs(i - j) >= band; });
  bool lengthsOk = true, sawMin = false, sawMax = false;
  for (const auto &s : seqs) {
    if (!s.endedByJump) continue; // the last sequence is unfinished
    const bool cut = s.start + s.length == K; // shortened at the last frame
    lengthsOk = lengthsOk && s.length <= Lmax && (s.length >= Lmin || cut);
    sawMin = sawMin || (s.length == Lmin && !cut);
    sawMax = sawMax || s.length == Lmax;
  }
  RCFD_CHECK(lengthsOk);
  RCFD_CHECK(sawMin && sawMax); // both ends of [Lmin, Lmax] occur
  RCFD_CHECK(seqs.size() > 1000);

  // Explicit parameters, several candidates.
  PathParams q;
  q.minLength = 3;
  q.maxLength = 5;
  q.band = 100;
  q.candidates = 3;
  q.seed = 7;
  auto c = makeFramePath("random", K, R, q);
  const auto cs = run(*c, 50000);
  const auto cseq = checkStitching(cs, R, K, 3, [](int i, int j) { return std::abs(i - j) >= 100; });
  bool ok = true;
  for (const auto &s : cseq)
    if (s.endedByJump) ok = ok && s.length <= 5 && (s.length >= 3 || s.start + s.length == K);
  RCFD_CHECK(ok);
}

void testMarkov() {
  const int K = 2000;
  const auto R = makeMatrix(K, 2);
  PathParams q;
  q.minLength = 5;
  q.meanIntervalSteps = 20.0;
  q.band = 50;
  q.seed = 3;
  auto p = makeFramePath("markov", K, R, q);
  const auto steps = run(*p, 200000);
  const auto seqs = checkStitching(steps, R, K, 1, [](int i, int j) { return std::abs(i - j) >= 50; });
  bool ok = true;
  double sum = 0.0;
  int n = 0;
  for (const auto &s : seqs) {
    if (!s.endedByJump) continue;
    const bool cut = s.start + s.length == K;
    ok = ok && (s.length >= 5 || cut);
    if (!cut) sum += s.length, ++n;
  }
  RCFD_CHECK(ok);
  // Geometric tail: mean length minLength + meanIntervalSteps = 25.
  RCFD_CHECK(n > 5000);
  RCFD_CHECK(std::fabs(sum / n - 25.0) < 1.0);

  // Defaults for K = 300: minLength 15, meanIntervalSteps 30, band 30.
  const auto R3 = makeMatrix(300, 4);
  auto d = makeFramePath("markov", 300, R3);
  const auto ds = run(*d, 50000);
  checkStitching(ds, R3, 300, 1, [](int i, int j) { return std::abs(i - j) >= 30; });
}

void testQuarter() {
  const int K = 403; // quarters of unequal size
  const auto R = makeMatrix(K, 5);
  const auto quarter = [&](int i) { return static_cast<int>(4LL * i / K); };
  auto p = makeFramePath("quarter", K, R); // minLength 16, maxLength 100
  const auto steps = run(*p, 100000);
  const auto seqs = checkStitching(steps, R, K, 1, [&](int i, int j) {
    return quarter(j) == (quarter(i) + 2) % 4;
  });
  bool ok = true;
  for (const auto &s : seqs)
    if (s.endedByJump) // L = 16 + floor(U * 84) lies in [16, 99]
      ok = ok && s.length <= 99 && (s.length >= 16 || s.start + s.length == K);
  RCFD_CHECK(ok);
  // Smallest K with a target for every frame.
  RCFD_CHECK(makeFramePath("quarter", 8, makeMatrix(8, 6)) != nullptr);
  RCFD_CHECK(throwsWith([] { makeFramePath("quarter", 7, makeMatrix(7, 6)); }, "no allowed jump"));
}

void testTies() {
  // All off-diagonal entries equal: the best match is the smallest allowed j.
  const int K = 40;
  std::vector<double> R(K * K, 1.0);
  for (int i = 0; i < K; ++i) R[i * K + i] = 0.0;
  PathParams q;
  q.band = 10;
  q.minLength = q.maxLength = 4;
  auto p = makeFramePath("random", K, R, q);
  const auto steps = run(*p, 2000);
  bool ok = true;
  for (std::size_t k = 1; k < steps.size(); ++k)
    if (steps[k].jump) {
      const int i = steps[k - 1].frame;
      const int j = i >= 10 ? 0 : i + 10; // smallest j with |i - j| >= 10
      ok = ok && steps[k].frame == j + 1;
    }
  RCFD_CHECK(ok);
}

void testPeriodicDatabase() {
  // A database that repeats itself every P frames: the recurrence matrix from
  // the library is zero between frames of the same phase, so every jump must
  // keep the phase (and ties go to the smallest such frame).
  const int K = 200, P = 20;
  const double kTwoPi = 6.283185307179586;
  const std::size_t n = 50;
  std::vector<std::vector<double>> f(K, std::vector<double>(n));
  for (int k = 0; k < K; ++k)
    for (std::size_t c = 0; c < n; ++c)
      f[k][c] = 0.3 + 0.2 * std::sin(0.7 * static_cast<double>(c) + kTwoPi * (k % P) / P);
  std::vector<const double *> ptr;
  for (const auto &x : f) ptr.push_back(x.data());
  const std::vector<double> V(n, 1.0);
  const auto R = recurrenceMatrix(RecurrenceNorm::Euclidean, ptr, V.data(), n);
  for (const char *kind : {"random", "markov"}) {
    auto p = makeFramePath(kind, K, R);
    const auto steps = run(*p, 20000);
    bool phaseKept = true, jumped = false;
    for (std::size_t k = 1; k < steps.size(); ++k)
      if (steps[k].jump) {
        jumped = true;
        const int i = steps[k - 1].frame, j = steps[k].frame - 1;
        const int smallest = i % P == i ? i + P : i % P; // same phase, j != i
        phaseKept = phaseKept && j == smallest;
      }
    RCFD_CHECK(jumped && phaseKept);
  }
}

void testSeeds() {
  const int K = 250;
  const auto R = makeMatrix(K, 8);
  for (const char *kind : {"random", "markov", "quarter"}) {
    PathParams q;
    q.seed = 11;
    auto a = makeFramePath(kind, K, R, q);
    auto b = makeFramePath(kind, K, R, q);
    q.seed = 12;
    auto c = makeFramePath(kind, K, R, q);
    const auto sa = run(*a, 5000), sb = run(*b, 5000), sc = run(*c, 5000);
    RCFD_CHECK(same(sa, sb));
    RCFD_CHECK(!same(sa, sc));
    RCFD_CHECK(a->describe() == b->describe());
    RCFD_CHECK(a->configurationHash() == b->configurationHash());
    RCFD_CHECK(a->configurationHash() != c->configurationHash());
  }
}

void testSaveRestore() {
  const int K = 250;
  const auto R = makeMatrix(K, 9);
  for (const char *kind : {"replay", "random", "markov", "quarter"}) {
    auto a = makeFramePath(kind, K, R);
    run(*a, 1234);
    const auto state = a->saveState();
    const int frameAtSave = a->frame();
    const bool jumpAtSave = a->lastWasJump();
    const auto cont = run(*a, 3000);

    // A fresh path restored from the state continues identically ...
    auto b = makeFramePath(kind, K, R);
    restorePathState(*b, state);
    RCFD_CHECK(b->frame() == frameAtSave && b->lastWasJump() == jumpAtSave);
    RCFD_CHECK(b->steps() == 1234);
    RCFD_CHECK(same(run(*b, 3000), cont));
    // ... and so does the original, rewound.
    restorePathState(*a, state);
    RCFD_CHECK(same(run(*a, 3000), cont));
    // A state saved before the first step.
    auto c = makeFramePath(kind, K, R);
    auto d = makeFramePath(kind, K, R);
    restorePathState(*d, c->saveState());
    RCFD_CHECK(same(run(*c, 500), run(*d, 500)));
  }
  // States are refused by paths they do not belong to.
  PathParams other;
  other.seed = 2;
  auto a = makeFramePath("random", K, R);
  const auto state = a->saveState();
  RCFD_CHECK(throwsWith([&] { restorePathState(*makeFramePath("random", K, R, other), state); },
                        "other parameters"));
  RCFD_CHECK(throwsWith([&] { restorePathState(*makeFramePath("markov", K, R), state); },
                        "other parameters"));
  RCFD_CHECK(throwsWith([&] { restorePathState(*makeFramePath("random", K, makeMatrix(K, 10)), state); },
                        "recurrence matrix"));
  auto truncated = state;
  truncated.pop_back();
  RCFD_CHECK(throwsWith([&] { restorePathState(*a, truncated); }, "wrong size"));
  RCFD_CHECK(throwsWith([&] { restorePathState(*a, {1, 2, 3}); }, "not a saved frame path state"));
}

void testRecorded() {
  const int K = 120;
  const auto R = makeMatrix(K, 12);
  auto p = makeFramePath("random", K, R);
  const auto steps = run(*p, 2000);
  std::vector<int> frames;
  for (const auto &s : steps) frames.push_back(s.frame);

  const std::string file = "test_frame_path_recorded.txt";
  writePathFile(file, frames, p->describe() + "\nsecond header line");
  {
    std::ifstream in(file);
    std::string first;
    std::getline(in, first);
    RCFD_CHECK(first.rfind("# random: K=120", 0) == 0);
  }
  const auto back = readPathFile(file);
  RCFD_CHECK(back == frames);

  // The recorded path reproduces frames and jumps.
  auto rec = makeRecordedPath(K, back);
  RCFD_CHECK(same(run(*rec, 2000), steps));
  RCFD_CHECK(throwsWith<std::out_of_range>([&] { rec->next(); }, "2001"));
  auto rec2 = makeRecordedPath(K, back);
  run(*rec2, 700);
  const auto st = rec2->saveState();
  auto rec3 = makeRecordedPath(K, back);
  restorePathState(*rec3, st);
  std::vector<Step> tail(steps.begin() + 700, steps.end());
  RCFD_CHECK(same(run(*rec3, 1300), tail));

  // The first step is never a jump, wherever the list starts.
  auto mid = makeRecordedPath(K, {5, 6, 40});
  RCFD_CHECK(mid->next() == 5 && !mid->lastWasJump());
  RCFD_CHECK(mid->next() == 6 && !mid->lastWasJump());
  RCFD_CHECK(mid->next() == 40 && mid->lastWasJump());

  RCFD_CHECK(throwsWith([&] { makeRecordedPath(100, back); }, "outside"));
  RCFD_CHECK(throwsWith([] { makeRecordedPath(10, {}); }, "empty"));

  {
    std::ofstream out(file);
    out << "# header\n3\n\n4\nfive\n";
  }
  RCFD_CHECK(throwsWith<std::runtime_error>([&] { readPathFile(file); }, ":5:"));
  {
    std::ofstream out(file);
    out << "# header\n3\n-4\n";
  }
  RCFD_CHECK(throwsWith<std::runtime_error>([&] { readPathFile(file); }, ":3:"));
  std::remove(file.c_str());
  RCFD_CHECK(throwsWith<std::runtime_error>([&] { readPathFile(file); }, "cannot open"));
}

void testBadParameters() {
  const int K = 100;
  const auto R = makeMatrix(K, 13);
  PathParams q;
  q.minLength = 10;
  q.maxLength = 5;
  RCFD_CHECK(throwsWith([&] { makeFramePath("random", K, R, q); }, "larger than maxLength"));
  RCFD_CHECK(throwsWith([&] { makeFramePath("quarter", K, R, q); }, "larger than maxLength"));

  PathParams wide;
  wide.band = 50; // the widest band for 100 frames is 49
  RCFD_CHECK(throwsWith([&] { makeFramePath("random", K, R, wide); }, "too wide"));
  RCFD_CHECK(throwsWith([&] { makeFramePath("markov", K, R, wide); }, "too wide"));
  wide.band = 49;
  RCFD_CHECK(makeFramePath("random", K, R, wide) != nullptr);

  for (const char *kind : {"replay", "random", "markov", "quarter"}) {
    RCFD_CHECK(throwsWith([&] { makeFramePath(kind, 1, std::vector<double>{0.0}); },
                          "at least 2 frames"));
    PathParams s;
    s.startFrame = K;
    RCFD_CHECK(throwsWith([&] { makeFramePath(kind, K, R, s); }, "startFrame"));
  }
  RCFD_CHECK(throwsWith([] { makeRecordedPath(1, {0}); }, "at least 2 frames"));
  RCFD_CHECK(throwsWith([&] { makeFramePath("random", 2, makeMatrix(2, 1)); }, "too wide"));
  RCFD_CHECK(throwsWith([&] { makeFramePath("stitch", K, R); }, "unknown frame path kind"));
  RCFD_CHECK(throwsWith([&] { makeFramePath("random", K + 1, R); }, "K * K"));

  auto nan = R;
  nan[5] = std::nan("");
  RCFD_CHECK(throwsWith([&] { makeFramePath("random", K, nan); }, "not finite"));

  PathParams b;
  b.band = 5;
  RCFD_CHECK(throwsWith([&] { makeFramePath("quarter", K, R, b); }, "does not apply"));
  RCFD_CHECK(throwsWith([&] { makeFramePath("replay", K, R, b); }, "does not apply"));
  PathParams m;
  m.meanIntervalSteps = 10.0;
  RCFD_CHECK(throwsWith([&] { makeFramePath("random", K, R, m); }, "does not apply"));
  m.meanIntervalSteps = -1.0;
  RCFD_CHECK(throwsWith([&] { makeFramePath("markov", K, R, m); }, "meanIntervalSteps"));
  PathParams c;
  c.candidates = 0;
  RCFD_CHECK(throwsWith([&] { makeFramePath("random", K, R, c); }, "candidates"));
  PathParams z;
  z.minLength = 0;
  RCFD_CHECK(throwsWith([&] { makeFramePath("random", K, R, z); }, "minLength"));
  z.minLength = K + 1;
  z.maxLength = K + 1;
  RCFD_CHECK(throwsWith([&] { makeFramePath("random", K, R, z); }, "exceeds"));
}

/// How far the use of frames 1 ... K-1 (steps spent in each) is from uniform:
/// the larger of largest / mean and mean / smallest, so 2 means "within a factor
/// 2 of uniform" (issue 15).  Frame 0 is entered only at the start (every
/// target is J + 1).
double unevenness(const std::vector<Step> &steps, int K) {
  std::vector<double> use(K, 0.0);
  for (const auto &s : steps) use[s.frame] += 1.0;
  const double mean = std::accumulate(use.begin() + 1, use.end(), 0.0) / (K - 1);
  const auto [lo, hi] = std::minmax_element(use.begin() + 1, use.end());
  return *lo > 0.0 ? std::max(*hi / mean, mean / *lo) : 1e300;
}

// The least-used rule (issue 15): every jump goes to the candidate whose next
// minLength frames (cut at the last frame) the path has used least per frame
// so far, checked by brute force for every kind; reproducible for a seed; its
// counts are saved and restored; its frame use is more even than the uniform
// draw's.
void testLeastUsed() {
  const int K = 200, n = 12, minLength = 4;
  const auto R = makeMatrix(K, 12);
  const auto byBand = [](int i, int j) { return std::abs(i - j) >= 20; }; // K / 10
  const auto byQuarter = [K](int i, int j) { return 4 * j / K == (4 * i / K + 2) % 4; };
  for (const char *kind : {"random", "markov", "quarter"}) {
    PathParams q;
    q.candidates = n;
    q.minLength = minLength;
    q.leastUsed = true;
    q.seed = 5;
    auto a = makeFramePath(kind, K, R, q);
    const auto steps = run(*a, 20000);
    const bool quarter = std::string(kind) == "quarter";
    std::vector<std::uint64_t> use(K, 0);
    ++use[steps[0].frame];
    bool leastUsed = true, jumped = false;
    for (std::size_t k = 1; k < steps.size(); ++k) {
      if (steps[k].jump) {
        jumped = true;
        const int J = steps[k].frame - 1;
        const auto best = quarter ? bestMatches(R, K, steps[k - 1].frame, n, byQuarter)
                                  : bestMatches(R, K, steps[k - 1].frame, n, byBand);
        const auto window = [&](int j, std::uint64_t &frames) {
          const int last = std::min(j + minLength, K - 1);
          std::uint64_t u = 0;
          for (int f = j + 1; f <= last; ++f) u += use[f];
          frames = static_cast<std::uint64_t>(last - j);
          return u;
        };
        std::uint64_t fJ = 0, fc = 0;
        const std::uint64_t uJ = window(J, fJ);
        leastUsed = leastUsed && std::find(best.begin(), best.end(), J) != best.end();
        for (int c : best) {
          const std::uint64_t uc = window(c, fc);
          leastUsed = leastUsed && uJ * fc <= uc * fJ; // mean use of J's window <= c's
        }
      }
      ++use[steps[k].frame];
    }
    RCFD_CHECK(jumped && leastUsed);
    auto b = makeFramePath(kind, K, R, q);
    RCFD_CHECK(same(run(*b, 20000), steps));
    RCFD_CHECK(b->describe().find("leastUsed") != std::string::npos);
    // Restored mid-run with its counts, it continues identically.
    auto c = makeFramePath(kind, K, R, q);
    run(*c, 1234);
    const auto state = c->saveState();
    const auto cont = run(*c, 5000);
    auto d = makeFramePath(kind, K, R, q);
    restorePathState(*d, state);
    RCFD_CHECK(same(run(*d, 5000), cont));
    // The rule is part of the configuration: states do not cross between the rules.
    PathParams uniform = q;
    uniform.leastUsed = false;
    RCFD_CHECK(throwsWith([&] { restorePathState(*makeFramePath(kind, K, R, uniform), state); },
                          "other parameters"));
    RCFD_CHECK(throwsWith([&] { restorePathState(*makeFramePath(kind, K, R, q), 
                                    makeFramePath(kind, K, R, uniform)->saveState()); },
                          "other parameters"));
    auto truncated = state;
    truncated.pop_back();
    RCFD_CHECK(throwsWith([&] { restorePathState(*d, truncated); }, "wrong size"));
    if (quarter) continue;
    // Over a long path, the frames are used far more evenly than with the uniform draw.
    const double even = unevenness(steps, K),
                 drawn = unevenness(run(*makeFramePath(kind, K, R, uniform), 20000), K);
    std::printf("%s path, %d frames, 20000 steps: use of frames 1..K-1 within a factor %.2f of "
                "uniform (least used), %.2f (uniform draw)\n", kind, K, even, drawn);
    RCFD_CHECK(even < 2.0);
    RCFD_CHECK(even < drawn);
  }
  // Replay has no jump targets to choose.
  PathParams r;
  r.leastUsed = true;
  RCFD_CHECK(throwsWith([&] { makeFramePath("replay", K, {}, r); }, "leastUsed"));
}

// The clock window (issue 28): every jump of step n lands within W frames of
// the clock min(n, K - 1) on one of the best matches among the frames there
// outside the band; past the database's end the path stays in its last
// frames; a saved state continues identically and does not cross to a path
// without the window; bad windows are refused with their name.
void testClockWindow() {
  const int K = 200, W = 10, candidates = 4;
  const auto R = makeMatrix(K, 21);
  for (const char *kind : {"random", "markov"})
    for (bool leastUsed : {false, true}) {
      PathParams q;
      q.candidates = candidates;
      q.clockWindow = W;
      q.leastUsed = leastUsed;
      q.seed = 9;
      auto a = makeFramePath(kind, K, R, q);
      const auto steps = run(*a, 3 * K);
      const int band = std::max(1, W / 6);
      bool inWindow = true, best = true, consecutive = true, late = true;
      int jumps = 0;
      for (std::size_t n = 1; n < steps.size(); ++n) {
        const int f = steps[n].frame, i = steps[n - 1].frame;
        const int c = std::min<int>(static_cast<int>(n), K - 1);
        if (n >= static_cast<std::size_t>(K)) late = late && f >= K - 1 - W;
        if (!steps[n].jump) {
          consecutive = consecutive && f == i + 1;
          continue;
        }
        ++jumps;
        inWindow = inWindow && std::abs(f - c) <= W && std::abs(i - (f - 1)) >= band;
        const auto allowed = [&](int from, int j) {
          return std::abs(j + 1 - c) <= W && std::abs(from - j) >= band;
        };
        const auto top = bestMatches(R, K, i, candidates, allowed);
        best = best && std::find(top.begin(), top.end(), f - 1) != top.end();
      }
      std::printf("%s path (leastUsed %d), clock window %d: %d jumps in %d steps\n", kind, leastUsed,
                  W, jumps, 3 * K);
      RCFD_CHECK(jumps > 10);
      RCFD_CHECK(inWindow && best && consecutive && late);
      RCFD_CHECK(a->describe().find("clockWindow=10") != std::string::npos);
      // Restored mid-run (past the end too), it continues identically.
      for (int at : {123, 250}) {
        auto c = makeFramePath(kind, K, R, q);
        run(*c, at);
        const auto state = c->saveState();
        const auto cont = run(*c, 300);
        auto d = makeFramePath(kind, K, R, q);
        restorePathState(*d, state);
        RCFD_CHECK(same(run(*d, 300), cont));
        PathParams off = q;
        off.clockWindow.reset();
        RCFD_CHECK(throwsWith([&] { restorePathState(*makeFramePath(kind, K, R, off), state); },
                              "other parameters"));
      }
    }
  PathParams z;
  z.clockWindow = 0;
  RCFD_CHECK(throwsWith([&] { makeFramePath("random", K, R, z); }, "clockWindow must be at least 1"));
  z.clockWindow = 6;
  z.band = 7;
  RCFD_CHECK(throwsWith([&] { makeFramePath("markov", K, R, z); }, "when the path follows the clock"));
  z.band.reset();
  RCFD_CHECK(throwsWith([&] { makeFramePath("quarter", K, R, z); }, "clockWindow"));
  // A database shorter than the window: the band is dropped where it leaves no target.
  const int k = 4;
  PathParams small;
  small.clockWindow = 6;
  small.band = 6;
  small.minLength = 1;
  small.maxLength = 1;
  const auto tiny = run(*makeFramePath("random", k, makeMatrix(k, 3), small), 50);
  bool valid = true;
  for (const auto &s : tiny) valid = valid && s.frame >= 0 && s.frame < k;
  RCFD_CHECK(valid);
}

} // namespace

int main(int argc, char **argv) {
  // PETSc up: a path's restoreState() reports its refusal as a PETSc error.
  if (PetscInitialize(&argc, &argv, nullptr, nullptr)) return 1;
  testPrng();
  testReplay();
  testRandom();
  testMarkov();
  testQuarter();
  testTies();
  testPeriodicDatabase();
  testSeeds();
  testSaveRestore();
  testLeastUsed();
  testClockWindow();
  testRecorded();
  testBadParameters();
  const int result = RCFD_TEST_RESULT();
  return PetscFinalize() ? 1 : result;
}
