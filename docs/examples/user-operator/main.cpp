// A researcher's own operator, added to rcfd without touching the library:
// a uniform first-order decay of every fraction's mass, dm/dt = -k m (think
// of attrition fines leaving the bed).  It is registered under the name
// "decay", selected with -pipeline shift,decay and reads its own option
// -decay_rate k [1/s].  Over a step of dt_rec it multiplies every mass by
// exp(-k dt_rec), so after time t the bed holds exactly exp(-k t) of each
// fraction's initial mass -- which is what the test of this example checks
// in cog.csv.
//
//   mpiexec -n 2 ./user_operator -db bed.h5 -t_end 1 -pipeline shift,decay -decay_rate 0.5
#include <rcfd/operator.hpp>
#include <rcfd/run.hpp>

#include <cmath>
#include <memory>

namespace {

class Decay : public rcfd::Operator {
public:
  std::string type() const override { return "decay"; }

  // The prefix is "decay_" (the registered name), so the option is -decay_rate.
  PetscErrorCode setFromOptions(MPI_Comm comm) override {
    PetscFunctionBeginUser;
    PetscOptionsBegin(comm, optionsPrefix().c_str(), "Uniform decay of every fraction", "user");
    PetscCall(PetscOptionsReal("-rate", "Decay rate k [1/s]", "", rate, &rate, nullptr));
    PetscOptionsEnd();
    PetscCheck(rate >= 0, comm, PETSC_ERR_USER_INPUT,
               "-%srate must be a non-negative rate in 1/s, got %g", optionsPrefix().c_str(),
               (double)rate);
    PetscFunctionReturn(0);
  }

  // Nothing to do for k = 0: the pipeline then leaves the operator out.
  bool needed(const rcfd::RunContext &) const override { return rate > 0; }

  PetscErrorCode setUp(const rcfd::RunContext &) override { return 0; }

  PetscErrorCode apply(const rcfd::StepInfo &step, rcfd::FractionState &state) override {
    PetscFunctionBeginUser;
    PetscCall(VecScale(state.masses(), std::exp(-rate * step.dt)));
    PetscFunctionReturn(0);
  }

  PetscErrorCode view(PetscViewer viewer) const override {
    PetscFunctionBeginUser;
    PetscCall(PetscViewerASCIIPrintf(viewer, "decay: rate %g 1/s\n", (double)rate));
    PetscFunctionReturn(0);
  }

  // Mass leaves the bed on purpose: the run's mass ledger must not treat
  // that as a leak.
  bool conservesMass() const override { return false; }

private:
  PetscReal rate = 0.0;
};

PetscErrorCode runWithDecay() {
  PetscFunctionBeginUser;
  rcfd::OperatorRegistry registry = rcfd::OperatorRegistry::withBuiltins();
  PetscCall(registry.add("decay", [] { return std::make_unique<Decay>(); },
                            "uniform decay of every fraction, -decay_rate k [1/s]"));
  rcfd::Run run(PETSC_COMM_WORLD, registry); // -pipeline shift,decay selects it
  PetscCall(run.setFromOptions());
  PetscCall(run.setUp());
  PetscCall(run.solve());
  PetscFunctionReturn(0);
}

} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, "A user operator in an rcfd run"));
  PetscCall(runWithDecay());
  PetscCall(PetscFinalize());
  return 0;
}
