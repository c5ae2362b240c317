#include "path/frame_path.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rcfd {

// ---------------------------------------------------------------------------
// Fingerprints

namespace {

/// Order-dependent hash of 64-bit words (for fingerprints).
class Hasher {
public:
  void add(std::uint64_t v) {
    std::uint64_t x = h_ ^ v;
    h_ = splitmix64(x);
  }
  void add(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    add(bits);
  }
  void add(const std::string &s) {
    add(static_cast<std::uint64_t>(s.size()));
    for (unsigned char c : s) add(static_cast<std::uint64_t>(c));
  }
  std::uint64_t value() const { return h_; }

private:
  std::uint64_t h_ = 0x72636664ULL;
};

} // namespace

// ---------------------------------------------------------------------------
// FramePath base

namespace {
constexpr std::uint64_t kStateMagic = 0x5243464450415448ULL; // "RCFDPATH"
constexpr std::uint64_t kStateVersion = 1;
constexpr std::size_t kStateHeader = 7;
} // namespace

FramePath::FramePath(int numFrames) : K_(numFrames) {
  if (numFrames < 2)
    throw std::invalid_argument("a frame path needs at least 2 frames; the database has " +
                                std::to_string(numFrames));
}

FramePath::~FramePath() = default;

int FramePath::next() {
  bool jump = false;
  const int f = advance(jump);
  if (f < 0 || f >= K_) // a bug in a path kind, never a user error
    throw std::logic_error(kind() + " path produced frame " + std::to_string(f) + " outside [0, " +
                           std::to_string(K_ - 1) + "]");
  frame_ = f;
  jump_ = jump;
  ++steps_;
  return f;
}

std::vector<std::uint64_t> FramePath::saveState() const {
  std::vector<std::uint64_t> s{kStateMagic,
                               kStateVersion,
                               fingerprint(),
                               static_cast<std::uint64_t>(K_),
                               steps_,
                               static_cast<std::uint64_t>(frame_ + 1),
                               jump_ ? 1u : 0u};
  saveExtra(s);
  return s;
}

void FramePath::restoreState(const std::vector<std::uint64_t> &s) {
  if (s.size() < kStateHeader || s[0] != kStateMagic || s[1] != kStateVersion)
    throw std::invalid_argument("restoreState: the data is not a saved frame path state");
  if (s[2] != fingerprint() || s[3] != static_cast<std::uint64_t>(K_))
    throw std::invalid_argument("restoreState: the state was saved by a " + kind() +
                                " path with other parameters, another seed or another "
                                "recurrence matrix, or by another kind of path");
  if (s[5] > static_cast<std::uint64_t>(K_) || s[6] > 1 || (s[5] == 0) != (s[4] == 0))
    throw std::invalid_argument("restoreState: the saved position is inconsistent");
  restoreExtra(s.data() + kStateHeader, s.size() - kStateHeader);
  steps_ = s[4];
  frame_ = static_cast<int>(s[5]) - 1;
  jump_ = s[6] != 0;
}

// ---------------------------------------------------------------------------
// Kinds

namespace {

std::string paramError(const std::string &kind, const std::string &what) {
  return kind + " path: " + what;
}

/// frame(step) = (startFrame + step) mod K; wrapping from K-1 to 0 is a jump.
class ReplayPath final : public FramePath {
public:
  ReplayPath(int K, int start) : FramePath(K), start_(start) {}
  std::string kind() const override { return "replay"; }
  std::string describe() const override {
    return "replay: K=" + std::to_string(numFrames()) + " start=" + std::to_string(start_);
  }

protected:
  int advance(bool &jump) override {
    if (frame() < 0) return start_;
    const int f = frame() + 1;
    jump = f == numFrames();
    return jump ? 0 : f;
  }
  std::uint64_t fingerprint() const override {
    Hasher h;
    h.add(kind());
    h.add(static_cast<std::uint64_t>(start_));
    return h.value();
  }
  void saveExtra(std::vector<std::uint64_t> &) const override {}
  void restoreExtra(const std::uint64_t *, std::size_t n) override {
    if (n != 0) throw std::invalid_argument("restoreState: wrong size for a replay path state");
  }

private:
  int start_;
};

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
};

