// How agitated the bed is, cell by cell and frame by frame, as the database
// records it: every shift T_k says how much of a cell's solid leaves it during
// dt_rec and how far it goes.  A drift law may scale with such a field (issue
// 12): segregation is driven by bubbling, and stops where the bed is still.
#pragma once

#include "rcfd/database.hpp"

#include <string>
#include <vector>

namespace rcfd {

enum class AgitationMeasure {
  /// a_i = 1 - T_k[i, i]: the share of cell i's solid that leaves it [-].
  LeavingShare,
  /// a_i = sum_j T_k[j, i] |x_j - x_i|^2 / dt_rec: a local dispersion rate [m^2/s].
  Dispersion,
};

/// Not collective.  The measure named "leaving" or "dispersion"; any other name
/// is refused (PETSC_ERR_ARG_OUTOFRANGE) with a sentence naming both.
PetscErrorCode parseAgitationMeasure(const std::string &name, AgitationMeasure *measure);
const char *agitationMeasureName(AgitationMeasure m);

/// Per-frame agitation of this rank's cells (PETSc order), computed once from the
/// shifts.  A cell without solid has a = 0 (its shift column is the identity).
class AgitationField {
public:
  /// Collective.  Needs a database loaded with its shifts.
  PetscErrorCode setUp(const Database &db, AgitationMeasure measure);
  /// Collective.  A field given per frame for this rank's cells (PETSc order;
  /// tests, or a measure computed elsewhere), normalised like setUp()'s.
  PetscErrorCode setValues(const Database &db, AgitationMeasure measure,
                           std::vector<std::vector<double>> perFrame);
  AgitationMeasure measure() const { return kind; }
  /// Database::identity() of the database the field was made for.
  const std::string &databaseIdentity() const { return madeFrom; }
  /// This rank's values of frame k.
  const std::vector<double> &frame(int k) const { return values[k]; }
  /// The solid-weighted mean over the occupied cells of all frames,
  /// sum_k,i alpha V a / sum_k,i alpha V: the field's normalisation (a bar).
  double solidWeightedMean() const { return mean; }
  /// The largest value over all cells and frames (for sub-step rules).
  double maximum() const { return largest; }

private:
  PetscErrorCode normalise(const Database &db); // mean and largest from values

  AgitationMeasure kind = AgitationMeasure::LeavingShare;
  std::string madeFrom;
  std::vector<std::vector<double>> values;
  double mean = 0.0, largest = 0.0;
};

} // namespace rcfd
