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
  std::string header = "time_s";
  for (int i = 0; i < nf; ++i) header += ",lacey_" + run.fractions.label(i);
  csv = std::make_unique<CsvSeries>(comm, dir + "/mixing.csv", header);
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
  PetscCall(csv->add(formatNumberRow(row)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode MixingMonitor::flush() { return csv->flush(); }

PetscErrorCode MixingMonitor::restoreState(const std::vector<double> &state) {
  PetscFunctionBeginUser;
  if (state.empty()) PetscFunctionReturn(PETSC_SUCCESS); // not in the checkpoint's run: starts anew
  PetscCheck(state.size() == 1, PETSC_COMM_SELF, PETSC_ERR_FILE_UNEXPECTED,
             "The checkpoint's mixing.csv state holds %zu numbers, expected 1 (the file's length)", state.size());
  PetscCall(csv->resume(state[0]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
