// Test helper: a small synthetic bubbling bed written to a database file, for
// tests that need several databases on one mesh (switching, blends).
#pragma once

#include "box_meshes.hpp"
#include "builders/synthetic/synthetic_bed.hpp"
#include "database/database_file_writer.hpp"

#include <cstdint>
#include <string>

namespace rcfd::test {

/// Collective: rank 0 writes a synthetic bed of 10 x 2 x nz cells, `frames`
/// frames, bubbles nucleated at `rate` from `seed`, recorded at `recorded`;
/// every rank waits for the file.
inline void writeBed(const std::string &path, int nz, double rate, std::uint64_t seed, int frames = 12,
                     const OperatingConditions &recorded = {}) {
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0) {
    SyntheticBedOptions o;
    o.box.nx = 10;
    o.box.ny = 2;
    o.box.nz = nz;
    o.numFrames = frames;
    o.warmUpTime = 0.1;
    o.nucleationRate = rate;
    o.seed = seed;
    DatabaseMetadata metadata;
    metadata.conditions = recorded;
    DatabaseFileWriter w(path, boxMesh(o.box), metadata);
    generateSyntheticBed(o, [&](const FrameRecord &f) { w.append(f); });
    w.finish();
  }
  MPI_Barrier(PETSC_COMM_WORLD);
}

} // namespace rcfd::test
