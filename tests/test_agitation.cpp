// Agitation fields of hand-made frames: the share of solid leaving each cell
// and the local dispersion rate, their solid-weighted mean and maximum, by
// hand, on 1 and 2 ranks.
#include "check.hpp"
#include "box_meshes.hpp"
#include "base/petsc_compat.hpp"
#include "scoped_options.hpp"
#include "state_access.hpp"

#include "rcfd/agitation.hpp"
#include "database/database_file_writer.hpp"


using namespace rcfd;

namespace {

PetscErrorCode run(const std::string &dir) {
  PetscFunctionBeginUser;
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  const std::string path = dir + "/agitation.h5";
  // A column of three 0.1 m cells.  Frame 0: half of cell 0 moves up one cell,
  // 3/4 of cell 1 moves up one cell, cell 2 keeps its solid; frame 1: nothing moves.
  if (rank == 0) {
    BoxSpec s;
    s.nx = 1;
    s.ny = 1;
    s.nz = 3;
    s.length = {0.1, 0.1, 0.3};
    DatabaseFileWriter w(path, rcfd::test::boxMesh(s), DatabaseMetadata{}); // dt_rec 5 ms
    FrameRecord f0, f1;
    f0.alphaS = {0.4, 0.4, 0.1};
    f0.shift = shiftFromTransfers(3, {0, 1, 1, 2, 2}, {0, 0, 1, 1, 2}, {1, 1, 1, 3, 1});
    f1.alphaS = {0.2, 0.3, 0.4};
    f1.shift = shiftFromTransfers(3, {}, {}, {});
    w.append(f0);
    w.append(f1);
    w.finish();
  }
  MPI_Barrier(PETSC_COMM_WORLD);
  std::unique_ptr<Database> db;
  PetscCall(Database::load(PETSC_COMM_WORLD, path, DatabaseLoadOptions{}, &db));
  auto natural = [&](const AgitationField &f, int k) {
    std::vector<double> all(3, 0.0), mine(3, 0.0);
    for (PetscInt i = 0; i < db->layout().numLocal(); ++i)
      mine[db->layout().naturalCell(db->layout().rowStart() + i)] = f.frame(k)[i];
    MPI_Allreduce(mine.data(), all.data(), 3, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD);
    return all;
  };
  AgitationField leaving;
  PetscCall(leaving.setUp(*db, AgitationMeasure::LeavingShare));
  const auto l0 = natural(leaving, 0), l1 = natural(leaving, 1);
  RCFD_CHECK_CLOSE(l0[0], 0.5, 1e-15);
  RCFD_CHECK_CLOSE(l0[1], 0.75, 1e-15);
  RCFD_CHECK(l0[2] == 0.0 && l1[0] == 0.0 && l1[1] == 0.0 && l1[2] == 0.0);
  // sum alpha V a / sum alpha V = (0.4 * 0.5 + 0.4 * 0.75) / (0.9 + 0.9).
  RCFD_CHECK_CLOSE(leaving.solidWeightedMean(), 0.5 / 1.8, 1e-15);
  RCFD_CHECK_CLOSE(leaving.maximum(), 0.75, 1e-15);
  // Dispersion rate: 0.5 of cell 0 goes 0.1 m in 5 ms: 0.5 * 0.01 / 0.005 = 1 m^2/s; cell 1: 1.5.
  AgitationField dispersion;
  PetscCall(dispersion.setUp(*db, AgitationMeasure::Dispersion));
  const auto d0 = natural(dispersion, 0);
  RCFD_CHECK_CLOSE(d0[0], 1.0, 1e-12);
  RCFD_CHECK_CLOSE(d0[1], 1.5, 1e-12);
  RCFD_CHECK(d0[2] == 0.0);
  RCFD_CHECK_CLOSE(dispersion.maximum(), 1.5, 1e-12);
  AgitationMeasure parsed = AgitationMeasure::LeavingShare;
  PetscCall(parseAgitationMeasure("dispersion", &parsed));
  RCFD_CHECK(parsed == AgitationMeasure::Dispersion);
  {
    ErrorCapture capture;
    RCFD_CHECK(parseAgitationMeasure("bubbles", &parsed) == PETSC_ERR_ARG_OUTOFRANGE);
    RCFD_CHECK(capture.message() == "the agitation measure 'bubbles' is not known; use leaving or dispersion");
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

int main(int argc, char **argv) { return test::rankTestMain(argc, argv, "agitation", run); }
