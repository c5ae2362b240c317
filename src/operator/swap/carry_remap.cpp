// The `remap` carry kind (the default before `column`): composition kept, bulk from the next frame.
#include "operator/swap/carry_kinds.hpp"
#include "base/petsc_compat.hpp"

#include <vector>

namespace rcfd {
namespace {

class RemapCarry : public CarryKind {
public:
  std::string type() const override { return "remap"; }
  PetscErrorCode apply(const CarryContext &ctx, const StepInfo &step, FractionState &state) override;
  PetscErrorCode view(PetscViewer viewer) const override;

private:
  PetscErrorCode remap(const CarryContext &ctx, Vec targetAlpha, FractionState &state);
  long jumps = 0;
};

PetscErrorCode RemapCarry::apply(const CarryContext &ctx, const StepInfo &step, FractionState &state) {
  PetscFunctionBeginUser;
  if (step.jump) PetscCall(remap(ctx, ctx.db.alphaS(step.nextFrame), state));
  jumps += step.jump;
  PetscFunctionReturn(PETSC_SUCCESS);
}

// Composition remap.  Each cell's mass shares y_i = m_i / M are kept and
// scaled to the next frame's bulk M* = rho alpha* V; a cell without mass
// takes the mass-weighted composition of its face neighbours, or, with none,
// the bed's.  Factors s_i = (total of fraction i before) / (total after), the
// same in every cell, then conserve every fraction exactly; they differ from 1
// by the difference between the frames, so the bulk is matched up to that.
PetscErrorCode RemapCarry::remap(const CarryContext &ctx, Vec targetAlpha, FractionState &state) {
  PetscFunctionBeginUser;
  FaceExchange &x = ctx.exchange;
  const int nf = ctx.numFractions;
  const double rho = ctx.solidDensity;
  // Neighbour masses summed per owned cell: gather, add each face's other
  // side, and add the sums into a zeroed work state.
  FractionState neighbours;
  PetscCall(neighbours.create(ctx.db.layout(), nf));
  PetscCall(x.sweep(
      state.masses(),
      [&] {
        for (const SwapFace &f : x.faces()) {
          PetscScalar *sumLower = x.changeAt(f.lower), *sumUpper = x.changeAt(f.upper);
          const PetscScalar *mLower = x.massAt(f.lower), *mUpper = x.massAt(f.upper);
          for (int i = 0; i < nf; ++i) {
            sumLower[i] += mUpper[i];
            sumUpper[i] += mLower[i];
          }
        }
      },
      neighbours.masses()));

  std::vector<double> before;
  PetscCall(state.totals(&before));
  double bedTotal = 0.0;
  for (double b : before) bedTotal += b;
  PetscScalar *m;
  const PetscScalar *nb, *a;
  const auto &vol = ctx.db.localVolumes();
  PetscCall(VecGetArray(state.masses(), &m));
  PetscCall(VecGetArrayRead(neighbours.masses(), &nb));
  PetscCall(VecGetArrayRead(targetAlpha, &a));
  for (size_t c = 0; c < vol.size(); ++c) {
    PetscScalar *mc = m + c * nf;
    const PetscScalar *source = mc;
    double M = 0.0;
    for (int i = 0; i < nf; ++i) M += mc[i];
    if (!(M > 0.0)) { // empty cell: the neighbours' composition
      source = nb + c * nf;
      for (int i = 0; i < nf; ++i) M += source[i];
    }
    const double target = rho * a[c] * vol[c];
    for (int i = 0; i < nf; ++i)
      mc[i] = M > 0.0 ? target * source[i] / M : target * before[i] / bedTotal;
  }
  PetscCall(VecRestoreArrayRead(targetAlpha, &a));
  PetscCall(VecRestoreArrayRead(neighbours.masses(), &nb));
  PetscCall(VecRestoreArray(state.masses(), &m));
  std::vector<double> after;
  PetscCall(state.totals(&after));
  std::vector<double> factor(nf, 1.0);
  for (int i = 0; i < nf; ++i) factor[i] = after[i] > 0 ? before[i] / after[i] : 1.0;
  PetscInt n;
  PetscCall(VecGetLocalSize(state.masses(), &n));
  PetscCall(VecGetArray(state.masses(), &m));
  for (PetscInt k = 0; k < n; ++k) m[k] *= factor[k % nf];
  PetscCall(VecRestoreArray(state.masses(), &m));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode RemapCarry::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer, "carry: composition remap at %ld jumps\n", jumps));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

std::unique_ptr<CarryKind> makeRemapCarry() { return std::make_unique<RemapCarry>(); }

} // namespace rcfd
