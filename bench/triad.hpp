// A STREAM-like triad measured on the same ranks as a benchmark, so that a
// kernel's bandwidth can be read against what the machine gave at the time.
#pragma once

#include <mpi.h>

#include <algorithm>
#include <cstdlib>
#include <vector>

// a = b + s c over arrays much larger than the caches; 24 bytes per element.
// Bytes per second over all ranks (the best of five).
inline double triadBandwidth(MPI_Comm comm) {
  const size_t n = 20'000'000;
  std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
  double best = 1e30;
  for (int rep = 0; rep < 5; ++rep) {
    MPI_Barrier(comm);
    const double t0 = MPI_Wtime();
    for (size_t k = 0; k < n; ++k) a[k] = b[k] + 3.0 * c[k];
    double t = MPI_Wtime() - t0;
    MPI_Allreduce(MPI_IN_PLACE, &t, 1, MPI_DOUBLE, MPI_MAX, comm);
    best = std::min(best, t);
  }
  int size;
  MPI_Comm_size(comm, &size);
  if (a[n / 2] != 7.0) std::abort(); // keep the loop
  return 24.0 * n * size / best;
}
