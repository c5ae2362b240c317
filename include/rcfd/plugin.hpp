// Plugins: shared libraries that add operators, size laws, carry kinds, path
// rules, switching rules and monitors to a program's registries without
// rebuilding it (docs/extending.md).  `rcfd run -plugin libmine.so` (several:
// comma-separated; or the environment variable RCFD_PLUGINS, colon-separated)
// opens each library on every rank and calls its registration function:
//
//   #include <rcfd/plugin.hpp>
//   RCFD_PLUGIN_VERSION_SYMBOL
//   extern "C" PetscErrorCode rcfd_plugin_register(rcfd::Registries *r) {
//     PetscFunctionBeginUser;
//     PetscCall(r->operators.add("mine", [] { return std::make_unique<Mine>(); }, "what it does"));
//     PetscFunctionReturn(0);
//   }
//
// then -pipeline shift,mine,carry selects the operator.  A library built
// against another version of rcfd is refused (its rcfd_plugin_version differs).
// The libraries stay loaded as long as the Registries that loaded them.
#pragma once

#include "rcfd/run.hpp"

#include <memory>
#include <string>
#include <vector>

/// The version of rcfd (the project's version; CMake checks that they agree).
#define RCFD_VERSION "0.3.0"

/// Defines the version a plugin was built against; put it once in a plugin.
#define RCFD_PLUGIN_VERSION_SYMBOL                                                                                    \
  extern "C" __attribute__((visibility("default"))) const char rcfd_plugin_version[] = RCFD_VERSION;

namespace rcfd {

/// Every registry of a program: the extension points of rcfd.
struct Registries {
  /// The libraries loaded into these registries; first, so that they are
  /// closed after the factories they hold are gone.
  std::vector<std::shared_ptr<void>> plugins;
  OperatorRegistry operators; ///< with its carry kinds and size laws
  PathRegistry paths;
  SwitchRuleRegistry switchRules;
  MonitorRegistry monitors;

  /// Registries holding rcfd's built-ins.
  static Registries withBuiltins();
  /// Collective on the viewer: every point with its names and help.
  PetscErrorCode view(PetscViewer viewer) const;
};

/// The function a plugin defines (extern "C").
using PluginRegisterFunction = PetscErrorCode (*)(Registries *);

/// Collective.  Opens the shared library `file` on every rank, checks that it
/// was built against this version of rcfd and calls its
/// rcfd_plugin_register(registries).  Refuses, with one sentence naming the
/// file, a library that cannot be opened, lacks either symbol, was built
/// against another version or whose registration fails.
PetscErrorCode loadPlugin(MPI_Comm comm, const std::string &file, Registries *registries);

/// Collective.  Loads the plugins of $RCFD_PLUGINS (colon-separated), then
/// those of -plugin (comma-separated), in order.
PetscErrorCode loadPlugins(MPI_Comm comm, Registries *registries);

} // namespace rcfd
