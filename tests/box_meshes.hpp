// A box Mesh a test knows to be valid (Mesh::createBox; a refusal is a bug in
// the test and aborts it).
#pragma once

#include "rcfd/mesh.hpp"

namespace rcfd::test {

inline Mesh boxMesh(const BoxSpec &spec) {
  Mesh mesh;
  PetscCallAbort(PETSC_COMM_SELF, Mesh::createBox(spec, &mesh));
  return mesh;
}

} // namespace rcfd::test
