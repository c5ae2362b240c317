// The stitching paths (random, markov, quarter): sequences of consecutive
// frames joined by jumps to a frame whose alpha_s matches, by the database's
// recurrence matrix, the one where the sequence ended (docs/paths.md).
#include "path/builtin_paths.hpp"
#include "base/checked_options.hpp"
#include "base/petsc_compat.hpp"

#include "base/collective.hpp"
#include "path/database_recurrence.hpp"
#include "path/hasher.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace rcfd {
namespace {

/// How a stitching path decides where a sequence ends.
enum class Ending {
  UniformLength, ///< random: L uniform in [minLength, maxLength], drawn at the start
  QuarterLength, ///< quarter: L = minLength + floor(U (maxLength - minLength))
  Markov         ///< after minLength frames, end with probability p at each step
};

struct StitchingConfig {
  std::string kind;
  Ending ending = Ending::UniformLength;
  std::uint64_t seed = 1;
  int start = 0;
  int minLength = 1, maxLength = 1, band = 0;
  double meanInterval = 0.0;
  int candidates = 1;
  bool leastUsed = false; ///< jump to the least-used candidate (PathParams::leastUsed)
  int clockWindow = 0;    ///< PathParams::clockWindow; 0: off
};

/// For every frame i, the `width` best allowed targets j (smallest R[i][j],
/// ties to the smaller j), and how many there are.
template <class Allowed>
void buildJumpTable(int K, const std::vector<double> &R, int width, Allowed allowed,
                    const std::string &kind, const std::string &hint, std::vector<int> &table,
                    std::vector<int> &count) {
  table.assign(static_cast<std::size_t>(K) * width, -1);
  count.assign(K, 0);
  std::vector<int> cand;
  cand.reserve(K);
  for (int i = 0; i < K; ++i) {
    const double *row = R.data() + static_cast<std::size_t>(i) * K;
    cand.clear();
    for (int j = 0; j <= K - 2; ++j) // j + 1 must be a frame
      if (allowed(i, j)) cand.push_back(j);
    if (cand.empty())
      throw std::invalid_argument(pathParameterError(kind, "frame " + std::to_string(i) + " of " +
                                                       std::to_string(K) +
                                                       " has no allowed jump target; " + hint));
    const auto better = [row](int a, int b) { return row[a] < row[b] || (row[a] == row[b] && a < b); };
    const int n = std::min<int>(width, static_cast<int>(cand.size()));
    std::partial_sort(cand.begin(), cand.begin() + n, cand.end(), better);
    std::copy(cand.begin(), cand.begin() + n, table.begin() + static_cast<std::size_t>(i) * width);
    count[i] = n;
  }
}

void checkRecurrence(int K, const std::vector<double> &R, const std::string &kind) {
  const std::size_t need = static_cast<std::size_t>(K) * static_cast<std::size_t>(K);
  if (R.size() != need)
    throw std::invalid_argument(pathParameterError(
        kind, "the recurrence matrix holds " + std::to_string(R.size()) + " values but " +
                  std::to_string(K) + " frames need K * K = " + std::to_string(need)));
  for (std::size_t e = 0; e < need; ++e)
    if (!std::isfinite(R[e]))
      throw std::invalid_argument(pathParameterError(
          kind, "recurrence matrix entry (" + std::to_string(e / K) + ", " +
                    std::to_string(e % K) + ") is not finite"));
}

/// How much more frames far apart differ than frames nearby: the mean of R
/// over pairs at least K/2 apart over its mean at K/10 ... K/4 apart.  About 1
/// or below for a steady bed (the synthetic default bed: 0.88); above for a
/// database that records a transient (the shared CFD-DEM beds: 1.17-1.30).
/// 0 when K < 8 (no such pairs).
double recurrenceTrend(int K, const std::vector<double> &R) {
  if (K < 8) return 0.0;
  double near = 0.0, far = 0.0;
  std::size_t nNear = 0, nFar = 0;
  for (int i = 0; i < K; ++i)
    for (int j = 0; j < K; ++j) {
      const int d = std::abs(i - j);
      const double r = R[static_cast<std::size_t>(i) * K + j];
      if (d >= std::max(1, K / 10) && d <= K / 4) near += r, ++nNear;
      if (d >= K / 2) far += r, ++nFar;
    }
  return near > 0.0 ? (far / nFar) / (near / nNear) : 0.0;
}

void refuseUnused(const std::string &kind, bool set, const char *name) {
  if (set)
    throw std::invalid_argument(pathParameterError(kind, std::string("the parameter ") + name +
                                                             " does not apply to this kind"));
}

/// The resolved configuration and jump table of a stitching kind for K frames.
void configureStitching(const std::string &kind, int K, const std::vector<double> &R,
                        const PathParams &p, StitchingConfig &c, std::vector<int> &table,
                        std::vector<int> &count) {
  const bool markov = kind == "markov", quarter = kind == "quarter";
  checkRecurrence(K, R, kind);
  c.kind = kind;
  c.seed = p.seed;
  c.start = p.startFrame;
  c.candidates = p.candidates;
  c.leastUsed = p.leastUsed;
  if (p.candidates < 1)
    throw std::invalid_argument(pathParameterError(kind, "candidates must be at least 1, not " +
                                                     std::to_string(p.candidates)));
  if (markov) {
    refuseUnused(kind, p.maxLength.has_value(), "maxLength");
    c.ending = Ending::Markov;
    c.minLength = p.minLength.value_or(std::max(1, K / 20));
    c.maxLength = K;
    c.meanInterval = p.meanIntervalSteps.value_or(K / 10);
    if (!std::isfinite(c.meanInterval) || c.meanInterval < 0.0)
      throw std::invalid_argument(
          pathParameterError(kind, "meanIntervalSteps must be a finite number >= 0"));
  } else {
    refuseUnused(kind, p.meanIntervalSteps.has_value(), "meanIntervalSteps");
    c.ending = quarter ? Ending::QuarterLength : Ending::UniformLength;
    c.minLength = p.minLength.value_or(std::max(1, quarter ? K / 25 : K / 20));
    c.maxLength = p.maxLength.value_or(std::max(c.minLength, quarter ? K / 4 : K / 5));
  }
  if (c.minLength < 1)
    throw std::invalid_argument(pathParameterError(kind, "minLength must be at least 1, not " +
                                                     std::to_string(c.minLength)));
  if (c.minLength > K)
    throw std::invalid_argument(pathParameterError(kind, "minLength " + std::to_string(c.minLength) +
                                                     " exceeds the " + std::to_string(K) +
                                                     " frames of the database"));
  if (c.minLength > c.maxLength)
    throw std::invalid_argument(pathParameterError(kind, "minLength " + std::to_string(c.minLength) +
                                                     " is larger than maxLength " +
                                                     std::to_string(c.maxLength)));

  if (quarter) {
    refuseUnused(kind, p.band.has_value(), "band");
    refuseUnused(kind, p.clockWindow.has_value(), "clockWindow");
    // Quarter q holds the frames i with floor(4 i / K) = q; targets come from
    // quarter (q + 2) mod 4.
    const auto q = [K](int i) { return static_cast<int>(4LL * i / K); };
    buildJumpTable(
        K, R, c.candidates, [&](int i, int j) { return q(j) == (q(i) + 2) % 4; }, kind,
        "quarter jumps need at least 8 frames, so that the last quarter holds a frame with a "
        "successor",
        table, count);
  } else if (p.clockWindow) {
    c.clockWindow = *p.clockWindow;
    if (c.clockWindow < 1)
      throw std::invalid_argument(pathParameterError(kind, "clockWindow must be at least 1 frame, not " +
                                                       std::to_string(c.clockWindow)));
    c.band = p.band.value_or(std::max(1, c.clockWindow / 6));
    // band <= clockWindow leaves targets outside the band in every window of
    // a database longer than the window (a sequence ends within
    // clockWindow + 1 frames of the clock); clockTargets() drops the band
    // where a short database leaves none.
    if (c.band < 1 || c.band > c.clockWindow)
      throw std::invalid_argument(pathParameterError(
          kind, "band " + std::to_string(c.band) + " must lie in [1, clockWindow = " +
                    std::to_string(c.clockWindow) + "] when the path follows the clock"));
  } else {
    c.band = p.band.value_or(std::max(1, K / 10));
    if (c.band < 1)
      throw std::invalid_argument(pathParameterError(kind, "band must be at least 1, not " +
                                                       std::to_string(c.band)));
    // Targets j <= K-2 with |i - j| >= band exist for every i iff
    // band <= (K - 1) / 2 (the middle frame is the hardest).
    const int widest = (K - 1) / 2;
    if (c.band > widest)
      throw std::invalid_argument(pathParameterError(
          kind, "band " + std::to_string(c.band) + " is too wide for " + std::to_string(K) +
                    " frames: some frame would have no jump target (the widest band is " +
                    std::to_string(widest) + ")"));
    const int band = c.band;
    buildJumpTable(
        K, R, c.candidates, [band](int i, int j) { return std::abs(i - j) >= band; }, kind,
        "lower the band", table, count);
  }
}

/// Sequences of consecutive frames; at the end of a sequence at frame i the
/// next one starts at J + 1, J drawn from the precomputed best matches of i.
/// Only the jump table is kept, not the K x K matrix; a path that follows the
/// clock keeps the band of it that its jumps can reach instead.
class StitchingPath final : public FramePath {
public:
  /// Waits for setFromOptions() and setUp().  In runs a jump draws among
  /// the 4 best matches by default (PathParams: 1).
  explicit StitchingPath(std::string kind) {
    cfg_.kind = std::move(kind);
    params_.candidates = 4;
  }
  StitchingPath(std::string kind, int K, const std::vector<double> &R, const PathParams &p)
      : params_(p) {
    cfg_.kind = std::move(kind);
    build(K, R);
  }

