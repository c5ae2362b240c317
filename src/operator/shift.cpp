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
  perFrame.clear();
  moving.reset();
  if (kernel == Kernel::Moving) {
    moving = std::make_unique<MovingRows>();
    PetscCall(moving->setUp(ctx.db, nf));
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
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(MatMult(perFrame[step.frame], state.masses(), state.scratch()));
  state.swap();
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
