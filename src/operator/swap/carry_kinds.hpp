// rcfd's built-in carry kinds (rcfd/carry.hpp describes them).
#pragma once

#include "rcfd/carry_kind.hpp"

#include <memory>

namespace rcfd {

std::unique_ptr<CarryKind> makeRemapCarry(); // carry_remap.cpp
std::unique_ptr<CarryKind> makeLevelCarry(); // carry_level.cpp
std::unique_ptr<CarryKind> makeColumnCarry(); // carry_column.cpp

} // namespace rcfd
