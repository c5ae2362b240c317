// Recurrence matrix of a database: the distance between every pair of frames
// of the bulk solid volume fraction alpha_s, normalised to [0, 1].
//
// The computation is split so that it runs on distributed cells without this
// file knowing about MPI:
//   1. every rank calls recurrencePartial() on its own cells;
//   2. the caller reduces the K x K partials over ranks, with MPI_SUM, or with
//      MPI_MAX when recurrenceNeedsMaxReduction(norm) is true;
//   3. every rank calls recurrenceFinish() on the reduced matrix.
// All entries of a partial are >= 0, so a rank without cells contributes a
// matrix of zeros, which is neutral for both reductions.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace rcfd {

/// Distance between frames i and j, with V_c the cell volumes:
///   SqrDiff   sum_c V_c (a_i - a_j)^2
///   Euclidean sqrt(sum_c V_c (a_i - a_j)^2)
///   AbsDiff   sum_c V_c |a_i - a_j|
///   Max       max_c |a_i - a_j|          (volumes are not used)
enum class RecurrenceNorm { SqrDiff, Euclidean, AbsDiff, Max };

/// "sqrDiff", "euclidean", "absDiff", "max" (as in the options files).
const char *recurrenceNormName(RecurrenceNorm norm);
/// Inverse of recurrenceNormName(); throws std::invalid_argument on an unknown name.
RecurrenceNorm parseRecurrenceNorm(const std::string &name);

/// True when the partials of `norm` combine by maximum (MPI_MAX), false when
/// they combine by sum (MPI_SUM).
bool recurrenceNeedsMaxReduction(RecurrenceNorm norm);

/// Local partial matrix from this rank's nLocal cells.  frames[k] points to
/// the nLocal values of alpha_s of frame k; cellVolume to the nLocal cell
/// volumes (> 0; may be null for RecurrenceNorm::Max).  On return `partial`
/// holds K * K values, row-major, symmetric, with a zero diagonal.  For
/// Euclidean the partial is the sum of squares: the root is taken by
/// recurrenceFinish() after the reduction.  Not collective.
void recurrencePartial(RecurrenceNorm norm, const std::vector<const double *> &frames,
                       const double *cellVolume, std::size_t nLocal,
                       std::vector<double> &partial);

/// Turns a reduced K x K partial into the recurrence matrix, in place: root
/// for Euclidean, exact symmetry (the upper triangle wins), zero diagonal,
/// division by the largest entry.  A matrix of zeros (all frames identical)
/// stays zero.  Throws std::invalid_argument when the size is not K * K or an
/// entry is negative or not finite (a frame holding NaN or Inf).  Not collective.
void recurrenceFinish(RecurrenceNorm norm, int K, std::vector<double> &matrix);

/// Serial convenience: recurrencePartial() followed by recurrenceFinish().
std::vector<double> recurrenceMatrix(RecurrenceNorm norm,
                                     const std::vector<const double *> &frames,
                                     const double *cellVolume, std::size_t nLocal);

} // namespace rcfd
