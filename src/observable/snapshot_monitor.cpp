// Mid-plane snapshots of each fraction's volume fraction (paper Fig. 1).
#include "observable/answers.hpp"
#include "base/petsc_compat.hpp"
#include "base/collective.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace rcfd {

PetscErrorCode SnapshotMonitor::setUp(const RunContext &run, const FractionState &, const std::string &dir) {
  PetscFunctionBeginUser;
  comm = run.db.layout().comm();
  fractions = &run.fractions;
  rho = run.solidDensity;
  directory = dir;
  const Mesh &mesh = run.db.mesh();
  PetscCheck(mesh.onBoxLattice(), comm, PETSC_ERR_SUP, "-snapshots_times needs a box mesh (a mid-plane of cells)");
  int up = 2;
  bool upward = true;
  verticalAxis(run.db.metadata().gravity, &up, &upward);
  const BoxSpec &b = mesh.boxSpec();
  const int n[3] = {b.nx, b.ny, b.nz};
  int across = -1, depth = -1; // the horizontal axes: the plane spans `across`, cuts `depth` in the middle
  for (int a = 0; a < 3; ++a)
    if (a != up) (across < 0 ? across : depth) = a;
  if (n[depth] > n[across]) std::swap(depth, across);
  const int middle = n[depth] / 2;
  const char *names = "xyz";
  header = std::string(1, names[across]) + "_m," + std::string(1, names[up]) + "_m";
  for (int i = 0; i < fractions->size(); ++i) header += ",alpha_" + fractions->label(i);
  header += ",alpha_total";
  const auto &owned = run.db.layout().ownedNatural();
  const auto &volumes = run.db.localVolumes();
  planeCells.clear();
  planeCoordinates.clear();
  planeVolumes.clear();
  for (std::size_t c = 0; c < owned.size(); ++c) {
    const PetscInt g = owned[c], boxCell = mesh.boxCell(static_cast<int>(g)); // a vessel: only its cells
    const int index[3] = {static_cast<int>(boxCell % b.nx), static_cast<int>((boxCell / b.nx) % b.ny),
                          static_cast<int>(boxCell / (static_cast<PetscInt>(b.nx) * b.ny))};
    if (index[depth] != middle) continue;
    planeCells.push_back(static_cast<PetscInt>(c));
    planeCoordinates.push_back(mesh.cellCentre[g][across]);
    planeCoordinates.push_back(mesh.cellCentre[g][up]);
    planeVolumes.push_back(volumes[c]);
  }
  const double dt = run.db.metadata().dtRec;
  steps.clear();
  for (double t : times) steps.push_back(std::lround(t / dt));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SnapshotMonitor::sample(const MonitorContext &ctx) {
  PetscFunctionBeginUser;
  for (std::size_t k = 0; k < steps.size(); ++k) {
    if (steps[k] != ctx.step) continue;
    const int nf = fractions->size(), width = nf + 2;
    std::vector<double> local;
    const PetscScalar *m;
    PetscCall(VecGetArrayRead(ctx.state.masses(), &m));
    for (std::size_t p = 0; p < planeCells.size(); ++p) {
      local.push_back(planeCoordinates[2 * p]);
      local.push_back(planeCoordinates[2 * p + 1]);
      for (int i = 0; i < nf; ++i) local.push_back(m[planeCells[p] * nf + i] / (rho * planeVolumes[p]));
    }
    PetscCall(VecRestoreArrayRead(ctx.state.masses(), &m));
    PetscMPIInt size, rank, count = static_cast<PetscMPIInt>(local.size());
    PetscCallMPI(MPI_Comm_size(comm, &size));
    PetscCallMPI(MPI_Comm_rank(comm, &rank));
    std::vector<PetscMPIInt> counts(size), offsets(size, 0);
    PetscCallMPI(MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm));
    for (int r = 1; r < size; ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
    std::vector<double> all(rank == 0 ? offsets[size - 1] + counts[size - 1] : 0);
    PetscCallMPI(MPI_Gatherv(local.data(), count, MPI_DOUBLE, all.data(), counts.data(), offsets.data(), MPI_DOUBLE,
                             0, comm));
    PetscErrorCode written = PETSC_SUCCESS;
    if (rank == 0) {
      std::vector<std::size_t> order(all.size() / width);
      for (std::size_t r = 0; r < order.size(); ++r) order[r] = r;
      std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { // bottom row first, then across
        const double *x = &all[a * width], *y = &all[b * width];
        return x[1] != y[1] ? x[1] < y[1] : x[0] < y[0];
      });
      std::string text = header + "\n";
      char number[32];
      for (std::size_t r : order) {
        double total = 0.0;
        for (int c = 0; c < width; ++c) {
          std::snprintf(number, sizeof number, "%.9g", all[r * width + c]);
          text += (c ? "," : "") + std::string(number);
          if (c >= 2) total += all[r * width + c];
        }
        std::snprintf(number, sizeof number, ",%.9g\n", total);
        text += number;
      }
      std::snprintf(number, sizeof number, "%.4f", ctx.time);
      written = writeFileAtomically(directory + "/snapshot_" + number + "s.csv", text);
    }
    PetscCall(agreeOnStatus(comm, written)); // written by rank 0 alone: the others must not wait
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
