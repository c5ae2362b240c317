// The recorded path: an explicit list of frames, e.g. the path.txt of an
// earlier run (-path_type recorded -path_file FILE).
#include "path/builtin_paths.hpp"
#include "base/petsc_compat.hpp"

#include "base/collective.hpp"
#include "path/hasher.hpp"

#include <stdexcept>

namespace rcfd {
namespace {

/// Replays an explicit list of frames.
class RecordedPath final : public FramePath {
public:
  RecordedPath() = default;
  RecordedPath(int K, std::vector<int> frames) : frames_(std::move(frames)) {
    requireFrames(K);
    PetscCallAbort(PETSC_COMM_SELF, setNumFrames(K));
    check();
  }
  std::string type() const override { return "recorded"; }
  std::string describe() const override {
    return "recorded: K=" + std::to_string(numFrames()) + " steps=" +
           std::to_string(frames_.size());
  }

  PetscErrorCode setFromOptions(MPI_Comm comm) override {
    char text[PETSC_MAX_PATH_LEN] = "";
    PetscBool set = PETSC_FALSE;
    PetscFunctionBeginUser;
    PetscOptionsBegin(comm, optionsPrefix().c_str(), "Frame path recorded: a list of frames", "rcfd");
    PetscCall(PetscOptionsString("-file", "Frames to replay, one per line (e.g. an earlier run's path.txt)",
                                 "", file_.c_str(), text, sizeof text, &set));
    PetscOptionsEnd();
    if (set) file_ = text;
    PetscCheck(!file_.empty() || helpRequested(), comm, PETSC_ERR_USER_INPUT,
               "-path_type recorded needs -%sfile FILE", optionsPrefix().c_str());
    PetscFunctionReturn(PETSC_SUCCESS);
  }

  PetscErrorCode setUp(const PathContext &ctx) override {
    PetscFunctionBeginUser;
    PetscCall(FramePath::setUp(ctx));
    PetscCall(collectively(
        ctx.db.layout().comm(),
        [&] {
          frames_ = readPathFile(file_);
          check();
        },
        PETSC_ERR_USER_INPUT));
    PetscFunctionReturn(PETSC_SUCCESS);
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
    h.add(type());
    for (int v : frames_) h.add(static_cast<std::uint64_t>(v));
    return h.value();
  }
  void saveExtra(std::vector<std::uint64_t> &) const override {}
  PetscErrorCode restoreExtra(const std::uint64_t *, std::size_t n) override {
    PetscFunctionBeginUser;
    PetscCheck(n == 0, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "restoreState: wrong size for a recorded path state");
    PetscFunctionReturn(PETSC_SUCCESS);
  }

private:
  static bool helpRequested() {
    PetscBool help = PETSC_FALSE;
    PetscOptionsHasName(nullptr, nullptr, "-help", &help);
    return help;
  }
  // The start of a message: the file the frames came from, if any.
  std::string where() const { return file_.empty() ? "recorded path" : "recorded path '" + file_ + "'"; }
  void check() const {
    const int K = numFrames();
    if (frames_.empty())
      throw std::invalid_argument(where() + ": the list of frames is empty");
    for (std::size_t s = 0; s < frames_.size(); ++s)
      if (frames_[s] < 0 || frames_[s] >= K)
        throw std::invalid_argument(where() + ": step " + std::to_string(s) + " uses frame " +
                                    std::to_string(frames_[s]) + ", outside the database's [0, " +
                                    std::to_string(K - 1) + "]");
  }

  std::string file_;
  std::vector<int> frames_;
};

} // namespace

std::unique_ptr<FramePath> newRecordedPath() { return std::make_unique<RecordedPath>(); }

std::unique_ptr<FramePath> makeRecordedPath(int K, std::vector<int> frames) {
  return std::make_unique<RecordedPath>(K, std::move(frames));
}

} // namespace rcfd
