// A FractionSet from lists a test knows to be valid (FractionSet::create; a
// refusal is a bug in the test and aborts it).
#pragma once

#include "rcfd/fractions.hpp"

#include <utility>
#include <vector>

namespace rcfd::test {

inline FractionSet fractionSet(std::vector<double> diameters, std::vector<double> massShares) {
  FractionSet set;
  PetscCallAbort(PETSC_COMM_SELF, FractionSet::create(std::move(diameters), std::move(massShares), &set));
  return set;
}

} // namespace rcfd::test
