// Test helpers: a product made by name from a registry, aborting on an error
// (checks of the error itself call create() and look at the code).
#pragma once

#include "rcfd/operator.hpp"
#include "rcfd/registry.hpp"

#include <memory>
#include <string>

namespace {

inline std::unique_ptr<rcfd::Operator> created(const rcfd::OperatorRegistry &registry, const std::string &name) {
  std::unique_ptr<rcfd::Operator> out;
  PetscCallAbort(PETSC_COMM_WORLD, registry.create(name, &out));
  return out;
}

template <typename Product>
std::unique_ptr<Product> created(const rcfd::Registry<Product> &registry, const std::string &name) {
  std::unique_ptr<Product> out;
  PetscCallAbort(PETSC_COMM_WORLD, registry.create(name, &out));
  return out;
}

/// Registers or aborts.
template <typename Registry, typename Factory>
void registered(Registry &registry, const std::string &name, Factory factory, const std::string &help) {
  PetscCallAbort(PETSC_COMM_WORLD, registry.add(name, std::move(factory), help));
}

/// Replaces a registered name or aborts.
template <typename Registry, typename Factory>
void replaced(Registry &registry, const std::string &name, Factory factory, const std::string &help) {
  PetscCallAbort(PETSC_COMM_WORLD, registry.replace(name, std::move(factory), help));
}

} // namespace
