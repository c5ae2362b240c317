// The face-swap operators: drift, dispersion and carry, all built on
// SwapOperator (rcfd/swap_operator.hpp) and FaceExchange (rcfd/face_exchange.hpp).
#pragma once

#include "rcfd/carry.hpp"
#include "rcfd/dispersion.hpp"
#include "rcfd/drift.hpp"