  bool hasSeed() const override { return true; }
  std::uint64_t seed() const override { return params_.seed; }
  void setSeed(std::uint64_t s) override { params_.seed = s; }

  PetscErrorCode setFromOptions(MPI_Comm comm) override;
  PetscErrorCode setUp(const PathContext &ctx) override;
  PetscErrorCode view(PetscViewer viewer) const override {
    PetscFunctionBeginUser;
    PetscCall(FramePath::view(viewer));
    PetscCall(PetscViewerASCIIPrintf(viewer, "  %s recurrence matrix, %s\n",
                                     recurrenceNormName(norm_),
                                     stored_ ? "stored in the database" : "computed by this run"));
    PetscCall(PetscViewerASCIIPrintf(viewer, "  frames far apart differ %.3g times as much as frames nearby%s\n",
                                     trend_, trend_ > kTransientTrend ? " (a transient)" : ""));
    PetscFunctionReturn(PETSC_SUCCESS);
  }

  std::string type() const override { return cfg_.kind; }
  std::string describe() const override {
    std::ostringstream os;
    os << cfg_.kind << ": K=" << numFrames() << " seed=" << cfg_.seed << " start=" << cfg_.start
       << " minLength=" << cfg_.minLength;
    if (cfg_.ending == Ending::Markov)
      os << " meanIntervalSteps=" << cfg_.meanInterval << " band=" << cfg_.band;
    else
      os << " maxLength=" << cfg_.maxLength;
    if (cfg_.ending == Ending::UniformLength) os << " band=" << cfg_.band;
    os << " candidates=" << cfg_.candidates;
    if (cfg_.leastUsed) os << " leastUsed";
    if (cfg_.clockWindow > 0) os << " clockWindow=" << cfg_.clockWindow;
    return os.str();
  }

protected:
  int advance(bool &jump) override {
    if (frame() < 0) {
      beginSequence(cfg_.start);
      return counted(cfg_.start);
    }
    const int i = frame();
    if (sequenceEnds(i)) {
      const int s = jumpTarget(i) + 1;
      beginSequence(s);
      jump = true;
      return counted(s);
    }
    // Within a sequence; sequenceEnds() guarantees i + 1 <= K - 1.
    ++used_;
    return counted(i + 1);
  }

