// A researcher's own switching rule, added to rcfd without touching the
// library: "alternate" moves on to the next database of the set (-db a.h5,b.h5)
// every n steps, in a ring.  It is registered under the name "alternate",
// selected with -db_switch_type alternate and reads its own option
// -db_switch_every n (the prefix of every switching rule is "db_switch_").
// It decides from the step number only, so it is the same on every rank.
//
//   mpiexec -n 2 ./user_switch_rule -db a.h5,b.h5 -t_end 0.2 -db_switch_type alternate -db_switch_every 10
#include <rcfd/operator.hpp>
#include <rcfd/run.hpp>
#include <rcfd/switching.hpp>

#include <memory>
#include <string>

namespace {

class Alternate : public rcfd::SwitchRule {
public:
  std::string type() const override { return "alternate"; }
  std::string describe() const override { return "alternate every " + std::to_string(every) + " steps"; }

  PetscErrorCode setFromOptions(MPI_Comm comm) override {
    PetscFunctionBeginUser;
    PetscInt n = every;
    PetscOptionsBegin(comm, optionsPrefix().c_str(), "Alternate between the databases", "user");
    PetscCall(PetscOptionsInt("-every", "Steps on each database", "", n, &n, nullptr));
    PetscOptionsEnd();
    PetscCheck(n >= 1, comm, PETSC_ERR_USER_INPUT, "-%severy must be at least 1 step, got %d",
               optionsPrefix().c_str(), (int)n);
    every = static_cast<long>(n);
    PetscFunctionReturn(0);
  }

  // After every step: the next database when the step count reaches a
  // multiple of n; the step number is the trigger written to switches.csv.
  rcfd::SwitchDecision decide(const rcfd::SwitchDecision &active, const rcfd::SwitchSignals &s) override {
    if (s.step % every != 0) return active;
    rcfd::SwitchDecision next;
    next.database = (active.database + 1) % numDatabases();
    next.trigger = static_cast<double>(s.step);
    return next;
  }

private:
  long every = 100;
};

PetscErrorCode runWithAlternate() {
  PetscFunctionBeginUser;
  const rcfd::OperatorRegistry operators = rcfd::OperatorRegistry::withBuiltins();
  rcfd::SwitchRuleRegistry rules = rcfd::SwitchRuleRegistry::withBuiltins();
  PetscCall(rules.add("alternate", [] { return std::make_unique<Alternate>(); },
                         "the next database every n steps, -db_switch_every n"));
  rcfd::Run run(PETSC_COMM_WORLD, operators);
  run.useSwitchRules(rules); // before setFromOptions; -db_switch_type alternate selects it
  PetscCall(run.setFromOptions());
  PetscCall(run.setUp());
  PetscCall(run.solve());
  PetscFunctionReturn(0);
}

} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, "A user switching rule in an rcfd run"));
  PetscCall(runWithAlternate());
  PetscCall(PetscFinalize());
  return 0;
}
