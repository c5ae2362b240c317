// Shift weights in reduced precision that still conserve mass exactly
// (docs/database-format.md, "Quantised weights").  Private to the library;
// serial and PETSc-free, on the CSR frames of the file format.
#pragma once

#include "rcfd/frames.hpp"

namespace rcfd {

/// Every column of T becomes integers n >= 0 over 2^bits that sum to exactly
/// 2^bits: each entry's share of its column times 2^bits, rounded down, and
/// the units still missing go to the entries with the largest remainders
/// (largest-remainder rounding; ties to the first entry).  Entries rounded to
/// 0 are dropped.  The weights n 2^-bits are exact in double and so are their
/// column sums, so the quantised shift is exactly column-stochastic in the
/// loader's arithmetic; each weight moves by less than 2^-bits.  Throws
/// std::invalid_argument for bits outside 1..16 or a column without weight.
void quantiseWeights(CsrMatrix *T, int bits);

} // namespace rcfd
