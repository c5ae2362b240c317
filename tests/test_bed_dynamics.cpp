// A database's bed dynamics from its alpha_s frames: a 3-cell column whose
// centre of gravity is known per frame gives Delta z_CoG by hand, on 1 and 2
// ranks.
#include "check.hpp"
#include "box_meshes.hpp"
#include "state_access.hpp"
#include "base/petsc_compat.hpp"

#include "observable/bed_dynamics.hpp"
#include "rcfd/database.hpp"
#include "database/database_file_writer.hpp"

#include <cstdio>
#include <string>

using namespace rcfd;

namespace {

PetscErrorCode run(const std::string &dir) {
  PetscFunctionBeginUser;
  PetscMPIInt rank;
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  const std::string path = dir + "/bed_dynamics_column.h5";
  // Cells 0.1 m high with centres at 0.05, 0.15, 0.25 m; three frames:
  //   (0.5, 0, 0)   -> z_CoG 0.05
  //   (0.25,0.25,0) -> 0.10
  //   (0, 0.2, 0.2) -> 0.20      mean 0.35/3, Delta = (0.06667 + 0.01667 + 0.08333)/3 = 0.05556
  if (rank == 0) {
    BoxSpec s;
    s.nx = 1;
    s.ny = 1;
    s.nz = 3;
    s.length = {0.1, 0.1, 0.3};
    DatabaseFileWriter w(path, rcfd::test::boxMesh(s), DatabaseMetadata{});
    const std::vector<std::vector<double>> alphas = {{0.5, 0, 0}, {0.25, 0.25, 0}, {0, 0.2, 0.2}};
    for (const auto &a : alphas) {
      FrameRecord f;
      f.alphaS = a;
      f.shift = shiftFromTransfers(3, {0, 1, 2}, {0, 1, 2}, {1, 1, 1});
      w.append(f);
    }
    w.finish();
  }
  PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
  DatabaseLoadOptions options;
  options.columnTolerance = 1.0; // identity shifts between unequal frames: not a consistent database
  std::unique_ptr<Database> db;
  PetscCall(Database::load(PETSC_COMM_WORLD, path, options, &db));
  std::vector<double> z;
  PetscCall(databaseBedCentres(*db, &z));
  RCFD_CHECK(z.size() == 3);
  RCFD_CHECK_CLOSE(z[0], 0.05, 1e-15);
  RCFD_CHECK_CLOSE(z[1], 0.10, 1e-15);
  RCFD_CHECK_CLOSE(z[2], 0.20, 1e-15);
  const double mean = 0.35 / 3.0;
  RCFD_CHECK_CLOSE(bedDynamics(z), ((mean - 0.05) + (mean - 0.10) + (0.20 - mean)) / 3.0, 1e-15);
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

int main(int argc, char **argv) { return test::rankTestMain(argc, argv, "bed_dynamics", run); }
