// Symmetric dispersion of composition by face swaps.
#pragma once

#include "rcfd/swap_operator.hpp"

namespace rcfd {

/// Symmetric exchange of mixture across every internal face: each side sends
/// X = rho_s alpha_face D A dt / delta of its own composition, which
/// diffuses composition but not bulk mass.  Options (prefix dispersion_):
/// -dispersion_coefficient D [m^2/s], -dispersion_alpha_min,
/// -dispersion_view [viewer].
class DispersionOperator : public SwapOperator {
public:
  DispersionOperator();
  ~DispersionOperator() override;
  std::string type() const override { return "dispersion"; }
  PetscErrorCode setFromOptions(MPI_Comm comm) override;
  bool needed(const RunContext &ctx) const override;
  PetscErrorCode apply(const StepInfo &step, FractionState &state) override;
  PetscErrorCode view(PetscViewer viewer) const override;
  /// Each side sends its mixture with its values (docs/scalars.md).
  bool carriesScalars() const override { return true; }

private:
  double coefficient = 0.0, alphaMin = 1e-3;
};

} // namespace rcfd