/// Sequences of consecutive frames; at the end of a sequence at frame i the
/// next one starts at J + 1, J drawn from the precomputed best matches of i.
/// Only the jump table is kept, not the K x K matrix.
class StitchingPath final : public FramePath {
public:
  StitchingPath(int K, StitchingConfig cfg, std::vector<int> table, std::vector<int> count)
      : FramePath(K), cfg_(std::move(cfg)), table_(std::move(table)), count_(std::move(count)),
        rng_(cfg_.seed) {
    jumpProbability_ = 1.0 / (1.0 + cfg_.meanInterval);
  }

  std::string kind() const override { return cfg_.kind; }
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
    return os.str();
  }

protected:
  int advance(bool &jump) override {
    if (frame() < 0) {
      beginSequence(cfg_.start);
      return cfg_.start;
    }
    const int i = frame();
    if (sequenceEnds(i)) {
      const int n = count_[i];
      const int pick = n > 1 ? static_cast<int>(rng_.below(static_cast<std::uint64_t>(n))) : 0;
      const int s = table_[static_cast<std::size_t>(i) * cfg_.candidates + pick] + 1;
      beginSequence(s);
      jump = true;
      return s;
    }
    // Within a sequence; sequenceEnds() guarantees i + 1 <= K - 1.
    ++used_;
    return i + 1;
  }

  std::uint64_t fingerprint() const override {
    Hasher h;
    h.add(cfg_.kind);
    h.add(static_cast<std::uint64_t>(cfg_.ending));
    h.add(cfg_.seed);
    for (int v : {cfg_.start, cfg_.minLength, cfg_.maxLength, cfg_.band, cfg_.candidates})
      h.add(static_cast<std::uint64_t>(v));
    h.add(cfg_.meanInterval);
    for (int v : table_) h.add(static_cast<std::uint64_t>(v));
    return h.value();
  }
  void saveExtra(std::vector<std::uint64_t> &out) const override {
    out.push_back(static_cast<std::uint64_t>(length_));
    out.push_back(static_cast<std::uint64_t>(used_));
    for (std::uint64_t w : rng_.state()) out.push_back(w);
  }
  void restoreExtra(const std::uint64_t *d, std::size_t n) override {
    const auto K = static_cast<std::uint64_t>(numFrames());
    if (n != 6 || d[0] > K || d[1] > K)
      throw std::invalid_argument("restoreState: wrong size or values for a " + cfg_.kind +
                                  " path state");
    rng_.setState({d[2], d[3], d[4], d[5]});
    length_ = static_cast<int>(d[0]);
    used_ = static_cast<int>(d[1]);
  }

private:
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

  StitchingConfig cfg_;
  std::vector<int> table_; // K x candidates best matches, best first
  std::vector<int> count_; // valid entries per row of table_
  Xoshiro256 rng_;
  double jumpProbability_ = 0.0;
  int length_ = 0; // planned length of the current sequence (not for markov)
  int used_ = 0;   // frames of the current sequence used so far
};

