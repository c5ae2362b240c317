// 10,000 replay steps of the default database with five fractions: every
// fraction's mass is conserved to relative 1e-12 (with the run's mass
// ledger, as `rcfd run` steps) and no mass ever becomes negative.  Without
// the ledger the drift must still be pure round-off (below 1e-11), so the
// ledger cannot be hiding a leak.  The two shift kernels (moving rows in
// place, whole-matrix MAIJ) give the same masses, and on 2 ranks the
// partition shares the moving rows evenly.  Runs at 1 and 2 ranks.
#include "check.hpp"
#include "fraction_sets.hpp"
#include "rcfd/database.hpp"
#include "rcfd/mass_ledger.hpp"
#include "rcfd/operator.hpp"

#include <cmath>

using namespace rcfd;

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  {
    PetscCheck(argc > 1, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "usage: test_replay DATABASE");
    std::unique_ptr<Database> db;
    PetscCall(Database::load(PETSC_COMM_WORLD, argv[1], DatabaseLoadOptions{}, &db));
    const FractionSet set = rcfd::test::fractionSet({1.783e-3, 1.998e-3, 2.284e-3, 2.855e-3, 3.426e-3},
                          {0.100, 0.205, 0.445, 0.150, 0.100});
    const int nf = set.size();
    FractionState st;
    PetscCall(st.create(db->layout(), nf));
    // A deliberately uneven start: fraction i only in cells whose natural
    // index is congruent to i mod nf, scaled by the frame-0 solid.
    PetscScalar *m;
    const PetscScalar *a;
    PetscCall(VecGetArrayWrite(st.masses(), &m));
    PetscCall(VecGetArrayRead(db->alphaS(0), &a));
    const auto &owned = db->layout().ownedNatural();
    for (size_t r = 0; r < owned.size(); ++r)
      for (int i = 0; i < nf; ++i)
        m[r * nf + i] = (owned[r] % nf == i) ? 1440.0 * a[r] * db->localVolumes()[r] : 0.0;
    PetscCall(VecRestoreArrayRead(db->alphaS(0), &a));
    PetscCall(VecRestoreArrayWrite(st.masses(), &m));

    ShiftOperator shift;
    RunContext ctx{*db, set, 1440.0};
    PetscCall(shift.setUp(ctx));
    OwnedVec start;
    PetscCall(VecDuplicate(st.masses(), start.put()));
    PetscCall(VecCopy(st.masses(), start));
    std::vector<double> before, after;
    PetscCall(st.totals(&before));
    const long steps = 10000;
    double lowest = 0.0, worst = 0.0;
    for (bool withLedger : {false, true}) {
      PetscCall(VecCopy(start, st.masses()));
      MassLedger ledger;
      PetscCall(ledger.start(st));
      StepInfo step;
      for (long s = 0; s < steps; ++s) {
        step.step = s;
        step.frame = static_cast<int>(s % db->numFrames());
        PetscCall(shift.apply(step, st));
        if (withLedger) PetscCall(ledger.check(s + 1, st));
        if (s % 500 == 0 || s + 1 == steps) {
          double low;
          PetscCall(st.minimum(&low));
          lowest = std::fmin(lowest, low);
        }
      }
      PetscCall(st.totals(&after));
      worst = 0.0;
      for (int i = 0; i < nf; ++i) {
        RCFD_CHECK(before[i] > 0);
        worst = std::fmax(worst, std::fabs(after[i] / before[i] - 1.0));
      }
      PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                            "replay %s the ledger: %ld steps, largest relative mass change %.3e\n",
                            withLedger ? "with" : "without", steps, worst));
      RCFD_CHECK(worst < (withLedger ? 1e-12 : 1e-11));
    }
    RCFD_CHECK(lowest >= 0.0);
    // The state has actually moved: fraction 0 is no longer confined to its
    // starting cells.
    PetscCall(VecGetArrayRead(st.masses(), &a));
    double outside = 0.0;
    for (size_t r = 0; r < owned.size(); ++r)
      if (owned[r] % nf != 0) outside += a[r * nf + 0];
    PetscCall(VecRestoreArrayRead(st.masses(), &a));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &outside, 1, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD));
    RCFD_CHECK(outside > 0.1 * after[0]);

    // One cycle of frames with each kernel from the same start: identical on
    // one rank (same summation order), round-off apart on two.
    OwnedVec byMaij;
    PetscCall(VecDuplicate(start, byMaij.put()));
    for (auto kernel : {ShiftOperator::Kernel::Maij, ShiftOperator::Kernel::Moving}) {
      ShiftOperator op;
      op.setKernel(kernel);
      PetscCall(op.setUp(ctx));
      PetscCall(VecCopy(start, st.masses()));
      StepInfo step;
      for (int k = 0; k < db->numFrames(); ++k) {
        step.frame = k;
        PetscCall(op.apply(step, st));
      }
      if (kernel == ShiftOperator::Kernel::Maij) PetscCall(VecCopy(st.masses(), byMaij));
    }
    PetscReal largest, difference;
    PetscCall(VecNorm(byMaij, NORM_INFINITY, &largest));
    PetscCall(VecAXPY(byMaij, -1.0, st.masses()));
    PetscCall(VecNorm(byMaij, NORM_INFINITY, &difference));
    PetscMPIInt size;
    PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "moving-rows vs MAIJ kernel after %d steps: largest difference %.3e of %.3e\n",
                          db->numFrames(), difference, largest));
    RCFD_CHECK(size == 1 ? difference == 0.0 : difference <= 1e-13 * largest);

    // The partition balances the work: each rank holds about its share of
    // all frames' moving (non-identity) rows, though the freeboard, which
    // never moves, is half of the cells.
    double moving[2] = {0.0, 0.0}; // this rank's, all ranks'
    for (int k = 0; k < db->numFrames(); ++k) {
      OwnedMat T;
      PetscCall(db->shiftMatrix(k, &T));
      for (PetscInt row = db->layout().rowStart(); row < db->layout().rowEnd(); ++row) {
        PetscInt n;
        const PetscInt *c;
        const PetscScalar *v;
        PetscCall(MatGetRow(T, row, &n, &c, &v));
        if (!(n == 1 && c[0] == row && v[0] == 1.0)) moving[0] += 1.0;
        PetscCall(MatRestoreRow(T, row, &n, &c, &v));
      }
    }
    PetscCallMPI(MPI_Allreduce(&moving[0], &moving[1], 1, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD));
    const double share = moving[0] / moving[1] * size;
    PetscCall(PetscPrintf(PETSC_COMM_SELF, "moving rows on this rank: %.1f %% of the fair share\n", 100.0 * share));
    RCFD_CHECK(share > 0.8 && share < 1.2); // unweighted, one rank had all of them
  }
  int failures = rcfd::test::failures(), total = 0;
  MPI_Allreduce(&failures, &total, 1, MPI_INT, MPI_SUM, PETSC_COMM_WORLD);
  PetscCall(PetscFinalize());
  return total == 0 ? 0 : 1;
}
