// Passes over a state's cells (nf masses each, cell-major) that sum each
// fraction as they go, cell by cell from the first: the order
// FractionState::localTotals adds in.  One kernel per number of fractions up
// to 8, so that the sums stay in registers instead of memory the masses might
// alias: the same operations in the same order, the same bits as a loop over
// nf, two to three times faster (the sums' dependency chains are the cost).
#pragma once

#include <petscsys.h>

namespace rcfd {

/// The number of fractions as a constant for the compiler; 0: known at run time only.
template <int N> struct Fractions {
  static constexpr int value = N;
};

/// Calls f(Fractions<nf>{}) for 1 <= nf <= 8, else f(Fractions<0>{}).
template <class F> void byFractions(int nf, F &&f) {
  switch (nf) {
  case 1: f(Fractions<1>{}); break;
  case 2: f(Fractions<2>{}); break;
  case 3: f(Fractions<3>{}); break;
  case 4: f(Fractions<4>{}); break;
  case 5: f(Fractions<5>{}); break;
  case 6: f(Fractions<6>{}); break;
  case 7: f(Fractions<7>{}); break;
  case 8: f(Fractions<8>{}); break;
  default: f(Fractions<0>{});
  }
}

/// Cells [from, to): m = m * first_i * factor_i (m * factor_i when first is
/// null), each result added to sums[i].
template <int N>
void scaleAndSumCells(int nf, PetscScalar *m, PetscInt from, PetscInt to, const double *first, const double *factor,
                      double *sums) {
  if constexpr (N == 0) {
    for (PetscInt c = from; c < to; ++c)
      for (int i = 0; i < nf; ++i)
        sums[i] += (m[c * nf + i] = first ? m[c * nf + i] * first[i] * factor[i] : m[c * nf + i] * factor[i]);
  } else {
    double s[N], f[N], g[N];
    for (int i = 0; i < N; ++i) s[i] = sums[i], f[i] = factor[i], g[i] = first ? first[i] : 1.0;
    if (first)
      for (PetscInt c = from; c < to; ++c)
        for (int i = 0; i < N; ++i) s[i] += (m[c * N + i] = m[c * N + i] * g[i] * f[i]);
    else
      for (PetscInt c = from; c < to; ++c)
        for (int i = 0; i < N; ++i) s[i] += (m[c * N + i] *= f[i]);
    for (int i = 0; i < N; ++i) sums[i] = s[i];
  }
}

/// Cells [from, to): m's masses added to sums[i].
template <int N> void sumCells(int nf, const PetscScalar *m, PetscInt from, PetscInt to, double *sums) {
  if constexpr (N == 0) {
    for (PetscInt c = from; c < to; ++c)
      for (int i = 0; i < nf; ++i) sums[i] += m[c * nf + i];
  } else {
    double s[N];
    for (int i = 0; i < N; ++i) s[i] = sums[i];
    for (PetscInt c = from; c < to; ++c)
      for (int i = 0; i < N; ++i) s[i] += m[c * N + i];
    for (int i = 0; i < N; ++i) sums[i] = s[i];
  }
}

} // namespace rcfd
