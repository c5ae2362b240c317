#include "base/checked_options.hpp"

#include <cmath>
#include <cstdio>

namespace rcfd {

PetscErrorCode checkedReal(PetscOptionItems *PetscOptionsObject, const char *option, const char *text,
                           PetscReal *value, const ValueRange &range, PetscBool *set) {
  PetscBool given = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsReal(option, text, "", *value, value, &given));
  if (set) *set = given;
  if (!given) PetscFunctionReturn(PETSC_SUCCESS);
  const double v = *value;
  const bool inside = std::isfinite(v) && (range.lowIncluded ? v >= range.low : v > range.low) &&
                      (range.highIncluded ? v <= range.high : v < range.high);
  const char *prefix = PetscOptionsObject->prefix ? PetscOptionsObject->prefix : "";
  char shown[32]; // PETSc's own %g would print "-5." and "nan."
  std::snprintf(shown, sizeof shown, "%g", v);
  PetscCheck(inside, PetscOptionsObject->comm, PETSC_ERR_USER_INPUT, "-%s%s %s: expected %s", prefix, option + 1,
             shown, range.meaning);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode checkedInt(PetscOptionItems *PetscOptionsObject, const char *option, const char *text,
                          PetscInt *value, PetscInt low, PetscInt high, PetscBool *set) {
  PetscBool given = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsInt(option, text, "", *value, value, &given));
  if (set) *set = given;
  if (!given) PetscFunctionReturn(PETSC_SUCCESS);
  const char *prefix = PetscOptionsObject->prefix ? PetscOptionsObject->prefix : "";
  PetscCheck(*value >= low && *value <= high, PetscOptionsObject->comm, PETSC_ERR_USER_INPUT,
             "-%s%s %" PetscInt_FMT ": expected a whole number from %" PetscInt_FMT " to %" PetscInt_FMT, prefix,
             option + 1, *value, low, high);
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
