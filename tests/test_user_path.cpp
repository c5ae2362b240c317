// A path rule written by a user, registered by name and selected with
// -path_type, with its own option (-path_stride): the run steps exactly the
// frames it gives, the operators see them (and its jumps), path.txt records
// them, and its state survives saveState()/restoreState().  Runs at 1 and 2 ranks.
// usage: test_user_path OUTPUT_DIR -db SMALL.h5 -path_type stride -path_stride 3 [run options]
#include "check.hpp"
#include "registry_helpers.hpp"
#include "base/petsc_compat.hpp"
#include "rcfd/run.hpp"

#include <fstream>
#include <string>
#include <vector>

using namespace rcfd;

namespace {

/// Frames 0, stride, 2 stride, ... modulo the number of frames.
class StridePath : public FramePath {
public:
  std::string type() const override { return "stride"; }
  std::string describe() const override { return "stride: every " + std::to_string(stride) + " frames"; }
  PetscErrorCode setFromOptions(MPI_Comm comm) override {
    PetscFunctionBeginUser;
    PetscOptionsBegin(comm, optionsPrefix().c_str(), "Stride path", "test");
    PetscCall(PetscOptionsInt("-stride", "Frames between steps", "", stride, &stride, nullptr));
    PetscOptionsEnd();
    PetscFunctionReturn(PETSC_SUCCESS);
  }

protected:
  int advance(bool &jump) override {
    if (frame() < 0) return 0;
    jump = stride != 1;
    return static_cast<int>((frame() + stride) % numFrames());
  }
  std::uint64_t fingerprint() const override { return 1000 + static_cast<std::uint64_t>(stride); }
  void saveExtra(std::vector<std::uint64_t> &) const override {}
  PetscErrorCode restoreExtra(const std::uint64_t *, std::size_t) override { return PETSC_SUCCESS; }

private:
  PetscInt stride = 1;
};

} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  {
    PetscCheck(argc > 1, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT,
               "usage: test_user_path OUTPUT_DIR -db DATABASE -path_type stride -path_stride N");
    PetscMPIInt size;
    PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
    const std::string dir = std::string(argv[1]) + "-np" + std::to_string(size); // np 1 and 2 may run at once
    OperatorRegistry operators = OperatorRegistry::withBuiltins();
    std::vector<StepInfo> seen;
    registered(operators, "spy", [&seen] {
      return std::make_unique<ShellOperator>("spy", [&seen](const StepInfo &s, FractionState &) {
        seen.push_back(s);
        return PETSC_SUCCESS;
      });
    }, "records the steps");
    PathRegistry paths = PathRegistry::withBuiltins();
    registered(paths, "stride", [] { return std::make_unique<StridePath>(); }, "every N-th frame");
    Run run(PETSC_COMM_WORLD, operators, paths);
    PetscCall(run.setFromOptions());
    run.setQuiet(true);
    run.keepHistory(true); // history() and framesUsed() below
    run.setWriteFields(false);
    run.setOutputDirectory(dir);
    PetscCall(run.setUp());
    PetscCall(run.solve());

    const int K = run.database().numFrames();
    const long steps = run.numSteps();
    RCFD_CHECK(run.path().type() == "stride");
    std::vector<int> expected;
    for (long s = 0; s < steps; ++s) expected.push_back(static_cast<int>((3 * s) % K));
    RCFD_CHECK(run.framesUsed() == expected);
    RCFD_CHECK(seen.size() == static_cast<size_t>(steps));
    for (size_t s = 0; s < seen.size() && s + 1 < expected.size(); ++s) {
      RCFD_CHECK(seen[s].frame == expected[s]);
      RCFD_CHECK(seen[s].nextFrame == expected[s + 1]);
      RCFD_CHECK(seen[s].jump);
    }
    // path.txt: a header naming the rule, then the frames.
    std::ifstream in(dir + "/path.txt");
    std::string header;
    std::getline(in, header);
    RCFD_CHECK(header.find("stride: every 3 frames") != std::string::npos);
    std::vector<int> written;
    for (int f; in >> f;) written.push_back(f);
    RCFD_CHECK(written == expected);
    // A saved state continues where it was.
    StridePath a, b;
    PetscCall(a.setUp(PathContext{run.database(), true}));
    PetscCall(b.setUp(PathContext{run.database(), true}));
    for (int s = 0; s < 5; ++s) a.next();
    PetscCall(b.restoreState(a.saveState()));
    RCFD_CHECK(b.next() == a.next());
  }
  const int result = RCFD_TEST_RESULT();
  PetscCall(PetscFinalize());
  return result;
}