  std::uint64_t fingerprint() const override {
    Hasher h;
    h.add(cfg_.kind);
    h.add(static_cast<std::uint64_t>(cfg_.ending));
    h.add(cfg_.seed);
    for (int v : {cfg_.start, cfg_.minLength, cfg_.maxLength, cfg_.band, cfg_.candidates})
      h.add(static_cast<std::uint64_t>(v));
    h.add(cfg_.meanInterval);
    if (cfg_.leastUsed) h.add(std::string("leastUsed")); // absent: the hash of earlier versions
    for (int v : table_) h.add(static_cast<std::uint64_t>(v));
    if (cfg_.clockWindow > 0) { // absent: the hash of earlier versions
      h.add(std::string("clockWindow"));
      h.add(static_cast<std::uint64_t>(cfg_.clockWindow));
      for (double r : nearby_) h.add(r);
    }
    return h.value();
  }
  void saveExtra(std::vector<std::uint64_t> &out) const override {
    out.push_back(static_cast<std::uint64_t>(length_));
    out.push_back(static_cast<std::uint64_t>(used_));
    for (std::uint64_t w : rng_.state()) out.push_back(w);
    out.insert(out.end(), use_.begin(), use_.end()); // empty unless leastUsed
  }
  PetscErrorCode restoreExtra(const std::uint64_t *d, std::size_t n) override {
    PetscFunctionBeginUser;
    const auto K = static_cast<std::uint64_t>(numFrames());
    PetscCheck(n == 6 + use_.size() && d[0] <= K && d[1] <= K, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG,
               "restoreState: wrong size or values for a %s path state", cfg_.kind.c_str());
    rng_.setState({d[2], d[3], d[4], d[5]});
    length_ = static_cast<int>(d[0]);
    used_ = static_cast<int>(d[1]);
    std::copy(d + 6, d + n, use_.begin());
    PetscFunctionReturn(PETSC_SUCCESS);
  }

private:
  /// Resolves the parameters for K frames and builds the jump table from the
  /// normalised recurrence matrix R (K x K); throws std::invalid_argument.
  void build(int K, const std::vector<double> &R) {
    checkPathStart(cfg_.kind, K, params_);
    requireFrames(K);
    PetscCallAbort(PETSC_COMM_SELF, setNumFrames(K));
    std::string kind = cfg_.kind;
    configureStitching(kind, K, R, params_, cfg_, table_, count_);
    if (cfg_.clockWindow > 0) keepNearbyRecurrence(K, R);
    rng_ = Xoshiro256(cfg_.seed);
    jumpProbability_ = 1.0 / (1.0 + cfg_.meanInterval);
    use_.assign(cfg_.leastUsed ? K : 0, 0);
  }

