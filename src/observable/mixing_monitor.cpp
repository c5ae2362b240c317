// Lacey's mixing index of every fraction over time (observable/mixing_index.hpp).
#include "observable/answers.hpp"
#include "base/petsc_compat.hpp"

#include "observable/mixing_index.hpp"

namespace rcfd {
namespace {
constexpr double kPi = 3.14159265358979323846;
}

PetscErrorCode MixingMonitor::setUp(const RunContext &run, const FractionState &, const std::string &dir) {
  PetscFunctionBeginUser;
  comm = run.db.layout().comm();
  nf = run.fractions.size();
  rho = run.solidDensity;
  // The inventory's particles per unit of its volume: sum_i w_i / v_i.
  double perVolume = 0.0;
  for (int i = 0; i < nf; ++i) {
    const double d = run.fractions.diameter(i);
    perVolume += run.fractions.massShare(i) / (kPi / 6.0 * d * d * d);
  }
  meanParticleVolume = 1.0 / perVolume;
  path = dir + "/mixing.csv";
  header = "time_s";
  for (int i = 0; i < nf; ++i) header += ",lacey_" + run.fractions.label(i);
  rows = NumberRows(1 + nf);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode MixingMonitor::sample(const MonitorContext &ctx) {
  PetscFunctionBeginUser;
  std::vector<LaceySums> sums(nf);
  const PetscScalar *m;
  PetscInt n;
  PetscCall(VecGetLocalSize(ctx.state.masses(), &n));
  PetscCall(VecGetArrayRead(ctx.state.masses(), &m));
  for (PetscInt c = 0; c < n / nf; ++c) {
    double solid = 0.0;
    for (int i = 0; i < nf; ++i) solid += m[c * nf + i];
    const double particles = solid / rho / meanParticleVolume; // n_c
    for (int i = 0; i < nf; ++i) sums[i].addCell(m[c * nf + i], solid, particles);
  }
  PetscCall(VecRestoreArrayRead(ctx.state.masses(), &m));
  std::vector<double> flat;
  for (const auto &s : sums) flat.insert(flat.end(), s.data(), s.data() + LaceySums::size);
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, flat.data(), static_cast<int>(flat.size()), MPI_DOUBLE, MPI_SUM, comm));
  std::vector<double> row{ctx.time};
  for (int i = 0; i < nf; ++i) {
    LaceySums total;
    std::copy(flat.begin() + i * LaceySums::size, flat.begin() + (i + 1) * LaceySums::size, total.data());
    const double p = total.data()[0] > 0.0 ? total.data()[1] / total.data()[0] : 0.0; // the fraction's share
    row.push_back(total.index(p));
  }
  rows.add(row);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode MixingMonitor::flush() {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) PetscCall(writeFileAtomically(path, rows.csv(header)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode MixingMonitor::restoreState(const std::vector<double> &state) {
  PetscFunctionBeginUser;
  PetscCheck(rows.restore(state.data(), state.size()), PETSC_COMM_SELF, PETSC_ERR_FILE_UNEXPECTED,
             "The checkpoint's mixing.csv state does not fit this run's %d fractions", nf);
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
