#include "rcfd/dispersion.hpp"
#include "base/checked_options.hpp"
#include "base/petsc_compat.hpp"

#include <algorithm>
#include <cmath>

namespace rcfd {

DispersionOperator::DispersionOperator() = default;
DispersionOperator::~DispersionOperator() = default;

PetscErrorCode DispersionOperator::setFromOptions(MPI_Comm comm) {
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, prefix.c_str(), "Dispersion (symmetric face swaps)", "rcfd");
  PetscCall(checkedReal(PetscOptionsObject, "-coefficient",
                        "Dispersion coefficient D [m^2/s]", &coefficient, kNonNegative));
  PetscCall(checkedReal(PetscOptionsObject, "-alpha_min",
                        "Faces touching a cell below this alpha_s do not swap",
                        &alphaMin, {0.0, 1.0, true, false, "a solid fraction in [0, 1)"}));
  PetscOptionsEnd();
  PetscCheck(coefficient >= 0 && std::isfinite(coefficient), comm, PETSC_ERR_USER_INPUT,
             "-%scoefficient must be a non-negative number of m^2/s, got %g", prefix.c_str(),
             coefficient);
  PetscFunctionReturn(PETSC_SUCCESS);
}

bool DispersionOperator::needed(const RunContext &ctx) const {
  return ctx.fractions.size() > 1 && coefficient > 0.0;
}

// Each side of a face sends X = rho alpha_face D A dt / delta of its own
// mixture, alpha_face = min(alpha_lower, alpha_upper), so the net flux of a
// fraction is X (y_lower - y_upper): Fickian diffusion of composition with no
// bulk flux.  Sub-steps keep every cell's total outgoing share below 1/2.
PetscErrorCode DispersionOperator::apply(const StepInfo &step, FractionState &state) {
  PetscFunctionBeginUser;
  FaceExchange &x = exchange();
  double worst = 0.0;
  for (const SwapFace &f : x.faces())
    worst = std::max(worst, coefficient * f.area / (f.distance * std::min(f.volumeLower, f.volumeUpper)));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &worst, 1, MPI_DOUBLE, MPI_MAX, comm));
  const int n = std::max(1, static_cast<int>(std::ceil(worst * x.maxFacesPerCell() * step.dt / 0.5)));
  const double dt = step.dt / n;
  // The scalars' amounts: the X a side sends of its mixture takes X / M of each amount.
  FaceExchange *ax = state.numScalars() > 0 ? amountExchange() : nullptr;
  const int w = ns * nf;
  for (int s = 0; s < n; ++s) {
    if (ax) {
      PetscCall(ax->gatherBegin(state.amounts()));
      PetscCall(ax->gatherEnd());
    }
    PetscCall(x.sweep(state.masses(), [&] {
      for (const SwapFace &f : x.faces()) {
        const PetscScalar *mL = x.massAt(f.lower), *mU = x.massAt(f.upper);
        double ML = 0.0, MU = 0.0;
        for (int i = 0; i < nf; ++i) ML += mL[i], MU += mU[i];
        const double aL = ML / (rho * f.volumeLower), aU = MU / (rho * f.volumeUpper);
        if (!(aL >= alphaMin && aU >= alphaMin)) continue;
        const double X = rho * std::min(aL, aU) * coefficient * f.area * dt / f.distance;
        PetscScalar *dL = x.changeAt(f.lower), *dU = x.changeAt(f.upper);
        for (int i = 0; i < nf; ++i) {
          const double net = X * (mL[i] / ML - mU[i] / MU);
          dL[i] -= net;
          dU[i] += net;
        }
        if (ax) {
          const PetscScalar *sL = ax->massAt(f.lower), *sU = ax->massAt(f.upper);
          PetscScalar *eL = ax->changeAt(f.lower), *eU = ax->changeAt(f.upper);
          for (int k = 0; k < w; ++k) {
            const double net = X * (sL[k] / ML - sU[k] / MU);
            eL[k] -= net;
            eU[k] += net;
          }
        }
      }
    }));
    if (ax) {
      PetscCall(ax->endKernel());
      PetscCall(ax->addChanges(state.amounts()));
    }
  }
  countStep(n);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode DispersionOperator::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer, "dispersion: D = %g m^2/s; %ld sub-steps over %ld steps\n",
                                   coefficient, substepsTaken(), stepsTaken()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
