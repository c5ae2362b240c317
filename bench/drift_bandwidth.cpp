// Time of the drift sweep per step against the bytes it must move, next to
// a STREAM-like triad measured in the same run on the same ranks (the
// shift's counterpart is shift_bandwidth).  The state is the run's: the
// inventory mixed into frame 0, then shift and drift step after step along
// the frames (a replay); the drift reads its options from the command line
// (-drift_kd, -drift_every, -drift_agitation leaving, ...).
//
// Bytes one drift step must move at least, counted per step from the state
// the drift sees: the masses of this rank's cells that hold solid (nf
// numbers read and written), one face record (two 4-byte cell indices and
// the two area/volume coefficients, 24 bytes) per face normal to gravity
// with solid on at least one side, a factor per solid cell when the drift
// is scaled by agitation, and the ghost cells' masses in (nf numbers each;
// a face between two ranks is computed on both, so no change goes back).
// usage: mpiexec -n P drift_bandwidth DB.h5 NF [STEPS] [-drift_... options]   (NF 2 or 5)
#include "rcfd/database.hpp"
#include "rcfd/drift.hpp"
#include "state/initial_state.hpp"

#include "triad.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

using namespace rcfd;

namespace {

// CPU time of this process (a busy machine's waits left out).
double cpuSeconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

// Bytes the drift of one step must move on this rank (see the file comment).
PetscErrorCode bytesOfStep(FaceExchange &x, Vec masses, int nf, bool scaled, double *bytes, double *touching, double *both) {
  PetscFunctionBeginUser;
  PetscCall(x.gatherBegin(masses));
  PetscCall(x.gatherEnd());
  PetscInt nlocal;
  PetscCall(VecGetLocalSize(masses, &nlocal));
  nlocal /= nf;
  auto solid = [&](PetscInt c) {
    const PetscScalar *m = x.massAt(c);
    for (int i = 0; i < nf; ++i)
      if (m[i] > 0) return true;
    return false;
  };
  double cells = 0, faces = 0;
  for (PetscInt c = 0; c < nlocal; ++c) cells += solid(c);
  for (const SwapFace &f : x.faces()) {
    faces += solid(f.lower) || solid(f.upper);
    *both += solid(f.lower) && solid(f.upper);
  }
  *touching += faces;
  PetscCall(x.endKernel());
  const double ghosts = x.numGathered() - nlocal;
  *bytes = cells * nf * 16.0 + faces * 24.0 + (scaled ? cells * 8.0 : 0.0) + ghosts * nf * 8.0;
  PetscFunctionReturn(0);
}

} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  {
    PetscCheck(argc >= 3, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT,
               "usage: drift_bandwidth DB NF [STEPS] [-drift_... options]");
    const int nf = std::atoi(argv[2]);
    PetscCheck(nf == 2 || nf == 5, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT,
               "drift_bandwidth: NF must be 2 (bi-disperse) or 5 (penta-disperse), got %s", argv[2]);
    const long steps = argc > 3 && argv[3][0] != '-' ? std::atol(argv[3]) : 2000;
    std::unique_ptr<Database> db;
    PetscCall(Database::load(PETSC_COMM_WORLD, argv[1], DatabaseLoadOptions{}, &db));
    FractionSet set;
    if (nf == 5)
      PetscCall(FractionSet::create({1.783e-3, 1.998e-3, 2.284e-3, 2.855e-3, 3.426e-3},
                                    {0.100, 0.205, 0.445, 0.150, 0.100}, &set));
    else PetscCall(FractionSet::create({1.950e-3, 2.820e-3}, {0.473, 0.527}, &set));
    const double rho = 1440.0;
    RunContext ctx{*db, set, rho};
    FractionState st;
    PetscCall(st.create(db->layout(), nf));
    PetscCall(setInitialState(InitialState{}, *db, set, rho, st));
    ShiftOperator shift;
    PetscCall(shift.setUp(ctx));
    DriftOperator drift;
    drift.setOptionsPrefix("drift_");
    PetscCall(drift.setFromOptions(PETSC_COMM_WORLD));
    PetscCall(drift.setUp(ctx));
    // The drift's faces, for counting bytes (not timed).
    FaceExchange count;
    const Vec3 g = db->metadata().gravity;
    PetscCall(count.setUp(*db, nf, {-g[0], -g[1], -g[2]}, 1e-9));
    const bool scaled = drift.agitationField() != nullptr;

    StepInfo step;
    step.dt = db->metadata().dtRec;
    const int K = db->numFrames();
    double cDrift = 0, tShift = 0, tDrift = 0, bytes = 0, touching = 0, both = 0;
    std::vector<double> driftTimes; // per step: the median is robust to a busy machine
    for (long s = 0; s < K + steps; ++s) { // one pass over the frames to warm up
      step.step = s;
      step.frame = static_cast<int>(s % K);
      step.nextFrame = static_cast<int>((s + 1) % K);
      step.jump = step.nextFrame != step.frame + 1;
      const bool timed = s >= K;
      const double t0 = MPI_Wtime();
      PetscCall(shift.apply(step, st));
      const double t1 = MPI_Wtime();
      if (timed) {
        double b = 0.0;
        PetscCall(bytesOfStep(count, st.masses(), nf, scaled, &b, &touching, &both));
        bytes += b;
      }
      const double t2 = MPI_Wtime(), c2 = cpuSeconds();
      PetscCall(drift.apply(step, st));
      const double t3 = MPI_Wtime(), c3 = cpuSeconds();
      if (timed) cDrift += c3 - c2;
      if (timed) tShift += t1 - t0, tDrift += t3 - t2, driftTimes.push_back(t3 - t2);
    }
    double sums[6] = {tShift, tDrift, bytes, touching, both, static_cast<double>(count.faces().size())};
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums + 2, 4, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD));
    std::nth_element(driftTimes.begin(), driftTimes.begin() + driftTimes.size() / 2, driftTimes.end());
    double median = driftTimes[driftTimes.size() / 2];
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &median, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &cDrift, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD));
    const double shiftStep = sums[0] / steps, driftStep = sums[1] / steps, perStep = sums[2] / steps;
    const double triad = triadBandwidth(PETSC_COMM_WORLD);
    int size;
    MPI_Comm_size(PETSC_COMM_WORLD, &size);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                          "ranks %d  nf %d  steps %ld  shift %.3f ms  drift step %.3f ms (median %.3f ms, cpu %.3f ms)  %.2f MB/step  %.1f GB/s  triad %.1f GB/s  %.0f %% of triad  (faces %.0f, touching solid %.0f, solid on both sides %.0f per step; sub-steps %ld over %ld steps)\n",
                          size, nf, steps, shiftStep * 1e3, driftStep * 1e3, median * 1e3, cDrift / steps * 1e3, perStep / 1e6, perStep / driftStep / 1e9,
                          triad / 1e9, 100.0 * perStep / driftStep / triad, sums[5], sums[3] / steps, sums[4] / steps, drift.substepsTaken(), drift.stepsTaken()));
  }
  PetscCall(PetscFinalize());
  return 0;
}
