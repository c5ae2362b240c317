// Frame paths: which database frame each time step of a run uses.
//
// A path is deterministic from its parameters, its seed and the normalised
// recurrence matrix, and uses only integer arithmetic and its own PRNG, so
// every MPI rank that builds the same path computes the same frames without
// communication.  (The recurrence matrix must then be bitwise identical on all
// ranks: reduce to one rank and broadcast it, see docs/paths.md.)
//
// A path is a sequence of *sequences* of consecutive frames s, s+1, ..., s+L-1.
// The step that starts a new sequence is a *jump*: the bed's alpha_s changes
// from (about) frame i+1 to frame s, and the caller must carry its state across.
// The first step of a path starts it and is not a jump.
#pragma once

#include "base/random.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace rcfd {

/// Parameters of the built-in path kinds.  Unset values take the kind's
/// default, which depends on the number of frames K (docs/paths.md).  Setting
/// a parameter that the kind does not use is an error, so that a misspelt
/// configuration does not pass silently.
struct PathParams {
  std::uint64_t seed = 1;
  int startFrame = 0; ///< frame of the first step
  /// Sequence length bounds.  random: L uniform in [minLength, maxLength]
  /// (defaults max(1, K/20), max(minLength, K/5)); quarter: L = minLength +
  /// floor(U (maxLength - minLength)) (defaults max(1, K/25), max(minLength, K/4));
  /// markov: minLength only, the steps before a jump may happen
  /// (minIntervalSteps, default max(1, K/20)).
  std::optional<int> minLength, maxLength;
  /// random and markov: a jump from frame i may only target frames j with
  /// |i - j| >= band (markov: correlationSteps).  Default max(1, K/10).
  std::optional<int> band;
  /// markov: once a sequence has minLength frames, each step ends it with
  /// probability 1 / (1 + meanIntervalSteps).  Default K/10.
  std::optional<double> meanIntervalSteps;
  /// Stitching kinds: the jump target is drawn uniformly among the
  /// `candidates` best allowed matches; 1 (default) takes the best match.
  int candidates = 1;
};

class FramePath {
public:
  virtual ~FramePath();
  FramePath(const FramePath &) = delete;
  FramePath &operator=(const FramePath &) = delete;

  /// Advances one step and returns its frame, in [0, numFrames()).
  int next();
  /// Frame of the last step, -1 before the first.
  int frame() const { return frame_; }
  /// True when the last step started a new sequence (not for the first step).
  bool lastWasJump() const { return jump_; }
  /// Number of steps taken.
  std::uint64_t steps() const { return steps_; }
  int numFrames() const { return K_; }

  virtual std::string kind() const = 0;
  /// One line: the kind and its resolved parameters (for logs and file headers).
  virtual std::string describe() const = 0;

  /// Hash of the kind, parameters, seed and jump table (derived from the
  /// recurrence matrix).  Ranks that built the same path agree on it: compare
  /// it across ranks (MPI_MIN and MPI_MAX) to catch a matrix that differs in
  /// its last bits from rank to rank.
  std::uint64_t configurationHash() const { return fingerprint(); }

  /// Everything needed to continue bit-identically: position, sequence
  /// bookkeeping, PRNG state, plus a fingerprint of the parameters and jump
  /// table.  restoreState() throws std::invalid_argument when the state is
  /// malformed or was saved by a path with other parameters or another
  /// recurrence matrix.
  std::vector<std::uint64_t> saveState() const;
  void restoreState(const std::vector<std::uint64_t> &state);

protected:
  explicit FramePath(int numFrames);
  /// The next frame; sets `jump` when it starts a new sequence.  frame() is
  /// still the previous frame (-1 on the first call).
  virtual int advance(bool &jump) = 0;
  /// Hash of everything that determines the continuation of a saved state.
  virtual std::uint64_t fingerprint() const = 0;
  virtual void saveExtra(std::vector<std::uint64_t> &out) const = 0;
  /// Restores what saveExtra() wrote; checks its size and values.
  virtual void restoreExtra(const std::uint64_t *data, std::size_t n) = 0;

private:
  int K_;
  int frame_ = -1;
  bool jump_ = false;
  std::uint64_t steps_ = 0;
};

/// "replay", "random", "markov", "quarter".
std::vector<std::string> framePathKinds();

/// Builds a path of a built-in kind for K frames.  `recurrence` is the
/// normalised recurrence matrix (K * K, row-major); "replay" ignores it and
/// accepts an empty vector.  Throws std::invalid_argument with a sentence for
/// an unknown kind or bad parameters (K < 2, minLength > maxLength, a band too
/// wide for K, ...).
std::unique_ptr<FramePath> makeFramePath(const std::string &kind, int K,
                                         const std::vector<double> &recurrence,
                                         const PathParams &params = {});

/// Replays an explicit list of frames, e.g. the path written by an earlier
/// run.  A step is a jump when its frame is not the previous frame + 1, which
/// reproduces the jumps of every built-in kind.  Asking for more steps than
/// the list holds throws std::out_of_range.
std::unique_ptr<FramePath> makeRecordedPath(int K, std::vector<int> frames);

/// Writes one frame index per line after a "# <header>" line.
/// Throws std::runtime_error when the file cannot be written.
void writePathFile(const std::string &filename, const std::vector<int> &frames,
                   const std::string &header);
/// Reads a file written by writePathFile(): lines starting with '#' and blank
/// lines are skipped.  Throws std::runtime_error naming the file and line on
/// anything that is not a non-negative integer.
std::vector<int> readPathFile(const std::string &filename);

} // namespace rcfd
