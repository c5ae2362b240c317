// Helpers on the serial CSR shift matrices of include/rcfd/frames.hpp that
// builders share: the product, mismatch measures, and the balancing of a
// shift towards given row totals.  Private to the library; PETSc-free.
#pragma once

#include "rcfd/frames.hpp"

#include <vector>

namespace rcfd {

/// y = T x.
void multiply(const CsrMatrix &T, const std::vector<double> &x, std::vector<double> &y);

/// ||T m - target||_1 / ||m||_1.
double relativeMismatch(const CsrMatrix &T, const std::vector<double> &m,
                        const std::vector<double> &target);

/// ||T m - t'||_1 / ||m||_1 with t' the target rescaled to m's total (what
/// a column-stochastic T can reach).
double scaledMismatch(const CsrMatrix &T, const std::vector<double> &m,
                      const std::vector<double> &target);

/// Iterative proportional scaling of a column-stochastic T (in place) in
/// the form T = diag(r) T0 diag(c): each iteration scales rows and
/// renormalises columns to 1, so that T m approaches `target` (rescaled, per
/// group of rows that share source columns, to the total T keeps there).
/// Iterations are Sinkhorn sweeps (row factor target_j / (T m)_j) until a
/// sweep removes less than a tenth of the mismatch, then Newton steps on the
/// row log-factors (the long-range corrections that sweeps need thousands
/// of iterations for).  Stops when ||T m - target'||_1 / ||m||_1 <=
/// tolerance, after `maxIterations`, or when two Newton steps in a row remove
/// less than a tenth (the support cannot carry the target).  Returns the
/// number of iterations.  Columns of cells with m = 0 keep their sum of 1.
int scaleToTarget(CsrMatrix &T, const std::vector<double> &m, const std::vector<double> &target,
                  int maxIterations, double tolerance);

} // namespace rcfd
