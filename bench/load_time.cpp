// Time of Database::load alone: N loads of one file in this process, each
// rank's process CPU seconds and wall seconds per load, and the median of
// the slowest rank's (the load is collective: the slowest rank is the load).
// usage: mpiexec -n P load_time DB.h5 [N]
#include "rcfd/database.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>

using namespace rcfd;

namespace {

double cpuSeconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; } // of this process

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
    }
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "load of %s, %d loads, slowest rank: median %.3f CPU s, %.3f wall s\n",
                          argv[1], loads, median(cpu), median(wall)));
  }
  PetscCall(PetscFinalize());
  return 0;
}
