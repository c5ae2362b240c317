// The registries of a program and the plugins that add to them (include/rcfd/plugin.hpp).
#include "rcfd/plugin.hpp"
#include "base/petsc_compat.hpp"

#include "base/collective.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <cstring>

namespace rcfd {
namespace {

std::vector<std::string> split(const std::string &text, char separator) {
  std::vector<std::string> out;
  std::string item;
  for (char c : text + separator) {
    if (c != separator) {
      item += c;
      continue;
    }
    if (!item.empty()) out.push_back(item);
    item.clear();
  }
  return out;
}

// Opens the library and finds its two symbols; "" on success, else why not.
std::string openPlugin(const std::string &file, std::shared_ptr<void> *handle, PluginRegisterFunction *reg) {
  void *h = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!h) {
    const char *why = dlerror();
    return "-plugin " + file + " cannot be opened: " + (why ? why : "unknown reason");
  }
  *handle = std::shared_ptr<void>(h, [](void *p) { dlclose(p); });
  const auto *version = static_cast<const char *>(dlsym(h, "rcfd_plugin_version"));
  if (!version)
    return "-plugin " + file + " defines no rcfd_plugin_version: build it with RCFD_PLUGIN_VERSION_SYMBOL of "
           "rcfd/plugin.hpp";
  if (std::strcmp(version, RCFD_VERSION) != 0)
    return "-plugin " + file + " was built against rcfd " + version + ", not this rcfd " + RCFD_VERSION +
           "; rebuild it against this version";
  void *function = dlsym(h, "rcfd_plugin_register");
  if (!function) return "-plugin " + file + " defines no extern \"C\" rcfd_plugin_register(rcfd::Registries *)";
  *reg = reinterpret_cast<PluginRegisterFunction>(function);
  return "";
}

} // namespace

Registries Registries::withBuiltins() {
  Registries r;
  r.operators = OperatorRegistry::withBuiltins();
  r.paths = PathRegistry::withBuiltins();
  r.switchRules = SwitchRuleRegistry::withBuiltins();
  r.monitors = MonitorRegistry::withBuiltins();
  return r;
}

PetscErrorCode Registries::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(operators.view(viewer));
  PetscCall(paths.view(viewer));
  PetscCall(switchRules.view(viewer));
  PetscCall(monitors.view(viewer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode loadPlugin(MPI_Comm comm, const std::string &file, Registries *registries) {
  std::shared_ptr<void> handle;
  PluginRegisterFunction reg = nullptr;
  PetscFunctionBeginUser;
  const std::string why = openPlugin(file, &handle, &reg);
  PetscCall(agreeOnFailure(comm, !why.empty(), why, PETSC_ERR_USER_INPUT));
  registries->plugins.push_back(handle);
  PetscErrorCode status = PETSC_SUCCESS;
  try {
    status = reg(registries);
  } catch (const std::exception &e) { // a plugin's exception stops here
    status = PETSC_ERR_LIB;
    (void)PetscError(PETSC_COMM_SELF, __LINE__, PETSC_FUNCTION_NAME, __FILE__, status, PETSC_ERROR_INITIAL, "%s",
                     e.what());
  }
  std::string text;
  if (status) {
    const char *generic = nullptr;
    char *specific = nullptr;
    PetscErrorMessage(status, &generic, &specific);
    text = "-plugin " + file + ": its registration failed: " +
           (specific && *specific ? specific : (generic ? generic : "unknown error"));
  }
  PetscCall(agreeOnFailure(comm, status != PETSC_SUCCESS, text, PETSC_ERR_USER_INPUT));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode loadPlugins(MPI_Comm comm, Registries *registries) {
  char text[PETSC_MAX_PATH_LEN] = "";
  PetscBool given = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, nullptr, "Plugins (docs/extending.md)", "rcfd");
  PetscCall(PetscOptionsString("-plugin",
                               "Shared libraries, comma-separated, that add operators, laws, paths, rules or "
                               "monitors (also $RCFD_PLUGINS, colon-separated)",
                               "", text, text, sizeof text, &given));
  PetscOptionsEnd();
  const char *environment = std::getenv("RCFD_PLUGINS");
  std::vector<std::string> files = split(environment ? environment : "", ':');
  if (given)
    for (const auto &file : split(text, ',')) files.push_back(file);
  for (const auto &file : files) PetscCall(loadPlugin(comm, file, registries));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
