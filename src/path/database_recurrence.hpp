// The recurrence matrix of a loaded database: read from the file when it was
// stored there (rcfd recurrence), otherwise computed collectively.
#pragma once

#include "path/recurrence.hpp"
#include "rcfd/database.hpp"

#include <string>
#include <vector>

namespace rcfd {

/// Name of the dataset under /extra that holds the matrix of `norm`.
std::string recurrenceDatasetName(RecurrenceNorm norm);

/// Collective.  Each rank computes the partial matrix of its cells; rank 0
/// reduces, finishes and broadcasts, so that every rank holds bitwise the
/// same matrix (paths compare its entries).
PetscErrorCode computeRecurrence(const Database &db, RecurrenceNorm norm, std::vector<double> *R);

/// Collective.  The stored matrix if the file has one for `norm` and the
/// loaded frame window is the whole database, else computeRecurrence().
/// *stored tells which.
PetscErrorCode loadOrComputeRecurrence(const Database &db, RecurrenceNorm norm,
                                       std::vector<double> *R, bool *stored);

} // namespace rcfd
