#include "rcfd/carry.hpp"
#include "base/petsc_compat.hpp"

#include "operator/swap/carry_kinds.hpp"

namespace rcfd {

PetscErrorCode CarryKind::setFromOptions(MPI_Comm) { return PETSC_SUCCESS; }

CarryKindRegistry CarryKindRegistry::withBuiltins() {
  CarryKindRegistry r;
  // The built-in names are identifiers and distinct: add() cannot fail here.
  PetscCallAbort(PETSC_COMM_SELF, r.add("remap", makeRemapCarry, "each cell keeps its composition and takes the next frame's bulk"));
  PetscCallAbort(PETSC_COMM_SELF, r.add("column", makeColumnCarry,
        "monotone transport by height in every column, solid gained or lost across columns at their tops"));
  PetscCallAbort(PETSC_COMM_SELF, r.add("level", makeLevelCarry, "sweeps move mixture from over- to under-filled neighbours"));
  return r;
}

CarryOperator::CarryOperator() : CarryOperator(CarryKindRegistry::withBuiltins()) {}
CarryOperator::CarryOperator(CarryKindRegistry kinds) : known(std::move(kinds)) {
  // The default kind when known (a registry without it: setFromOptions refuses).
  if (known.has(name) && known.create(name, &kind) == PETSC_SUCCESS) kind->setOptionsPrefix(prefix);
}
CarryOperator::~CarryOperator() = default;

PetscErrorCode CarryOperator::setKind(MPI_Comm comm, const std::string &kindName) {
  PetscFunctionBeginUser;
  PetscCheck(known.has(kindName), comm, PETSC_ERR_USER_INPUT,
             "-%stype %s is not a known carry kind; known kinds: %s", prefix.c_str(),
             kindName.c_str(), known.listing().c_str()); // collective, unlike the registry's own check
  PetscCheck(!isSetUp(), comm, PETSC_ERR_ARG_WRONGSTATE,
             "The carry kind cannot change after set-up (asked for %s)", kindName.c_str());
  PetscCall(known.create(kindName, &kind));
  name = kindName;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode CarryOperator::setFromOptions(MPI_Comm comm) {
  char text[256];
  PetscBool set = PETSC_FALSE;
  PetscFunctionBeginUser;
  const std::string help = "How the state is carried across a jump: " + known.listing();
  PetscOptionsBegin(comm, prefix.c_str(), "Carrying the state across jumps between frames", "rcfd");
  PetscCall(PetscOptionsString("-type", help.c_str(), "", name.c_str(), text, sizeof text, &set));
  PetscOptionsEnd();
  if (set || !kind) PetscCall(setKind(comm, set ? std::string(text) : name));
  kind->setOptionsPrefix(prefix); // the kind's options are the operator's: -carry_<name>
  PetscCall(kind->setFromOptions(comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

bool CarryOperator::needed(const RunContext &) const { return kind && kind->needed(); }

PetscErrorCode CarryOperator::apply(const StepInfo &step, FractionState &state) {
  PetscFunctionBeginUser;
  const CarryContext ctx{database(), exchange(), rho, nf, amountExchange()};
  PetscCall(kind->apply(ctx, step, state));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode CarryOperator::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(kind->view(viewer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
