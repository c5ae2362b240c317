// The bed's centre of gravity over the run, its mean and Delta z_CoG (paper Sec. 3.3).
#include "observable/answers.hpp"
#include "base/petsc_compat.hpp"

#include "observable/bed_dynamics.hpp"

#include <cstdio>
#include <numeric>

namespace rcfd {

PetscErrorCode BedDynamicsMonitor::setUp(const RunContext &run, const FractionState &, const std::string &dir) {
  PetscFunctionBeginUser;
  comm = run.db.layout().comm();
  nf = run.fractions.size();
  path = dir + "/bed_dynamics.csv";
  zBed.clear();
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BedDynamicsMonitor::sample(const MonitorContext &ctx) {
  PetscFunctionBeginUser;
  const std::vector<double> *perLayer;
  PetscCall(sampler->masses(ctx, &perLayer));
  // Every cell of a layer has the layer's height, so the layers' sums give z_CoG.
  double mass = 0.0, moment = 0.0;
  for (int l = 0; l < sampler->geometry().numLayers(); ++l)
    for (int i = 0; i < nf; ++i) {
      mass += (*perLayer)[static_cast<std::size_t>(l) * nf + i];
      moment += (*perLayer)[static_cast<std::size_t>(l) * nf + i] * sampler->geometry().height(l);
    }
  if (mass > 0.0) zBed.push_back(moment / mass);
  if (ctx.last && !quiet && !zBed.empty())
    PetscCall(PetscPrintf(comm, "  bed dynamics: mean z_CoG %.6g m, Delta z_CoG = mean |z_CoG - mean| %.4g m over %zu samples\n",
                          std::accumulate(zBed.begin(), zBed.end(), 0.0) / zBed.size(), bedDynamics(zBed),
                          zBed.size()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BedDynamicsMonitor::flush() {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank != 0 || zBed.empty()) PetscFunctionReturn(PETSC_SUCCESS);
  char text[256];
  std::snprintf(text, sizeof text, "samples,mean_z_cog_m,delta_z_cog_m\n%zu,%.10g,%.10g\n", zBed.size(),
                std::accumulate(zBed.begin(), zBed.end(), 0.0) / zBed.size(), bedDynamics(zBed));
  PetscCall(writeFileAtomically(path, text));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BedDynamicsMonitor::restoreState(const std::vector<double> &state) {
  zBed = state;
  return PETSC_SUCCESS;
}

} // namespace rcfd
