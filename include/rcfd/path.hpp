// Frame paths: which database frame each time step of a run uses.
//
// A path is a sequence of *sequences* of consecutive frames s, s+1, ..., s+L-1.
// The step that starts a new sequence is a *jump*: the bed's alpha_s changes
// from (about) frame i+1 to frame s, and the run's carry operator takes the
// state across.  The first step of a path starts it and is not a jump.
//
// Paths have an operator's life cycle (docs/extending.md): created by name
// from a PathRegistry (-path_type), setFromOptions (each kind reads its own
// -path_* options), setUp (once the database is loaded; re-entrant), then
// next() once per step, view (-path_view).  Built-in kinds: replay, random,
// markov, quarter, recorded (docs/paths.md).
//
// A path must be deterministic from its options and the database: every MPI
// rank builds its own copy and all must produce the same frames without
// communication.  A run is restarted bit-identically from saveState() /
// restoreState() (written into checkpoints), so a kind keeps everything that
// decides its continuation in the words of saveExtra().
//
// Adding a path rule: derive from FramePath (type, describe, advance, and for
// checkpoints fingerprint, saveExtra, restoreExtra), add a factory to a
// PathRegistry and hand it to Run; docs/examples/user-path-rule is such a
// project, built against the installed library by the test suite.
#pragma once

#include "rcfd/database.hpp"
#include "rcfd/registry.hpp"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace rcfd {

/// What a path may read while it is set up.
struct PathContext {
  const Database &db;
  bool quiet; ///< no messages on stdout
};

class FramePath {
public:
  virtual ~FramePath();
  FramePath(const FramePath &) = delete;
  FramePath &operator=(const FramePath &) = delete;

  /// Options of this path are read as -<prefix><name>; the default prefix is "path_".
  void setOptionsPrefix(const std::string &p) { prefix_ = p; }
  const std::string &optionsPrefix() const { return prefix_; }
  /// Reads the kind's own options (collective).  The base reads none.
  virtual PetscErrorCode setFromOptions(MPI_Comm comm);
  /// Prepares the path for the loaded database (collective).  The base
  /// records the number of frames (at least 2); a kind that overrides it
  /// calls FramePath::setUp first.  Re-entrant: a second call on the same
  /// database gives the same path.
  virtual PetscErrorCode setUp(const PathContext &ctx);
  /// Prints describe() (collective on the viewer).
  virtual PetscErrorCode view(PetscViewer viewer) const;

  /// Stochastic kinds draw from a seeded generator: an ensemble gives its
  /// members seeds s, s+1, ...  setSeed() applies before setUp().
  virtual bool hasSeed() const { return false; }
  virtual std::uint64_t seed() const { return 0; }
  virtual void setSeed(std::uint64_t) {}

  /// Advances one step and returns its frame, in [0, numFrames()).  A kind
  /// whose advance() gives a frame outside is a bug: the program stops with
  /// a message (as an assertion would).
  int next();
  /// Frame of the last step, -1 before the first.
  int frame() const { return frame_; }
  /// True when the last step started a new sequence (not for the first step).
  bool lastWasJump() const { return jump_; }
  /// Number of steps taken.
  std::uint64_t steps() const { return steps_; }
  int numFrames() const { return K_; }

  /// The registered name of the kind.
  virtual std::string type() const = 0;
  /// One line: the kind and its resolved parameters (for logs and file headers).
  virtual std::string describe() const = 0;

  /// Hash of the kind, parameters, seed and jump table.  Ranks that built the
  /// same path agree on it: compare it across ranks (MPI_MIN and MPI_MAX) to
  /// catch a recurrence matrix that differs in its last bits between ranks.
  std::uint64_t configurationHash() const { return fingerprint(); }

  /// Everything needed to continue bit-identically: position, sequence
  /// bookkeeping, PRNG state, plus a fingerprint of the parameters.
  /// restoreState() refuses (PETSC_ERR_ARG_WRONG, not collective) a state
  /// that is malformed or was saved by a path with other parameters or
  /// another database.
  std::vector<std::uint64_t> saveState() const;
  PetscErrorCode restoreState(const std::vector<std::uint64_t> &state);

protected:
  /// The number of frames is set by setUp().
  FramePath() = default;
  /// Not collective.  Sets the number of frames (setUp() sets the database's);
  /// fewer than 2 are refused (PETSC_ERR_ARG_OUTOFRANGE).
  PetscErrorCode setNumFrames(int numFrames);

  /// The next frame; sets `jump` when it starts a new sequence.  frame() is
  /// still the previous frame (-1 on the first call).
  virtual int advance(bool &jump) = 0;
  /// Hash of everything that determines the continuation of a saved state.
  virtual std::uint64_t fingerprint() const = 0;
  /// Appends the kind's own state words; restoreExtra() reads them back
  /// (not collective) and refuses a wrong size or value with
  /// PETSC_ERR_ARG_WRONG and one sentence; restoreState() returns its error.
  virtual void saveExtra(std::vector<std::uint64_t> &out) const = 0;
  virtual PetscErrorCode restoreExtra(const std::uint64_t *data, std::size_t n) = 0;

private:
  std::string prefix_ = "path_";
  int K_ = 0;
  int frame_ = -1;
  bool jump_ = false;
  std::uint64_t steps_ = 0;
};

using PathFactory = std::function<std::unique_ptr<FramePath>()>;

/// Name -> factory of path kinds (rcfd/registry.hpp).  One per program (no
/// global state); users add their own kinds and select them with -path_type.
class PathRegistry : public Registry<FramePath> {
public:
  PathRegistry() : Registry("-path_type", "path") {}
  /// replay, random, markov, quarter and recorded.
  static PathRegistry withBuiltins();
  /// Collective.  Reads -path_type (default replay), creates that kind and
  /// lets it read its own options.
  PetscErrorCode createFromOptions(MPI_Comm comm, std::unique_ptr<FramePath> *path) const;
};

} // namespace rcfd
