#include "rcfd/operator.hpp"
#include "base/petsc_compat.hpp"

#include "operator/moving_rows.hpp"

#include <algorithm>

namespace rcfd {

ShiftOperator::ShiftOperator() = default;
ShiftOperator::~ShiftOperator() = default;

PetscErrorCode ShiftOperator::setFromOptions(MPI_Comm comm) {
  const char *kernels[] = {"moving", "maij"};
  PetscInt which = static_cast<PetscInt>(kernel);
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, prefix.c_str(), "Shift (one database frame per step)", "rcfd");
  PetscCall(PetscOptionsEList("-kernel", "moving: only the rows of cells whose solid moves, in place; maij: whole-matrix MAIJ product",
                              "", kernels, 2, kernels[which], &which, nullptr));
  PetscOptionsEnd();
  kernel = static_cast<Kernel>(which);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ShiftOperator::setUp(const RunContext &ctx) {
  PetscFunctionBeginUser;
  PetscCheck(ctx.db.hasShifts(), ctx.db.layout().comm(), PETSC_ERR_ARG_WRONGSTATE,
             "The shift operator needs a database loaded with its shift matrices");
  nf = columns > 0 ? columns : ctx.fractions.size();
  // The scalar amounts (docs/scalars.md): the same matrix on their ns x nf
  // columns, a second pass over the frame (the masses' kernel is unchanged).
  const int amountColumns = columns > 0 ? 0 : ctx.numScalars * nf;
  PetscCheck(amountColumns <= kMaxFractions, ctx.db.layout().comm(), PETSC_ERR_USER_INPUT,
             "-scalars: %d scalars of %d fractions are %d columns per cell; rcfd carries at most %d",
             ctx.numScalars, nf, amountColumns, kMaxFractions);
  perFrame.clear();
  perFrameAmounts.clear();
  moving.reset();
  movingAmounts.reset();
  if (kernel == Kernel::Moving) {
    moving = std::make_unique<MovingRows>();
    PetscCall(moving->setUp(ctx.db, nf));
    if (amountColumns > 0) {
      movingAmounts = std::make_unique<MovingRows>();
      PetscCall(movingAmounts->setUp(ctx.db, amountColumns));
    }
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  for (int k = 0; k < ctx.db.numFrames(); ++k) {
    OwnedMat T, m;
    // MAIJ applies the cell-to-cell matrix to all nf interleaved fractions in
    // one pass over the matrix, 2-4x faster than nf separate products.  The
    // matrices are built here from the compact frames (and held by MAIJ).
    PetscCall(ctx.db.shiftMatrix(k, &T));
    PetscCall(MatCreateMAIJ(T, nf, m.put()));
    perFrame.push_back(std::move(m));
    if (amountColumns > 0) {
      OwnedMat a;
      PetscCall(MatCreateMAIJ(T, amountColumns, a.put()));
      perFrameAmounts.push_back(std::move(a));
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ShiftOperator::apply(const StepInfo &step, FractionState &state) {
  PetscFunctionBeginUser;
  if (moving) {
    PetscInt occupied;
    PetscCall(state.occupiedEnd(&occupied));
    PetscCall(moving->apply(step.frame, state.masses()));
    // Only the frame's moving rows were written: a cell that was empty and
    // is none of them is empty still.
    PetscCall(state.setOccupiedEnd(std::max(occupied, moving->writtenEnd(step.frame))));
    if (movingAmounts && state.numScalars() > 0) PetscCall(movingAmounts->apply(step.frame, state.amounts()));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(MatMult(perFrame[step.frame], state.masses(), state.scratch()));
  state.swap();
  if (!perFrameAmounts.empty() && state.numScalars() > 0) {
    PetscCall(MatMult(perFrameAmounts[step.frame], state.amounts(), state.amountsScratch()));
    state.swapAmounts();
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ShiftOperator::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  if (!moving) {
    PetscCall(PetscViewerASCIIPrintf(viewer, "shift: %zu frames, %d fractions per product (MAIJ)\n",
                                     perFrame.size(), nf));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(PetscViewerASCIIPrintf(viewer, "shift: moving rows only, %d fractions at once; on this rank %zu entries in all frames, compact frames %.1f MB (read in place) + %.2f MB of buffers, %" PetscInt_FMT " ghost cells\n",
                                   nf, moving->numEntries(), moving->frameBytes() / 1e6, moving->bufferBytes() / 1e6, moving->numGhosts()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
