// Time of Database::load alone: N loads of one file in this process, each
// rank's process CPU seconds and wall seconds per load, and the median of
// the slowest rank's (the load is collective: the slowest rank is the load),
// and a hash of what each rank holds (frames, ghost rows, alpha_s), to
// compare loaders bit for bit.
// usage: mpiexec -n P load_time DB.h5 [N]
#include "rcfd/database.hpp"
#include "base/petsc_compat.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>

using namespace rcfd;

namespace {

double cpuSeconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; } // of this process

// FNV-1a over the bytes of a vector.
template <typename T> void hash(const std::vector<T> &v, unsigned long long *h) {
  const auto *p = reinterpret_cast<const unsigned char *>(v.data());
  for (size_t i = 0; i < v.size() * sizeof(T); ++i) *h = (*h ^ p[i]) * 1099511628211ULL;
}

PetscErrorCode hashOf(const Database &db, unsigned long long *h) {
  PetscFunctionBeginUser;
  *h = 14695981039346656037ULL;
  hash(db.ghostRows(), h);
  for (int k = 0; k < db.numFrames(); ++k) {
    const CompactFrame &f = db.frame(k);
    for (const auto &part : {f.rows, f.ptr, f.col}) hash(part, h);
    hash(std::vector<int32_t>(f.group.begin(), f.group.end()), h);
    hash(std::vector<int32_t>(f.firstEntry.begin(), f.firstEntry.end()), h);
    hash(f.offset, h);
    hash(f.val, h);
    hash(f.quantum, h);
    const PetscScalar *a;
    PetscInt n;
    PetscCall(VecGetLocalSize(db.alphaS(k), &n));
    PetscCall(VecGetArrayRead(db.alphaS(k), &a));
    hash(std::vector<double>(a, a + n), h);
    PetscCall(VecRestoreArrayRead(db.alphaS(k), &a));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  {
    PetscCheck(argc >= 2, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "usage: load_time DB.h5 [N]");
    const int loads = argc > 2 ? std::atoi(argv[2]) : 5;
    std::vector<double> cpu, wall;
    for (int i = 0; i < loads; ++i) {
      PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
      double t[2] = {cpuSeconds(), MPI_Wtime()};
      std::unique_ptr<Database> db;
      PetscCall(Database::load(PETSC_COMM_WORLD, argv[1], DatabaseLoadOptions{}, &db));
      t[0] = cpuSeconds() - t[0];
      t[1] = MPI_Wtime() - t[1];
      PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, t, 2, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD));
      cpu.push_back(t[0]);
      wall.push_back(t[1]);
      if (i > 0) continue;
      unsigned long long h;
      PetscCall(hashOf(*db, &h));
      PetscCall(PetscSynchronizedPrintf(PETSC_COMM_WORLD, "frames held: hash %016llx\n", h));
      PetscCall(PetscSynchronizedFlush(PETSC_COMM_WORLD, PETSC_STDOUT));
    }
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "load of %s, %d loads, slowest rank: median %.3f CPU s, %.3f wall s\n",
                          argv[1], loads, median(cpu), median(wall)));
  }
  PetscCall(PetscFinalize());
  return 0;
}
