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
  bool carriesScalars() const override { return true; }

private:
  PetscErrorCode remap(const CarryContext &ctx, Vec targetAlpha, FractionState &state);
  PetscErrorCode carryAmounts(MPI_Comm comm, const std::vector<double> &old, FractionState &state);
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
// With scalars (docs/scalars.md) the remap is read as a transport: of each
// fraction, the mass a cell loses takes the cell's value along into one pool
// per fraction over the bed, and the mass a cell gains comes from that pool
// with the pool's mean value.  A cell that loses keeps its value, one that
// gains takes a mass-weighted mean of its value and the pool's: no value
// leaves the range it had, a uniform one stays uniform, and every amount's
// total is kept (what the losers give, the gainers take).
PetscErrorCode RemapCarry::remap(const CarryContext &ctx, Vec targetAlpha, FractionState &state) {
  PetscFunctionBeginUser;
  FaceExchange &x = ctx.exchange;
  const int nf = ctx.numFractions;
  std::vector<double> old; // with scalars: the own cells' masses before
  if (state.numScalars() > 0) {
    const PetscScalar *m;
    PetscInt n;
    PetscCall(VecGetLocalSize(state.masses(), &n));
    PetscCall(VecGetArrayRead(state.masses(), &m));
    old.assign(m, m + n);
    PetscCall(VecRestoreArrayRead(state.masses(), &m));
  }
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
  if (state.numScalars() > 0) PetscCall(carryAmounts(ctx.db.layout().comm(), old, state));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The amounts with the masses' changes (the remap's comment): `old` the own
// cells' masses before, the state's masses after.  One pass gives the losers'
// amounts (value kept) and the pools, one reduction of (ns + 1) nf numbers, and
// a second pass gives the gainers theirs.
PetscErrorCode RemapCarry::carryAmounts(MPI_Comm comm, const std::vector<double> &old, FractionState &state) {
  PetscFunctionBeginUser;
  const int nf = state.numFractions(), na = nf * state.numScalars();
  const PetscScalar *m;
  PetscScalar *a;
  std::vector<double> pool(na + nf, 0.0); // the amounts lost [s][i], then the masses lost [i]
  double *lost = pool.data() + na;
  PetscCall(VecGetArrayRead(state.masses(), &m));
  PetscCall(VecGetArray(state.amounts(), &a));
  const std::size_t cells = old.size() / nf;
  for (std::size_t c = 0; c < cells; ++c)
    for (int i = 0; i < nf; ++i) {
      const double before = old[c * nf + i], after = m[c * nf + i];
      if (!(after < before)) continue;
      lost[i] += before - after;
      for (int k = i; k < na; k += nf) { // k = s nf + i
        PetscScalar &ak = a[c * na + k];
        const double kept = after > 0.0 ? ak * (after / before) : 0.0;
        pool[k] += ak - kept;
        ak = kept;
      }
    }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, pool.data(), na + nf, MPI_DOUBLE, MPI_SUM, comm));
  for (std::size_t c = 0; c < cells; ++c)
    for (int i = 0; i < nf; ++i) {
      const double gained = m[c * nf + i] - old[c * nf + i];
      if (!(gained > 0.0) || !(lost[i] > 0.0)) continue;
      for (int k = i; k < na; k += nf) a[c * na + k] += gained * (pool[k] / lost[i]);
    }
  PetscCall(VecRestoreArray(state.amounts(), &a));
  PetscCall(VecRestoreArrayRead(state.masses(), &m));
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
