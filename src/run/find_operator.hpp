// The first operator of a pipeline of a given class (the granulator's, whose
// rates a live run sets and a forecast holds), or null.
#pragma once

#include "rcfd/operator.hpp"

namespace rcfd {

template <typename T> T *findOperator(const Pipeline &ops) {
  for (const auto &op : ops.operators())
    if (auto *found = dynamic_cast<T *>(op.get())) return found;
  return nullptr;
}

} // namespace rcfd
