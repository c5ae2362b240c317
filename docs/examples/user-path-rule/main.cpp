// A researcher's own frame path rule, added to rcfd without touching the
// library: "stride" steps through the database s frames at a time, frames
// 0, s, 2s, ... modulo the number of frames K.  Every step that is not to the
// next frame is a jump (the run's carry operator takes the state across).  It
// is registered under the name "stride", selected with -path_type stride and
// reads its own option -path_stride s (the prefix of every path is "path_").
//
//   mpiexec -n 2 ./user_path_rule -db bed.h5 -t_end 0.1 -path_type stride -path_stride 3
#include <rcfd/operator.hpp>
#include <rcfd/path.hpp>
#include <rcfd/run.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace {

class Stride : public rcfd::FramePath {
public:
  std::string type() const override { return "stride"; }
  std::string describe() const override { return "stride " + std::to_string(stride); }

  PetscErrorCode setFromOptions(MPI_Comm comm) override {
    PetscFunctionBeginUser;
    PetscInt s = stride;
    PetscOptionsBegin(comm, optionsPrefix().c_str(), "Every s-th frame", "user");
    PetscCall(PetscOptionsInt("-stride", "Frames advanced per step", "", s, &s, nullptr));
    PetscOptionsEnd();
    PetscCheck(s >= 1, comm, PETSC_ERR_USER_INPUT, "-%sstride must be at least 1, got %d",
               optionsPrefix().c_str(), (int)s);
    stride = static_cast<int>(s);
    PetscFunctionReturn(0);
  }

protected:
  // frame() is still the previous frame here, -1 before the first step.
  int advance(bool &jump) override {
    const int next = frame() < 0 ? 0 : (frame() + stride) % numFrames();
    jump = frame() >= 0 && next != frame() + 1;
    return next;
  }
  // What decides the continuation of a saved state: the stride.  The base
  // saves the position; this rule keeps no state of its own.
  std::uint64_t fingerprint() const override { return static_cast<std::uint64_t>(stride); }
  void saveExtra(std::vector<std::uint64_t> &) const override {}
  PetscErrorCode restoreExtra(const std::uint64_t *, std::size_t n) override {
    PetscFunctionBeginUser;
    PetscCheck(n == 0, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "path stride: a saved state with words of its own");
    PetscFunctionReturn(0);
  }

private:
  int stride = 2;
};

PetscErrorCode runWithStride() {
  PetscFunctionBeginUser;
  const rcfd::OperatorRegistry operators = rcfd::OperatorRegistry::withBuiltins();
  rcfd::PathRegistry paths = rcfd::PathRegistry::withBuiltins();
  PetscCall(paths.add("stride", [] { return std::make_unique<Stride>(); },
                         "frames 0, s, 2s, ... modulo K, -path_stride s"));
  rcfd::Run run(PETSC_COMM_WORLD, operators, paths); // -path_type stride selects it
  PetscCall(run.setFromOptions());
  PetscCall(run.setUp());
  PetscCall(run.solve());
  PetscFunctionReturn(0);
}

} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, "A user path rule in an rcfd run"));
  PetscCall(runWithStride());
  PetscCall(PetscFinalize());
  return 0;
}
