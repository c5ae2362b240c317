#include "rcfd/granulation.hpp"
#include "rcfd/operator.hpp"
#include "rcfd/swaps.hpp"

namespace rcfd {

// The built-in names are identifiers and distinct: add() cannot fail here.
OperatorRegistry OperatorRegistry::withBuiltins() {
  OperatorRegistry r;
  const auto add = [&r](const char *name, OperatorFactory factory, const char *help) {
    PetscCallAbort(PETSC_COMM_SELF, r.add(name, std::move(factory), help));
  };
  const auto addWith = [&r](const char *name, Makers::Factory factory, const char *help) {
    PetscCallAbort(PETSC_COMM_SELF, r.makers.add(name, std::move(factory), help));
  };
  add("shift", [] { return std::make_unique<ShiftOperator>(); },
      "move all fractions with the frame's shift matrix (bulk convection)");
  addWith("drift", [](const OperatorRegistry &self) { return std::make_unique<DriftOperator>(self.sizeLaws()); },
          "fractional drift along gravity by face swaps (paper Eq. 4-6; -drift_size_law)");
  add("dispersion", [] { return std::make_unique<DispersionOperator>(); },
      "symmetric mixing of composition across all faces");
  addWith("carry", [](const OperatorRegistry &self) { return std::make_unique<CarryOperator>(self.carryKinds()); },
          "carries the state across a jump between frames (-carry_type)");
  add("growth", [] { return std::make_unique<GrowthOperator>(); },
      "granulation: mass moves to the next larger class in the spray zone (-growth_zone, -growth_rate)");
  add("feed", [] { return std::make_unique<FeedOperator>(); },
      "granulation: continuous feed into the feed zone (-feed_zone, -feed_rate)");
  add("discharge", [] { return std::make_unique<DischargeOperator>(); },
      "granulation: discharge at local concentrations from the discharge zone (-discharge_rate)");
  return r;
}

} // namespace rcfd