  /// Counts the step in frame f (leastUsed only) and returns f.
  int counted(int f) {
    if (!use_.empty()) ++use_[f];
    return f;
  }

  /// Jump target J of a sequence ending at frame i: one of its best matches
  /// (row, n of them, best first), least used or drawn uniformly.
  int jumpTarget(int i) {
    if (cfg_.clockWindow > 0) clockTargets(i);
    const int *row = cfg_.clockWindow > 0 ? near_.data()
                                          : table_.data() + static_cast<std::size_t>(i) * cfg_.candidates;
    const int n = cfg_.clockWindow > 0 ? static_cast<int>(near_.size()) : count_[i];
    if (cfg_.leastUsed) return leastUsedTarget(row, n);
    return row[n > 1 ? static_cast<int>(rng_.below(static_cast<std::uint64_t>(n))) : 0];
  }

  /// Distances D = 2 clockWindow + 2 on either side of every frame: all a
  /// clock-following jump can reach, since a sequence ends within
  /// clockWindow + 1 of the clock and its target lies within clockWindow.
  int nearbyReach() const { return 2 * cfg_.clockWindow + 2; }
  void keepNearbyRecurrence(int K, const std::vector<double> &R) {
    const int D = nearbyReach(), width = 2 * D + 1;
    nearby_.assign(static_cast<std::size_t>(K) * width, 0.0);
    for (int i = 0; i < K; ++i)
      for (int j = std::max(0, i - D); j <= std::min(K - 1, i + D); ++j)
        nearby_[static_cast<std::size_t>(i) * width + (j - i + D)] = R[static_cast<std::size_t>(i) * K + j];
  }

