#include "rcfd/granulation.hpp"
#include "rcfd/operator.hpp"
#include "rcfd/swaps.hpp"

namespace rcfd {

OperatorRegistry OperatorRegistry::withBuiltins() {
  OperatorRegistry r;
  r.add("shift", [] { return std::make_unique<ShiftOperator>(); },
        "move all fractions with the frame's shift matrix (bulk convection)");
  r.makers.add("drift", [](const OperatorRegistry &self) { return std::make_unique<DriftOperator>(self.sizeLaws()); },
               "fractional drift along gravity by face swaps (paper Eq. 4-6; -drift_size_law)");
  r.add("dispersion", [] { return std::make_unique<DispersionOperator>(); },
        "symmetric mixing of composition across all faces");
  r.makers.add("carry",
               [](const OperatorRegistry &self) { return std::make_unique<CarryOperator>(self.carryKinds()); },
               "carries the state across a jump between frames (-carry_type)");
  r.add("growth", [] { return std::make_unique<GrowthOperator>(); },
        "granulation: mass moves to the next larger class in the spray zone (-growth_zone, -growth_rate)");
  r.add("feed", [] { return std::make_unique<FeedOperator>(); },
        "granulation: continuous feed into the feed zone (-feed_zone, -feed_rate)");
  r.add("discharge", [] { return std::make_unique<DischargeOperator>(); },
        "granulation: discharge at local concentrations from the discharge zone (-discharge_rate)");
  return r;
}

} // namespace rcfd
