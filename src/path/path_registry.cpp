#include "rcfd/path.hpp"
#include "base/petsc_compat.hpp"

#include "base/collective.hpp"
#include "path/frame_path.hpp"

namespace rcfd {

PathRegistry PathRegistry::withBuiltins() {
  PathRegistry r;
  addBuiltinPaths(r);
  return r;
}

PetscErrorCode PathRegistry::createFromOptions(MPI_Comm comm, std::unique_ptr<FramePath> *path) const {
  char type[256] = "replay";
  const std::string help = "Frame path: " + listing();
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, nullptr, "Frame path", "rcfd");
  PetscCall(PetscOptionsString("-path_type", help.c_str(), "", type, type, sizeof type, nullptr));
  PetscOptionsEnd();
  PetscCall(agreeOnStatus(comm, create(type, path)));
  PetscCall((*path)->setFromOptions(comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