/// Replays an explicit list of frames.
class RecordedPath final : public FramePath {
public:
  RecordedPath(int K, std::vector<int> frames) : FramePath(K), frames_(std::move(frames)) {
    if (frames_.empty())
      throw std::invalid_argument("recorded path: the list of frames is empty");
    for (std::size_t s = 0; s < frames_.size(); ++s)
      if (frames_[s] < 0 || frames_[s] >= K)
        throw std::invalid_argument("recorded path: step " + std::to_string(s) + " uses frame " +
                                    std::to_string(frames_[s]) + ", outside the database's [0, " +
                                    std::to_string(K - 1) + "]");
  }
  std::string kind() const override { return "recorded"; }
  std::string describe() const override {
    return "recorded: K=" + std::to_string(numFrames()) + " steps=" +
           std::to_string(frames_.size());
  }

protected:
  int advance(bool &jump) override {
    const std::uint64_t s = steps();
    if (s >= frames_.size())
      throw std::out_of_range("recorded path: it holds " + std::to_string(frames_.size()) +
                              " steps and step " + std::to_string(s + 1) + " was asked for");
    const int f = frames_[s];
    jump = s > 0 && f != frame() + 1;
    return f;
  }
  std::uint64_t fingerprint() const override {
    Hasher h;
    h.add(kind());
    for (int v : frames_) h.add(static_cast<std::uint64_t>(v));
    return h.value();
  }
  void saveExtra(std::vector<std::uint64_t> &) const override {}
  void restoreExtra(const std::uint64_t *, std::size_t n) override {
    if (n != 0) throw std::invalid_argument("restoreState: wrong size for a recorded path state");
  }

private:
  std::vector<int> frames_;
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
      throw std::invalid_argument(paramError(kind, "frame " + std::to_string(i) + " of " +
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
    throw std::invalid_argument(paramError(
        kind, "the recurrence matrix holds " + std::to_string(R.size()) + " values but " +
                  std::to_string(K) + " frames need K * K = " + std::to_string(need)));
  for (std::size_t e = 0; e < need; ++e)
    if (!std::isfinite(R[e]))
      throw std::invalid_argument(paramError(
          kind, "recurrence matrix entry (" + std::to_string(e / K) + ", " +
                    std::to_string(e % K) + ") is not finite"));
}

} // namespace

std::vector<std::string> framePathKinds() { return {"replay", "random", "markov", "quarter"}; }

std::unique_ptr<FramePath> makeFramePath(const std::string &kind, int K,
                                         const std::vector<double> &R, const PathParams &p) {
  const auto kinds = framePathKinds();
  if (std::find(kinds.begin(), kinds.end(), kind) == kinds.end())
    throw std::invalid_argument("unknown frame path kind \"" + kind +
                                "\": expected replay, random, markov or quarter");
  if (K < 2)
    throw std::invalid_argument(paramError(kind, "a frame path needs at least 2 frames; the "
                                                 "database has " +
                                                     std::to_string(K)));
  if (p.startFrame < 0 || p.startFrame >= K)
    throw std::invalid_argument(paramError(kind, "startFrame " + std::to_string(p.startFrame) +
                                                     " is outside [0, " + std::to_string(K - 1) +
                                                     "]"));
  const auto unused = [&](bool set, const char *name) {
    if (set)
      throw std::invalid_argument(paramError(kind, std::string("the parameter ") + name +
                                                       " does not apply to this kind"));
  };
  const bool markov = kind == "markov", quarter = kind == "quarter";

  if (kind == "replay") {
    unused(p.minLength.has_value(), "minLength");
    unused(p.maxLength.has_value(), "maxLength");
    unused(p.band.has_value(), "band");
    unused(p.meanIntervalSteps.has_value(), "meanIntervalSteps");
    unused(p.candidates != 1, "candidates");
    return std::make_unique<ReplayPath>(K, p.startFrame);
  }

  checkRecurrence(K, R, kind);
  StitchingConfig c;
  c.kind = kind;
  c.seed = p.seed;
  c.start = p.startFrame;
  c.candidates = p.candidates;
  if (p.candidates < 1)
    throw std::invalid_argument(paramError(kind, "candidates must be at least 1, not " +
                                                     std::to_string(p.candidates)));
  if (markov) {
    unused(p.maxLength.has_value(), "maxLength");
    c.ending = Ending::Markov;
    c.minLength = p.minLength.value_or(std::max(1, K / 20));
    c.maxLength = K;
    c.meanInterval = p.meanIntervalSteps.value_or(K / 10);
    if (!std::isfinite(c.meanInterval) || c.meanInterval < 0.0)
      throw std::invalid_argument(
          paramError(kind, "meanIntervalSteps must be a finite number >= 0"));
  } else {
    unused(p.meanIntervalSteps.has_value(), "meanIntervalSteps");
    c.ending = quarter ? Ending::QuarterLength : Ending::UniformLength;
    c.minLength = p.minLength.value_or(std::max(1, quarter ? K / 25 : K / 20));
    c.maxLength = p.maxLength.value_or(std::max(c.minLength, quarter ? K / 4 : K / 5));
  }
  if (c.minLength < 1)
    throw std::invalid_argument(paramError(kind, "minLength must be at least 1, not " +
                                                     std::to_string(c.minLength)));
  if (c.minLength > K)
    throw std::invalid_argument(paramError(kind, "minLength " + std::to_string(c.minLength) +
                                                     " exceeds the " + std::to_string(K) +
                                                     " frames of the database"));
  if (c.minLength > c.maxLength)
    throw std::invalid_argument(paramError(kind, "minLength " + std::to_string(c.minLength) +
                                                     " is larger than maxLength " +
                                                     std::to_string(c.maxLength)));

  std::vector<int> table, count;
  if (quarter) {
    unused(p.band.has_value(), "band");
    // Quarter q holds the frames i with floor(4 i / K) = q; targets come from
    // quarter (q + 2) mod 4.
    const auto q = [K](int i) { return static_cast<int>(4LL * i / K); };
    buildJumpTable(
        K, R, c.candidates, [&](int i, int j) { return q(j) == (q(i) + 2) % 4; }, kind,
        "quarter jumps need at least 8 frames, so that the last quarter holds a frame with a "
        "successor",
        table, count);
  } else {
    c.band = p.band.value_or(std::max(1, K / 10));
    if (c.band < 1)
      throw std::invalid_argument(paramError(kind, "band must be at least 1, not " +
                                                       std::to_string(c.band)));
    // Targets j <= K-2 with |i - j| >= band exist for every i iff
    // band <= (K - 1) / 2 (the middle frame is the hardest).
    const int widest = (K - 1) / 2;
    if (c.band > widest)
      throw std::invalid_argument(paramError(
          kind, "band " + std::to_string(c.band) + " is too wide for " + std::to_string(K) +
                    " frames: some frame would have no jump target (the widest band is " +
                    std::to_string(widest) + ")"));
    const int band = c.band;
    buildJumpTable(
        K, R, c.candidates, [band](int i, int j) { return std::abs(i - j) >= band; }, kind,
        "lower the band", table, count);
  }
  return std::make_unique<StitchingPath>(K, std::move(c), std::move(table), std::move(count));
}

std::unique_ptr<FramePath> makeRecordedPath(int K, std::vector<int> frames) {
  return std::make_unique<RecordedPath>(K, std::move(frames));
}

// ---------------------------------------------------------------------------
// Path files

void writePathFile(const std::string &filename, const std::vector<int> &frames,
                   const std::string &header) {
  std::ofstream out(filename);
  if (!out) throw std::runtime_error("cannot open the path file " + filename + " for writing");
  std::string h = header;
  std::replace(h.begin(), h.end(), '\n', ' '); // the header is one comment line
  out << "# " << h << '\n';
  for (int f : frames) out << f << '\n';
  out.flush();
  if (!out) throw std::runtime_error("writing the path file " + filename + " failed");
}

std::vector<int> readPathFile(const std::string &filename) {
  std::ifstream in(filename);
  if (!in) throw std::runtime_error("cannot open the path file " + filename);
  std::vector<int> frames;
  std::string line;
  for (long lineNo = 1; std::getline(in, line); ++lineNo) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream is(line);
    long long v = -1;
    std::string rest;
    if (!(is >> v) || (is >> rest) || v < 0 || v > 2147483647LL)
      throw std::runtime_error(filename + ":" + std::to_string(lineNo) + ": expected one frame "
                               "index (a non-negative integer), found \"" + line + "\"");
    frames.push_back(static_cast<int>(v));
  }
  if (in.bad()) throw std::runtime_error("reading the path file " + filename + " failed");
  return frames;
}

} // namespace rcfd
