// Test helper: a whole run with scalars from options, and what it ends with (masses, amounts,
// the sources' account, in natural cell order), for the tests of the scalars; and their common checks.
#pragma once

#include "base/petsc_compat.hpp"
#include "check.hpp"
#include "scoped_options.hpp"
#include "state_access.hpp"
#include "rcfd/run.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace rcfd::test {

struct ScalarOutcome {
  std::vector<double> masses, amounts;            // natural order, at the end
  std::vector<double> account;                    // of the sources
  int nf = 0, ns = 0;
  std::vector<double> initialMass, initialAmount; // per fraction; per scalar and fraction
  int jumps = 0;                                  // steps whose next frame does not follow
  std::vector<std::string> labels;                // of the fractions
};

/// Collective on `comm`.  Runs `options` (with -output_dir `dir`) made with `registry`, quiet, its
/// history kept, field files only when `fields`.
inline PetscErrorCode runScalarCaseWith(MPI_Comm comm, const OperatorRegistry &registry, const std::string &options,
                                        const std::string &dir, ScalarOutcome *out, bool fields = false) {
  PetscFunctionBeginUser;
  ScopedOptions scoped(options + " -output_dir " + dir);
  Run run(comm, registry);
  PetscCall(run.setFromOptions());
  run.setQuiet(true);
  run.keepHistory(true);
  run.setWriteFields(fields);
  PetscCall(run.setUp());
  PetscCall(run.state().totals(&out->initialMass));
  PetscCall(run.state().amountTotals(&out->initialAmount));
  PetscCall(run.solve());
  out->nf = run.state().numFractions();
  out->ns = run.state().numScalars();
  out->masses = gatherNatural(run.database(), run.state().masses(), out->nf);
  out->amounts = gatherNatural(run.database(), run.state().amounts(), out->nf * out->ns);
  out->account = run.scalarSourceAccount();
  const std::vector<int> &frames = run.framesUsed();
  for (std::size_t k = 1; k < frames.size(); ++k) out->jumps += frames[k] != frames[k - 1] + 1;
  for (int i = 0; i < out->nf; ++i) out->labels.push_back(run.fractions().label(i));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/// The same with the built-in operators, without fields.
inline PetscErrorCode runScalarCase(MPI_Comm comm, const std::string &options, const std::string &dir,
                                    ScalarOutcome *out) {
  return runScalarCaseWith(comm, OperatorRegistry::withBuiltins(), options, dir, out);
}

/// Scalar s's amount summed over the bed.
inline double scalarTotal(const ScalarOutcome &o, int s) {
  double sum = 0.0;
  const int w = o.nf * o.ns;
  for (std::size_t c = 0; c < o.masses.size() / o.nf; ++c)
    for (int i = 0; i < o.nf; ++i) sum += o.amounts[c * w + s * o.nf + i];
  return sum;
}

/// The bytes of a file ("" when it cannot be read).
inline std::string fileBytes(const std::string &path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// The checks of a run of temperature (300 everywhere), moisture (0.1, 0.4 in a zone) and a tracer
/// decaying at `decay` [1/s], at its end time t: the temperature uniform in every cell and fraction
/// holding mass to 1e-12, every total kept (the tracer's times exp(-decay t)) to 1e-12, no negative
/// amount, and (`bounded`) the moisture within its initial values 0.1 and 0.4.
inline void checkScalarsCarried(const ScalarOutcome &o, double t, double decay, bool bounded,
                                const std::string &what) {
  const int nf = static_cast<int>(o.initialMass.size()), ns = 3, w = ns * nf;
  const std::size_t cells = o.masses.size() / nf;
  RCFD_CHECK(o.amounts.size() == cells * w);
  double worstUniform = 0.0, lowMoisture = 1e300, highMoisture = -1e300, lowest = 0.0;
  std::vector<double> total(w, 0.0);
  for (std::size_t c = 0; c < cells; ++c)
    for (int i = 0; i < nf; ++i) {
      const double m = o.masses[c * nf + i];
      for (int s = 0; s < ns; ++s) {
        const double a = o.amounts[c * w + s * nf + i];
        total[s * nf + i] += a;
        lowest = std::fmin(lowest, a);
      }
      if (!(m > 1e-12 * o.initialMass[i])) continue; // a trace: its value is round-off over round-off
      worstUniform = std::fmax(worstUniform, std::fabs(o.amounts[c * w + i] / m / 300.0 - 1.0));
      const double moisture = o.amounts[c * w + nf + i] / m;
      lowMoisture = std::fmin(lowMoisture, moisture);
      highMoisture = std::fmax(highMoisture, moisture);
    }
  if (!(worstUniform < 1e-12)) std::printf("%s: uniform temperature off by %.3g\n", what.c_str(), worstUniform);
  RCFD_CHECK_CLOSE(worstUniform, 0.0, 1e-12);
  RCFD_CHECK(lowest >= 0.0);
  RCFD_CHECK(highMoisture - lowMoisture > 0.01); // not mixed away: the bounds below are tested
  if (bounded) RCFD_CHECK(lowMoisture >= 0.1 * (1.0 - 1e-12) && highMoisture <= 0.4 * (1.0 + 1e-12));
  for (int i = 0; i < nf; ++i) {
    RCFD_CHECK_CLOSE(total[i] / o.initialAmount[i], 1.0, 1e-12);
    RCFD_CHECK_CLOSE(total[nf + i] / o.initialAmount[nf + i], 1.0, 1e-12);
    RCFD_CHECK_CLOSE(total[2 * nf + i] / (o.initialAmount[2 * nf + i] * std::exp(-decay * t)), 1.0, 1e-12);
  }
}

/// Largest relative difference between two runs' amounts, and their masses where `b` holds more than
/// a trace (1e-12 of a fraction's start: below, a value is round-off over round-off).
inline double largestDifference(const ScalarOutcome &a, const ScalarOutcome &b) {
  const int nf = static_cast<int>(b.initialMass.size());
  double worst = 0.0;
  for (std::size_t k = 0; k < b.amounts.size(); ++k)
    worst = std::fmax(worst, std::fabs(a.amounts[k] - b.amounts[k]) / std::fmax(1e-300, std::fabs(b.amounts[k])));
  for (std::size_t k = 0; k < b.masses.size(); ++k)
    if (b.masses[k] > 1e-12 * b.initialMass[k % nf])
      worst = std::fmax(worst, std::fabs(a.masses[k] / b.masses[k] - 1.0));
  return worst;
}

} // namespace rcfd::test
