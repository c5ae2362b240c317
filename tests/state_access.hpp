// Test helpers: read and write a distributed fraction state in natural cell
// order, and write small databases, so that tests can state expectations per
// mesh cell whatever the partition.
#pragma once

#include "rcfd/database.hpp"
#include "check.hpp"
#include "rcfd/fractions.hpp"
#include "database/database_file_writer.hpp"

#include <cstdlib>
#include <string>
#include <vector>

namespace rcfd::test {

/// Masses in natural order (nf per cell) on every rank.  Collective.
inline std::vector<double> gatherNatural(const Database &db, Vec masses, int nf) {
  std::vector<double> out;
  db.layout().gatherToAll(nf, masses, &out);
  return out;
}

/// Set the state from natural-ordered values (every rank passes all values).
inline void setNatural(const Database &db, FractionState &st, const std::vector<double> &values) {
  const int nf = st.numFractions();
  PetscScalar *m;
  VecGetArrayWrite(st.masses(), &m);
  const auto &owned = db.layout().ownedNatural();
  for (size_t r = 0; r < owned.size(); ++r)
    for (int i = 0; i < nf; ++i) m[r * nf + i] = values[owned[r] * nf + i];
  VecRestoreArrayWrite(st.masses(), &m);
}

/// Write (on rank 0) a database of `frames` identity shifts with the given
/// alpha_s, and wait for it on all ranks.
inline void writeIdentityDatabase(const std::string &path, const Mesh &mesh,
                                  const std::vector<double> &alpha, const DatabaseMetadata &meta,
                                  int frames = 1, long long formatVersion = kDatabaseFormatVersion) {
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0) {
    DatabaseFileWriter w(path, mesh, meta, formatVersion);
    FrameRecord f;
    f.alphaS = alpha;
    f.shift = shiftFromTransfers(mesh.numCells(), {}, {}, {});
    for (int k = 0; k < frames; ++k) w.append(f);
    w.finish();
  }
  MPI_Barrier(PETSC_COMM_WORLD);
}

/// The directory for a test's files at this number of ranks,
/// ARG/<name>_np<ranks> (ARG: argv[1], default "."), made by rank 0 before
/// any rank returns.  Collective; empty if it could not be made.
inline std::string rankCountDirectory(int argc, char **argv, const std::string &name) {
  int size, rank;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  const std::string dir = (argc > 1 ? argv[1] : std::string(".")) + "/" + name + "_np" + std::to_string(size);
  int made = rank != 0 || std::system(("mkdir -p '" + dir + "'").c_str()) == 0;
  MPI_Bcast(&made, 1, MPI_INT, 0, PETSC_COMM_WORLD);
  return made ? dir : std::string();
}

/// Sum of failures over all ranks, for main()'s exit status.
inline int globalFailures() {
  int mine = failures(), total = 0;
  MPI_Allreduce(&mine, &total, 1, MPI_INT, MPI_SUM, PETSC_COMM_WORLD);
  return total;
}

/// main() of a test run at 1 and 2 ranks: PETSc up (errors returned, not
/// printed as tracebacks), `run(dir)` in rankCountDirectory(argc, argv, name),
/// the failures of all ranks summed into the exit status.
template <typename F> int rankTestMain(int argc, char **argv, const std::string &name, F &&run) {
  if (PetscInitialize(&argc, &argv, nullptr, nullptr)) return 1;
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  RCFD_CHECK(argc > 1);
  const std::string dir = rankCountDirectory(argc, argv, name);
  RCFD_CHECK(!dir.empty() && run(dir) == 0);
  PetscPopErrorHandler();
  const int failed = globalFailures();
  if (PetscFinalize()) return 1;
  return failed == 0 ? 0 : 1;
}

} // namespace rcfd::test
