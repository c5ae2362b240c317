#include "rcfd/path.hpp"
#include "base/petsc_compat.hpp"

#include "base/collective.hpp"
#include "path/frame_path.hpp"

#include <stdexcept>

namespace rcfd {

PathRegistry PathRegistry::withBuiltins() {
  PathRegistry r;
  addBuiltinPaths(r);
  return r;
}

void PathRegistry::add(const std::string &name, PathFactory factory, const std::string &help) {
  entries[name] = Entry{std::move(factory), help};
}

std::unique_ptr<FramePath> PathRegistry::create(const std::string &name) const {
  const auto it = entries.find(name);
  if (it == entries.end()) {
    std::string known;
    for (const auto &e : entries) known += (known.empty() ? "" : ", ") + e.first;
    throw std::invalid_argument("-path_type " + name + " is not known; the known paths are " + known);
  }
  return it->second.factory();
}

std::string PathRegistry::listing() const {
  std::string out;
  for (const auto &e : entries) out += "  " + e.first + ": " + e.second.help + "\n";
  return out;
}

PetscErrorCode PathRegistry::createFromOptions(MPI_Comm comm, std::unique_ptr<FramePath> *path) const {
  char type[256] = "replay";
  std::string names;
  for (const auto &e : entries) names += (names.empty() ? "" : ", ") + e.first;
  const std::string help = "Frame path: " + names;
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, nullptr, "Frame path", "rcfd");
  PetscCall(PetscOptionsString("-path_type", help.c_str(), "", type, type, sizeof type, nullptr));
  PetscOptionsEnd();
  PetscCall(collectively(comm, [&] { *path = create(type); }, PETSC_ERR_USER_INPUT));
  PetscCall((*path)->setFromOptions(comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
