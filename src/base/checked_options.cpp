#include "base/checked_options.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

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

namespace {

/// Reads one slot more than `*n` into a copy, so that a value too many is seen.
template <typename T, typename Read>
PetscErrorCode boundedArray(PetscOptionItems *PetscOptionsObject, const char *option, T *values, PetscInt *n,
                            PetscBool *set, Read read) {
  PetscBool given = PETSC_FALSE;
  PetscFunctionBeginUser;
  const PetscInt capacity = *n;
  std::vector<T> buffer(values, values + capacity);
  buffer.push_back(T{});
  PetscInt count = capacity + 1;
  PetscCall(read(buffer.data(), &count, &given));
  if (set) *set = given;
  if (!given) PetscFunctionReturn(PETSC_SUCCESS);
  const char *prefix = PetscOptionsObject->prefix ? PetscOptionsObject->prefix : "";
  PetscCheck(count <= capacity, PetscOptionsObject->comm, PETSC_ERR_USER_INPUT,
             "-%s%s takes at most %" PetscInt_FMT " comma-separated values", prefix, option + 1, capacity);
  std::copy(buffer.begin(), buffer.begin() + count, values);
  *n = count;
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

PetscErrorCode checkedRealArray(PetscOptionItems *PetscOptionsObject, const char *option, const char *text,
                                PetscReal *values, PetscInt *n, PetscBool *set) {
  PetscBool given = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(boundedArray(PetscOptionsObject, option, values, n, &given,
                         [&](PetscReal *v, PetscInt *m, PetscBool *s) {
                           return PetscOptionsRealArray(option, text, "", v, m, s);
                         }));
  if (set) *set = given;
  const char *prefix = PetscOptionsObject->prefix ? PetscOptionsObject->prefix : "";
  for (PetscInt i = 0; given && i < *n; ++i)
    PetscCheck(std::isfinite(values[i]), PetscOptionsObject->comm, PETSC_ERR_USER_INPUT,
               "-%s%s: value %" PetscInt_FMT " is not a finite number", prefix, option + 1, i + 1);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode checkedStringArray(PetscOptionItems *PetscOptionsObject, const char *option, const char *text,
                                  PetscInt capacity, std::vector<std::string> *values, PetscBool *set) {
  std::vector<char *> read(capacity + 1, nullptr);
  PetscInt count = capacity + 1;
  PetscBool given = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsStringArray(option, text, "", read.data(), &count, &given));
  if (set) *set = given;
  if (!given) PetscFunctionReturn(PETSC_SUCCESS);
  for (PetscInt i = 0; i < count; ++i) {
    if (i < capacity) values->emplace_back(read[i]);
    PetscCall(PetscFree(read[i]));
  }
  const char *prefix = PetscOptionsObject->prefix ? PetscOptionsObject->prefix : "";
  PetscCheck(count <= capacity, PetscOptionsObject->comm, PETSC_ERR_USER_INPUT,
             "-%s%s takes at most %" PetscInt_FMT " comma-separated values", prefix, option + 1, capacity);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode checkedIntArray(PetscOptionItems *PetscOptionsObject, const char *option, const char *text,
                               PetscInt *values, PetscInt *n, PetscBool *set) {
  PetscFunctionBeginUser;
  PetscCall(boundedArray(PetscOptionsObject, option, values, n, set,
                         [&](PetscInt *v, PetscInt *m, PetscBool *s) {
                           return PetscOptionsIntArray(option, text, "", v, m, s);
                         }));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
