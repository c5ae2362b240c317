// The replay path: the database's frames in their recorded order, from
// -path_start, wrapping from the last frame to frame 0 (a jump).
#include "path/builtin_paths.hpp"
#include "base/petsc_compat.hpp"

#include "base/collective.hpp"
#include "path/hasher.hpp"


namespace rcfd {
namespace {

/// frame(step) = (startFrame + step) mod K; wrapping from K-1 to 0 is a jump.
class ReplayPath final : public FramePath {
public:
  ReplayPath() = default;
  ReplayPath(int K, int start) : start_(start) {
    requireFrames(K);
    PetscCallAbort(PETSC_COMM_SELF, setNumFrames(K));
  }
  std::string type() const override { return "replay"; }
  std::string describe() const override {
    return "replay: K=" + std::to_string(numFrames()) + " start=" + std::to_string(start_);
  }

  PetscErrorCode setFromOptions(MPI_Comm comm) override {
    PetscInt start = start_;
    PetscFunctionBeginUser;
    PetscOptionsBegin(comm, optionsPrefix().c_str(), "Frame path replay: the recorded frames in order", "rcfd");
    PetscCall(PetscOptionsInt("-start", "Frame of the first step", "", start, &start, nullptr));
    PetscOptionsEnd();
    start_ = static_cast<int>(start);
    PetscFunctionReturn(PETSC_SUCCESS);
  }

  PetscErrorCode setUp(const PathContext &ctx) override {
    PetscFunctionBeginUser;
    PetscCall(FramePath::setUp(ctx));
    PetscCheck(start_ >= 0 && start_ < numFrames(), ctx.db.layout().comm(), PETSC_ERR_USER_INPUT,
               "-%sstart %d is outside the database's frames [0, %d]", optionsPrefix().c_str(),
               start_, numFrames() - 1);
    PetscFunctionReturn(PETSC_SUCCESS);
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
    h.add(type());
    h.add(static_cast<std::uint64_t>(start_));
    return h.value();
  }
  void saveExtra(std::vector<std::uint64_t> &) const override {}
  PetscErrorCode restoreExtra(const std::uint64_t *, std::size_t n) override {
    PetscFunctionBeginUser;
    PetscCheck(n == 0, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "restoreState: wrong size for a replay path state");
    PetscFunctionReturn(PETSC_SUCCESS);
  }

private:
  int start_ = 0;
};

} // namespace

std::unique_ptr<FramePath> newReplayPath() { return std::make_unique<ReplayPath>(); }
std::unique_ptr<FramePath> newReplayPath(int K, int start) {
  return std::make_unique<ReplayPath>(K, start);
}

} // namespace rcfd
