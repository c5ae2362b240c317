#include "path/frame_path.hpp"

#include "base/atomic_file.hpp"
#include "base/input_file.hpp"
#include "base/petsc_compat.hpp"

#include "path/builtin_paths.hpp"

#include "base/collective.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rcfd {

// ---------------------------------------------------------------------------
// FramePath base

namespace {
constexpr std::uint64_t kStateMagic = 0x5243464450415448ULL; // "RCFDPATH"
constexpr std::uint64_t kStateVersion = 1;
constexpr std::size_t kStateHeader = 7;
} // namespace

FramePath::~FramePath() = default;

namespace {
// Why a path cannot have K frames; empty when it can.
std::string framesProblem(int K) {
  return K < 2 ? "a frame path needs at least 2 frames; the database has " + std::to_string(K) : std::string();
}
} // namespace

PetscErrorCode FramePath::setNumFrames(int numFrames) {
  PetscFunctionBeginUser;
  const std::string why = framesProblem(numFrames);
  PetscCheck(why.empty(), PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "%s", why.c_str());
  K_ = numFrames;
  PetscFunctionReturn(PETSC_SUCCESS);
}

void requireFrames(int numFrames) {
  const std::string why = framesProblem(numFrames);
  if (!why.empty()) throw std::invalid_argument(why);
}

PetscErrorCode FramePath::setFromOptions(MPI_Comm) { return PETSC_SUCCESS; }

PetscErrorCode FramePath::setUp(const PathContext &ctx) {
  PetscFunctionBeginUser;
  const std::string why = framesProblem(ctx.db.numFrames()); // the same on every rank
  PetscCheck(why.empty(), ctx.db.layout().comm(), PETSC_ERR_USER_INPUT, "%s", why.c_str());
  PetscCall(setNumFrames(ctx.db.numFrames()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FramePath::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer, "Path: %s\n", describe().c_str()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

int FramePath::next() {
  bool jump = false;
  const int f = advance(jump);
  if (f < 0 || f >= K_) { // a bug in a path kind, never a user error: stop, as an assertion would
    std::fprintf(stderr, "rcfd: bug: the %s path produced frame %d outside [0, %d]\n", type().c_str(), f, K_ - 1);
    std::abort();
  }
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

PetscErrorCode FramePath::restoreState(const std::vector<std::uint64_t> &s) {
  PetscFunctionBeginUser;
  PetscCheck(s.size() >= kStateHeader && s[0] == kStateMagic && s[1] == kStateVersion, PETSC_COMM_SELF,
             PETSC_ERR_ARG_WRONG, "restoreState: the data is not a saved frame path state");
  PetscCheck(s[2] == fingerprint() && s[3] == static_cast<std::uint64_t>(K_), PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG,
             "restoreState: the state was saved by a %s path with other parameters, another seed or another "
             "recurrence matrix, or by another kind of path",
             type().c_str());
  PetscCheck(s[5] <= static_cast<std::uint64_t>(K_) && s[6] <= 1 && (s[5] == 0) == (s[4] == 0), PETSC_COMM_SELF,
             PETSC_ERR_ARG_WRONG, "restoreState: the saved position is inconsistent");
  PetscCall(restoreExtra(s.data() + kStateHeader, s.size() - kStateHeader));
  steps_ = s[4];
  frame_ = static_cast<int>(s[5]) - 1;
  jump_ = s[6] != 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

void restorePathState(FramePath &path, const std::vector<std::uint64_t> &state) {
  throwOnError([&] { return path.restoreState(state); });
}

// ---------------------------------------------------------------------------
// Built-in kinds without options

std::string pathParameterError(const std::string &kind, const std::string &what) {
  return kind + " path: " + what;
}

std::vector<std::string> framePathKinds() { return {"replay", "random", "markov", "quarter"}; }

// The built-in names are identifiers and distinct: add() cannot fail here.
void addBuiltinPaths(PathRegistry &registry) {
  PetscCallAbort(PETSC_COMM_SELF, registry.add("replay", [] { return newReplayPath(); },
                                               "the recorded frames in order from -path_start, wrapping to frame 0"));
  for (const char *kind : {"random", "markov", "quarter"}) {
    const std::string name = kind;
    PetscCallAbort(PETSC_COMM_SELF,
                   registry.add(name, [name] { return newStitchingPath(name); },
                                name == "random"   ? "sequences of random length joined by jumps to matching frames"
                                : name == "markov" ? "sequences that end with a fixed probability per step"
                                                   : "sequences that jump between opposite quarters of the frames"));
  }
  PetscCallAbort(PETSC_COMM_SELF, registry.add("recorded", [] { return newRecordedPath(); },
                                               "the frames listed in -path_file (e.g. an earlier run's path.txt)"));
}

std::unique_ptr<FramePath> makeFramePath(const std::string &kind, int K,
                                         const std::vector<double> &R, const PathParams &p) {
  const auto kinds = framePathKinds();
  if (std::find(kinds.begin(), kinds.end(), kind) == kinds.end())
    throw std::invalid_argument("unknown frame path kind \"" + kind +
                                "\": expected replay, random, markov or quarter");
  checkPathStart(kind, K, p);
  if (kind != "replay") return newStitchingPath(kind, K, R, p);
  const auto unused = [&](bool set, const char *name) {
    if (set)
      throw std::invalid_argument(pathParameterError(kind, std::string("the parameter ") + name +
                                                               " does not apply to this kind"));
  };
  unused(p.minLength.has_value(), "minLength");
  unused(p.maxLength.has_value(), "maxLength");
  unused(p.band.has_value(), "band");
  unused(p.meanIntervalSteps.has_value(), "meanIntervalSteps");
  unused(p.candidates != 1, "candidates");
  unused(p.leastUsed, "leastUsed");
  return newReplayPath(K, p.startFrame);
}

// ---------------------------------------------------------------------------
// Path files

void writePathFile(const std::string &filename, const std::vector<int> &frames,
                   const std::string &header) {
  std::string h = header;
  std::replace(h.begin(), h.end(), '\n', ' '); // the header is one comment line
  std::string text = "# " + h + '\n';
  for (int f : frames) text += std::to_string(f) + '\n';
  writeTextAtomically(filename, text);
}

std::vector<int> readPathFile(const std::string &filename) {
  requireRegularFile(filename);
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
