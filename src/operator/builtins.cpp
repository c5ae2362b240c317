#include "rcfd/operator.hpp"

namespace rcfd {

OperatorRegistry OperatorRegistry::withBuiltins() {
  OperatorRegistry r;
  r.add("shift", [] { return std::make_unique<ShiftOperator>(); },
        "move all fractions with the frame's shift matrix (bulk convection)");
  return r;
}

} // namespace rcfd
