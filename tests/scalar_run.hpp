// Test helper: a whole run with scalars from options, and what it ends with (masses, amounts,
// the sources' account), for the tests of the scalars' sources.
#pragma once

#include "base/petsc_compat.hpp"
#include "scoped_options.hpp"
#include "state_access.hpp"
#include "rcfd/run.hpp"

#include <string>
#include <vector>

namespace rcfd::test {

struct ScalarOutcome {
  std::vector<double> masses, amounts; // natural order
  std::vector<double> account;         // of the sources
  int nf = 0, ns = 0;
};

/// Collective on `comm`.  Runs `options` (with -output_dir `dir`), quiet and without fields.
inline PetscErrorCode runScalarCase(MPI_Comm comm, const std::string &options, const std::string &dir,
                                    ScalarOutcome *out) {
  PetscFunctionBeginUser;
  ScopedOptions scoped(options + " -output_dir " + dir);
  const OperatorRegistry registry = OperatorRegistry::withBuiltins();
  Run run(comm, registry);
  PetscCall(run.setFromOptions());
  run.setQuiet(true);
  run.setWriteFields(false);
  PetscCall(run.setUp());
  PetscCall(run.solve());
  out->nf = run.state().numFractions();
  out->ns = run.state().numScalars();
  out->masses = gatherNatural(run.database(), run.state().masses(), out->nf);
  out->amounts = gatherNatural(run.database(), run.state().amounts(), out->nf * out->ns);
  out->account = run.scalarSourceAccount();
  PetscFunctionReturn(PETSC_SUCCESS);
}

/// Scalar s's amount summed over the bed.
inline double scalarTotal(const ScalarOutcome &o, int s) {
  double sum = 0.0;
  const int w = o.nf * o.ns;
  for (std::size_t c = 0; c < o.masses.size() / o.nf; ++c)
    for (int i = 0; i < o.nf; ++i) sum += o.amounts[c * w + s * o.nf + i];
  return sum;
}

} // namespace rcfd::test
