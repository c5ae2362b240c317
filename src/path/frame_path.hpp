// The built-in frame path kinds without the options database: built from
// explicit parameters and a recurrence matrix (tests, tools), plus path files.
// The FramePath base and the registry are public: include/rcfd/path.hpp.
//
// The stitching kinds are deterministic from their parameters, their seed and
// the normalised recurrence matrix, and use only integer arithmetic and their
// own PRNG, so every MPI rank that builds the same path computes the same
// frames without communication.  (The recurrence matrix must then be bitwise
// identical on all ranks: reduce to one rank and broadcast it, see docs/paths.md.)
#pragma once

#include "rcfd/path.hpp"

#include "base/random.hpp"

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
  /// Stitching kinds: jump to the least-used of the candidate targets J, by
  /// the steps the path has spent so far in the frames J+1 ... J+minLength
  /// that its next sequence starts with (ties drawn at random), so that frames
  /// are used about equally often (issue 15).  false (default): uniform draw.
  bool leastUsed = false;
  /// random and markov: follow the run's clock.  A jump at step n may only
  /// target frames J + 1 within clockWindow frames of c = min(startFrame + n,
  /// K - 1), the frame a replay would use (past the database's end, its last
  /// frame).  For databases that record a transient (a bed that bubbles hard,
  /// then settles): without it a stitched path draws the late bed early and
  /// the early bed late (docs/paths.md).  band then defaults to
  /// max(1, clockWindow / 6) and must not exceed clockWindow.  Unset: off.
  std::optional<int> clockWindow;
};

/// FramePath::restoreState() that throws std::invalid_argument instead of
/// returning an error (for code that already turns exceptions into errors).
void restorePathState(FramePath &path, const std::vector<std::uint64_t> &state);

/// Throws std::invalid_argument, with FramePath::setNumFrames()'s sentence,
/// for fewer than 2 frames (for the built-in kinds, made where errors are
/// exceptions, before they call setNumFrames()).
void requireFrames(int numFrames);

/// Adds replay, random, markov, quarter and recorded to a registry.
void addBuiltinPaths(PathRegistry &registry);

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