  /// The clock-following targets of frame i into near_, best first: frames J
  /// with J + 1 within clockWindow of the clock and |i - J| >= band (without
  /// the band if a short database leaves none), the `candidates` best.
  void clockTargets(int i) {
    const int K = numFrames(), W = cfg_.clockWindow, D = nearbyReach();
    const auto clock = std::min<std::uint64_t>(static_cast<std::uint64_t>(cfg_.start) + steps(),
                                               static_cast<std::uint64_t>(K - 1));
    const int c = static_cast<int>(clock);
    const int lo = std::max({0, c - 1 - W, i - D}), hi = std::min({K - 2, c - 1 + W, i + D});
    near_.clear();
    for (int j = lo; j <= hi; ++j)
      if (std::abs(i - j) >= cfg_.band) near_.push_back(j);
    if (near_.empty())
      for (int j = lo; j <= hi; ++j) near_.push_back(j);
    if (near_.empty()) { // a bug, never a user error (the clock and i are within D): stop, as next() does
      std::fprintf(stderr, "rcfd: bug: the clock-following path has no jump target from frame %d\n", i);
      std::abort();
    }
    const double *row = nearby_.data() + static_cast<std::size_t>(i) * (2 * D + 1);
    const auto r = [row, i, D](int j) { return row[j - i + D]; };
    const auto better = [r](int a, int b) { return r(a) < r(b) || (r(a) == r(b) && a < b); };
    const int n = std::min<int>(cfg_.candidates, static_cast<int>(near_.size()));
    std::partial_sort(near_.begin(), near_.begin() + n, near_.end(), better);
    near_.resize(n);
  }

  /// The best match J of frame i whose next frames J+1 ... J+minLength (the
  /// ones the next sequence surely uses, up to the last frame) the path has
  /// used least so far, per frame (a window cut at the last frame holds fewer
  /// frames and must not look less used for it); ties drawn uniformly.
  /// Integers only (means compared by cross-multiplication), so every rank
  /// and platform picks the same target.
  int leastUsedTarget(const int *row, int n) {
    const int K = numFrames();
    std::uint64_t fewest = 0, fewestFrames = 0; // the least mean use so far, as a fraction
    ties_.clear();
    for (int c = 0; c < n; ++c) {
      const int last = std::min(row[c] + cfg_.minLength, K - 1);
      std::uint64_t u = 0;
      for (int f = row[c] + 1; f <= last; ++f) u += use_[f];
      const auto frames = static_cast<std::uint64_t>(last - row[c]); // >= 1: J <= K - 2
      if (ties_.empty() || u * fewestFrames < fewest * frames) {
        fewest = u;
        fewestFrames = frames;
        ties_.clear();
      }
      if (u * fewestFrames == fewest * frames) ties_.push_back(row[c]);
    }
    const auto tied = static_cast<std::uint64_t>(ties_.size());
    return tied > 1 ? ties_[rng_.below(tied)] : ties_.front();
  }

  void beginSequence(int s) {
    const int K = numFrames();
    used_ = 1;
    switch (cfg_.ending) {
    case Ending::UniformLength:
      length_ = cfg_.minLength +
                static_cast<int>(rng_.below(static_cast<std::uint64_t>(cfg_.maxLength -
                                                                       cfg_.minLength + 1)));
      break;
    case Ending::QuarterLength:
      length_ = cfg_.minLength +
                static_cast<int>(std::floor(rng_.uniform() * (cfg_.maxLength - cfg_.minLength)));
      break;
    case Ending::Markov: length_ = 0; return; // decided step by step
    }
    // A sequence must not run past the last frame: shorten it.
    length_ = std::min(length_, K - s);
  }

