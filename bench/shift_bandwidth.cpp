// Achieved memory bandwidth of the shift step (cycling over the frames of a
// database held in memory) next to a STREAM-like triad measured in the same
// run on the same ranks.  KERNEL is the shift operator's -shift_kernel:
// moving (default) or maij.
// usage: mpiexec -n P shift_bandwidth DB.h5 NF [STEPS [KERNEL]]
#include "rcfd/database.hpp"
#include "rcfd/operator.hpp"

#include "triad.hpp"

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace rcfd;

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  {
    PetscCheck(argc >= 3, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "usage: shift_bandwidth DB NF [STEPS [moving|maij]]");
    const int nf = std::atoi(argv[2]);
    const long steps = argc > 3 ? std::atol(argv[3]) : 2000;
    std::unique_ptr<Database> db;
    PetscCall(Database::load(PETSC_COMM_WORLD, argv[1], DatabaseLoadOptions{}, &db));
    std::vector<double> d(nf), w(nf, 1.0 / nf);
    for (int i = 0; i < nf; ++i) d[i] = 1e-3 * (1 + i);
    FractionSet set;
    PetscCall(FractionSet::create(d, w, &set));
    FractionState st;
    PetscCall(st.create(db->layout(), nf));
    PetscCall(VecSet(st.masses(), 1.0));
    const std::string kernel = argc > 4 ? argv[4] : "moving";
    PetscCheck(kernel == "moving" || kernel == "maij", PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT,
               "KERNEL must be moving or maij, got '%s'", kernel.c_str());
    ShiftOperator shift;
    shift.setKernel(kernel == "maij" ? ShiftOperator::Kernel::Maij : ShiftOperator::Kernel::Moving);
    RunContext ctx{*db, set, 1440.0};
    PetscCall(shift.setUp(ctx));
    // Bytes one step must move at least.  maij: the whole matrix (values,
    // column indices, row pointers), the input and the output vectors.
    // moving: the compact frame (moving rows' numbers, pointers, column
    // offsets and weights, include/rcfd/frames.hpp), and their masses read
    // and written once.
    double sums[3] = {0.0, 0.0, 0.0}; // nonzeros, moving rows, compact bytes
    for (int k = 0; k < db->numFrames(); ++k) {
      const CompactFrame &f = db->frame(k);
      sums[0] += static_cast<double>(f.numEntries() + db->layout().numLocal() - f.numRows());
      sums[1] += static_cast<double>(f.numRows());
      sums[2] += static_cast<double>(f.bytes());
    }
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums, 3, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD));
    const double nnz = sums[0] / db->numFrames(), movingRows = sums[1] / db->numFrames(),
                 frameBytes = sums[2] / db->numFrames();
    const double N = db->mesh().numCells();
    const double bytes = kernel == "maij" ? nnz * 12.0 + (N + 1) * 4.0 + 2.0 * N * nf * 8.0
                                          : frameBytes + 2.0 * movingRows * nf * 8.0;
    StepInfo step;
    for (int warm = 0; warm < db->numFrames(); ++warm) {
      step.frame = warm;
      PetscCall(shift.apply(step, st));
    }
    PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
    const double t0 = MPI_Wtime();
    for (long s = 0; s < steps; ++s) {
      step.frame = static_cast<int>(s % db->numFrames());
      PetscCall(shift.apply(step, st));
    }
    PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
    const double perStep = (MPI_Wtime() - t0) / steps;
    const double triad = triadBandwidth(PETSC_COMM_WORLD);
    int size;
    MPI_Comm_size(PETSC_COMM_WORLD, &size);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                          "kernel %s  ranks %d  nf %d  cells %.0f  nnz/col %.2f  moving rows %.0f %%  shift step %.3f ms  %.1f GB/s  triad %.1f GB/s  %.0f %% of triad\n",
                          kernel.c_str(), size, nf, N, nnz / N, 100.0 * movingRows / N, perStep * 1e3, bytes / perStep / 1e9, triad / 1e9,
                          100.0 * bytes / perStep / triad));
  }
  PetscCall(PetscFinalize());
  return 0;
}
