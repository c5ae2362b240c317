// Numeric options checked for what they mean where they are read: a value
// that is not finite, or outside the range the quantity has, is refused with
// one sentence naming the option (with its prefix) instead of silently falling
// back to a default or running with nonsense.  Use inside a
// PetscOptionsBegin/End block, like PetscOptionsReal.
#pragma once

#include "base/petsc_compat.hpp"

#include <petscsys.h>

#include <string>
#include <vector>

namespace rcfd {

/// The values a quantity may take.
struct ValueRange {
  double low, high;
  bool lowIncluded, highIncluded;
  const char *meaning; ///< completes "expected ...", e.g. "a positive time in s"
};

inline constexpr ValueRange kPositive{0.0, PETSC_MAX_REAL, false, true, "a positive number"};
inline constexpr ValueRange kNonNegative{0.0, PETSC_MAX_REAL, true, true, "a number >= 0"};
inline constexpr ValueRange kOpenUnit{0.0, 1.0, false, false, "a number between 0 and 1 (exclusive)"};
inline constexpr ValueRange kUnitInterval{0.0, 1.0, false, true, "a number in (0, 1]"};
/// A time the Markov chain is followed for (docs/markov.md): an hour of bed
/// time is 720,000 steps of 5 ms, far beyond any zone's return time or a
/// bed's mixing; 1e9 s would be a computation that never ends.
inline constexpr ValueRange kChainTime{0.0, 3600.0, false, true, "a positive time of at most 3600 s"};

/// PetscOptionsReal plus the check: when the option is given, its value must be finite
/// and in `range`.  `PetscOptionsObject` is the block's (pass it by that name).
PetscErrorCode checkedReal(PetscOptionItems *PetscOptionsObject, const char *option, const char *text,
                           PetscReal *value, const ValueRange &range, PetscBool *set = nullptr);
/// The same for integers (range given as whole numbers).
PetscErrorCode checkedInt(PetscOptionItems *PetscOptionsObject, const char *option, const char *text,
                          PetscInt *value, PetscInt low, PetscInt high, PetscBool *set = nullptr);

/// PetscOptionsRealArray / IntArray that refuse too many values: PETSc stops
/// reading at the array's size and drops the rest silently (`-synth_cells
/// 10,2,20,7` would run with 10,2,20).  On input *n is the capacity of
/// `values`; on output, the number given.  Real values must be finite.
PetscErrorCode checkedRealArray(PetscOptionItems *PetscOptionsObject, const char *option, const char *text,
                                PetscReal *values, PetscInt *n, PetscBool *set);
PetscErrorCode checkedIntArray(PetscOptionItems *PetscOptionsObject, const char *option, const char *text,
                               PetscInt *values, PetscInt *n, PetscBool *set);
/// The same for strings: at most `capacity` of them, appended to `values`.
PetscErrorCode checkedStringArray(PetscOptionItems *PetscOptionsObject, const char *option, const char *text,
                                  PetscInt capacity, std::vector<std::string> *values, PetscBool *set);

} // namespace rcfd