  /// Whether the sequence that used frame i as its used_-th frame ends here.
  bool sequenceEnds(int i) {
    if (i == numFrames() - 1) return true; // no frame after the last one
    if (cfg_.ending != Ending::Markov) return used_ >= length_;
    if (used_ < cfg_.minLength) return false;
    return rng_.uniform() < jumpProbability_;
  }

  PathParams params_;
  RecurrenceNorm norm_ = RecurrenceNorm::SqrDiff;
  bool stored_ = false; // the matrix came from the database file
  StitchingConfig cfg_;
  std::vector<int> table_; // K x candidates best matches, best first
  std::vector<int> count_; // valid entries per row of table_
  Xoshiro256 rng_;
  double jumpProbability_ = 0.0;
  int length_ = 0; // planned length of the current sequence (not for markov)
  int used_ = 0;   // frames of the current sequence used so far
  std::vector<std::uint64_t> use_; // leastUsed: steps spent in each frame so far
  std::vector<int> ties_;          // leastUsed: scratch for the tied targets
  std::vector<double> nearby_;     // clockWindow: R within nearbyReach() of each frame
  std::vector<int> near_;          // clockWindow: scratch for the targets of a jump
  double trend_ = 0.0;             // recurrenceTrend() of the database
  /// Above it setUp() notes a transient: between the synthetic bed's 0.88
  /// and the CFD-DEM beds' 1.17.
  static constexpr double kTransientTrend = 1.1;
};


PetscErrorCode StitchingPath::setFromOptions(MPI_Comm comm) {
  const std::string &kind = cfg_.kind;
  const bool markov = kind == "markov", quarter = kind == "quarter";
  PetscInt seed = static_cast<PetscInt>(params_.seed), start = params_.startFrame;
  PetscInt minLength = params_.minLength.value_or(-1), maxLength = params_.maxLength.value_or(-1);
  PetscInt band = params_.band.value_or(-1), candidates = params_.candidates;
  PetscInt clockWindow = params_.clockWindow.value_or(-1);
  PetscBool leastUsed = params_.leastUsed ? PETSC_TRUE : PETSC_FALSE;
  PetscReal meanInterval = params_.meanIntervalSteps.value_or(-1.0);
  char norm[32];
  PetscFunctionBeginUser;
  PetscCall(PetscStrncpy(norm, recurrenceNormName(norm_), sizeof norm));
  const std::string title = "Frame path " + kind + ": stitched sequences of frames";
  if (optionsPrefix() == "path_") { // the option's name before paths read their own options
    PetscOptionsBegin(comm, nullptr, "Frame path: renamed options", "rcfd");
    PetscCall(PetscOptionsDeprecated("-recurrence_norm", "-path_recurrence_norm", "0.2", nullptr));
    PetscOptionsEnd();
  }
  PetscOptionsBegin(comm, optionsPrefix().c_str(), title.c_str(), "rcfd");
  PetscCall(PetscOptionsInt("-seed", "Seed of the stitching path", "", seed, &seed, nullptr));
  PetscCall(PetscOptionsInt("-start", "Frame of the first step", "", start, &start, nullptr));
  PetscCall(PetscOptionsInt("-min_length", "Shortest sequence [frames] (default: by kind)", "",
                            minLength, &minLength, nullptr));
  if (!markov)
    PetscCall(PetscOptionsInt("-max_length", "Longest sequence [frames] (default: by kind)", "",
                              maxLength, &maxLength, nullptr));
  if (!quarter)
    PetscCall(PetscOptionsInt("-band", "Jumps only to frames at least this far away (default: K/10)",
                              "", band, &band, nullptr));
  if (markov)
    PetscCall(checkedReal(PetscOptionsObject, "-mean_interval",
                          "Mean extra steps before a jump (default: K/10)", &meanInterval, kNonNegative));
  PetscCall(PetscOptionsInt("-candidates", "Jump to one of this many best matches, at random", "",
                            candidates, &candidates, nullptr));
  if (!quarter)
    PetscCall(PetscOptionsInt("-clock_window",
                              "Jump only to frames within this many of the run's clock, the frame a replay "
                              "would use (for databases that record a transient; default: off)",
                              "", clockWindow, &clockWindow, nullptr));
  PetscCall(PetscOptionsBool("-least_used",
                             "Jump to the candidate whose next frames the path has used least "
                             "(evens out how often frames are used)",
                             "", leastUsed, &leastUsed, nullptr));
  PetscCall(PetscOptionsString("-recurrence_norm", "Distance between frames: sqrDiff, euclidean, absDiff or max",
                               "", norm, norm, sizeof norm, nullptr));
  PetscOptionsEnd();
  PetscCall(collectively(
      comm,
      [&] {
        try {
          norm_ = parseRecurrenceNorm(norm);
        } catch (const std::invalid_argument &e) {
          throw std::invalid_argument("-" + optionsPrefix() + "recurrence_norm: " + e.what());
        }
      },
      PETSC_ERR_USER_INPUT));
  // Values <= 0 (< 0 for the mean interval) keep the kind's default.
  params_.seed = static_cast<std::uint64_t>(seed);
  params_.startFrame = static_cast<int>(start);
  if (minLength > 0) params_.minLength = static_cast<int>(minLength);
  if (maxLength > 0) params_.maxLength = static_cast<int>(maxLength);
  if (band > 0) params_.band = static_cast<int>(band);
  if (clockWindow > 0) params_.clockWindow = static_cast<int>(clockWindow);
  if (meanInterval >= 0) params_.meanIntervalSteps = meanInterval;
  params_.candidates = static_cast<int>(candidates);
  params_.leastUsed = leastUsed == PETSC_TRUE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The path is built identically on every rank: from the stored recurrence
// matrix (or one computed and broadcast from rank 0), its parameters and seed.
PetscErrorCode StitchingPath::setUp(const PathContext &ctx) {
  const MPI_Comm comm = ctx.db.layout().comm();
  const int K = ctx.db.numFrames();
  std::vector<double> R;
  PetscFunctionBeginUser;
  PetscCall(FramePath::setUp(ctx));
  PetscCall(loadOrComputeRecurrence(ctx.db, norm_, &R, &stored_));
  if (!ctx.quiet && stored_)
    PetscCall(PetscPrintf(comm, "Using the %s recurrence matrix stored in %s\n",
                          recurrenceNormName(norm_), ctx.db.path().c_str()));
  if (!ctx.quiet && !stored_)
    PetscCall(PetscPrintf(comm, "Computed the %s recurrence matrix of %d frames (store it with "
                                "'rcfd recurrence %s' to reuse it)\n",
                          recurrenceNormName(norm_), K, ctx.db.path().c_str()));
  PetscCall(collectively(comm, [&] { build(K, R); }, PETSC_ERR_USER_INPUT));
  trend_ = recurrenceTrend(K, R);
  if (!ctx.quiet && cfg_.clockWindow == 0 && trend_ > kTransientTrend)
    PetscCall(PetscPrintf(comm,
                          "Note: frames far apart in %s differ %.2f times as much as frames nearby: it records "
                          "a transient, which a stitched path scrambles in time; -%sclock_window follows "
                          "it (docs/paths.md, \"Databases that record a transient\")\n",
                          ctx.db.path().c_str(), trend_, optionsPrefix().c_str()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

void checkPathStart(const std::string &kind, int K, const PathParams &p) {
  if (K < 2)
    throw std::invalid_argument(pathParameterError(kind, "a frame path needs at least 2 frames; the "
                                                 "database has " +
                                                     std::to_string(K)));
  if (p.startFrame < 0 || p.startFrame >= K)
    throw std::invalid_argument(pathParameterError(kind, "startFrame " + std::to_string(p.startFrame) +
                                                     " is outside [0, " + std::to_string(K - 1) +
                                                     "]"));
}

std::unique_ptr<FramePath> newStitchingPath(const std::string &kind) {
  return std::make_unique<StitchingPath>(kind);
}

std::unique_ptr<FramePath> newStitchingPath(const std::string &kind, int K,
                                            const std::vector<double> &recurrence,
                                            const PathParams &params) {
  return std::make_unique<StitchingPath>(kind, K, recurrence, params);
}

} // namespace rcfd
