// Names -> factories, each with a line of help: the one registry behind every
// kind rcfd lets users choose by name -- operators (-pipeline), size laws
// (-drift_size_law), carry kinds (-carry_type), path rules (-path_type),
// switching rules (-db_switch_type) and monitors (-monitors).  Like PETSc's
// PetscFunctionList, but owned by an object instead of being global, so two
// programs in one process do not see each other's additions.
//
// Every function returns a PetscErrorCode and throws nothing: a factory that
// throws is caught here and becomes a PETSc error carrying its message.
#pragma once

#include <petscsys.h>
#include <petscviewer.h>

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace rcfd {

/// Whether `name` can be registered: a letter, then letters, digits or '_'
/// (it becomes part of option names such as -<name>_view).
inline bool isRegistrableName(const std::string &name) {
  if (name.empty() || !((name[0] >= 'a' && name[0] <= 'z') || (name[0] >= 'A' && name[0] <= 'Z'))) return false;
  for (char c : name)
    if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_')) return false;
  return true;
}

/// The registry of one extension point: `Product` is its base class (e.g.
/// Operator), `Args` what its factories take (usually nothing).
template <typename Product, typename... Args> class Registry {
public:
  using Factory = std::function<std::unique_ptr<Product>(Args...)>;

  /// `option` selects a product by name (for messages, e.g. "-pipeline");
  /// `what` names one product ("operator"), `plural` several ("operators").
  Registry(std::string option, std::string what, std::string plural = {})
      : option_(std::move(option)), what_(std::move(what)),
        plural_(plural.empty() ? what_ + "s" : std::move(plural)) {}

  /// Not collective.  Registers `name`; refuses, with one sentence, a name that
  /// is not an identifier (isRegistrableName), one already registered and an
  /// empty factory.
  PetscErrorCode add(const std::string &name, Factory factory, const std::string &help) {
    PetscFunctionBeginUser;
    PetscCheck(isRegistrableName(name), PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG,
               "Cannot register the %s '%s': a name is a letter followed by letters, digits or '_'", what_.c_str(),
               name.c_str());
    PetscCheck(!has(name), PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG,
               "Cannot register the %s '%s': the name is taken (known %s: %s)", what_.c_str(), name.c_str(),
               plural_.c_str(), listing().c_str());
    PetscCall(store(name, std::move(factory), help));
    PetscFunctionReturn(0);
  }
  /// Not collective.  Replaces the factory of a registered `name` on purpose
  /// (a test's reference implementation); refuses a name that is not registered.
  PetscErrorCode replace(const std::string &name, Factory factory, const std::string &help) {
    PetscFunctionBeginUser;
    PetscCheck(has(name), PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG,
               "Cannot replace the %s '%s': it is not registered (known %s: %s)", what_.c_str(), name.c_str(),
               plural_.c_str(), listing().c_str());
    PetscCall(store(name, std::move(factory), help));
    PetscFunctionReturn(0);
  }
  bool has(const std::string &name) const { return entries.count(name) > 0; }

  /// Not collective.  A new product of the kind registered as `name`;
  /// unknown names are refused with "<option>: unknown <what> '<name>';
  /// known <plural>: a, b".  The caller sets its options prefix.
  PetscErrorCode create(const std::string &name, std::unique_ptr<Product> *out, Args... args) const {
    PetscFunctionBeginUser;
    const auto it = entries.find(name);
    PetscCheck(it != entries.end(), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: unknown %s '%s'; known %s: %s",
               option_.c_str(), what_.c_str(), name.c_str(), plural_.c_str(), listing().c_str());
    PetscCallCXX(*out = it->second.factory(args...));
    PetscCheck(*out, PETSC_COMM_SELF, PETSC_ERR_PLIB, "The factory of the %s '%s' made nothing", what_.c_str(),
               name.c_str());
    PetscFunctionReturn(0);
  }

  /// The line of help given with `name` (empty if unknown).
  std::string help(const std::string &name) const {
    const auto it = entries.find(name);
    return it == entries.end() ? std::string() : it->second.help;
  }
  /// The names in alphabetical order.
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto &entry : entries) out.push_back(entry.first);
    return out;
  }
  /// The names, comma-separated, in alphabetical order.
  std::string listing() const {
    std::string out;
    for (const auto &entry : entries) out += (out.empty() ? "" : ", ") + entry.first;
    return out;
  }
  /// Collective on the viewer: "<plural> (<option>):" then "  name: help" per entry.
  PetscErrorCode view(PetscViewer viewer) const {
    PetscFunctionBeginUser;
    PetscCall(PetscViewerASCIIPrintf(viewer, "%s (%s):\n", plural_.c_str(), option_.c_str()));
    for (const auto &entry : entries)
      PetscCall(PetscViewerASCIIPrintf(viewer, "  %s: %s\n", entry.first.c_str(), entry.second.help.c_str()));
    PetscFunctionReturn(0);
  }
  const std::string &option() const { return option_; }
  const std::string &what() const { return what_; }

private:
  PetscErrorCode store(const std::string &name, Factory factory, const std::string &help) {
    PetscFunctionBeginUser;
    PetscCheck(static_cast<bool>(factory), PETSC_COMM_SELF, PETSC_ERR_ARG_NULL,
               "Cannot register the %s '%s' without a factory", what_.c_str(), name.c_str());
    PetscCallCXX(entries[name] = Entry{std::move(factory), help});
    PetscFunctionReturn(0);
  }
  struct Entry {
    Factory factory;
    std::string help;
  };
  std::string option_, what_, plural_;
  std::map<std::string, Entry> entries;
};

/// Collective.  Views `object` (anything with view(PetscViewer)) in the
/// viewer named by -<prefix>view, if given (plain: stdout; ascii:FILE).
template <typename Object>
PetscErrorCode viewFromOptions(MPI_Comm comm, const std::string &prefix, const Object &object) {
  PetscViewer viewer = nullptr;
  PetscViewerFormat format = PETSC_VIEWER_DEFAULT;
  PetscBool given = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetViewer(comm, nullptr, prefix.c_str(), "-view", &viewer, &format, &given));
  if (!given || !viewer) PetscFunctionReturn(0);
  PetscCall(PetscViewerPushFormat(viewer, format));
  const PetscErrorCode status = object.view(viewer);
  PetscCall(PetscViewerPopFormat(viewer));
  PetscCall(PetscViewerFlush(viewer));
  PetscCall(PetscViewerDestroy(&viewer));
  PetscCall(status);
  PetscFunctionReturn(0);
}

} // namespace rcfd
