// Names newer PETSc releases define that rcfd uses with the PETSc 3.18 of
// Debian 12.  Private: a public header must not define PETSc's names, since
// from PETSc 3.19 on PETSC_SUCCESS is an enumerator and a macro would break
// every user's build.
#pragma once

#include <petscsys.h>

#if PETSC_VERSION_LT(3, 19, 0)
#define PETSC_SUCCESS 0
// Documented and exported by PETSc 3.18, but declared in none of its headers.
PETSC_EXTERN PetscErrorCode PetscObjectStateGet(PetscObject, PetscObjectState *);
#endif
