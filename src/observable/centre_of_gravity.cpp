#include "rcfd/observables.hpp"
#include "base/petsc_compat.hpp"

#include <cmath>
#include <limits>

namespace rcfd {

PetscErrorCode CentreOfGravity::setUp(const Database &db, const FractionSet &fractions) {
  PetscFunctionBeginUser;
  comm = db.layout().comm();
  nf = fractions.size();
  small = fractions.smallest();
  large = fractions.largest();
  const Vec3 g = db.metadata().gravity;
  const double gn = std::hypot(g[0], g[1], g[2]);
  height.clear();
  volume = db.localVolumes();
  for (PetscInt c : db.layout().ownedNatural()) {
    const Vec3 &x = db.mesh().cellCentre[c];
    height.push_back(-(g[0] * x[0] + g[1] * x[1] + g[2] * x[2]) / gn);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

namespace {

// One pass over this rank's cells: per fraction the mass and its first
// moment, the absolute bulk mismatch against the database, the database
// bulk, and the smallest mass.  NF > 0 fixes the number of fractions at
// compile time so that the sums stay in registers (the monitor runs every
// step by default and was as costly as the step itself).
template <int NF>
void accumulate(const PetscScalar *m, const PetscScalar *a, const std::vector<double> &height,
                const std::vector<double> &volume, double rho, int nfRuntime, double *sums,
                double *lowest) {
  const int nf = NF > 0 ? NF : nfRuntime;
  constexpr int cap = NF > 0 ? NF : 1;
  // Separate accumulators per fraction: a single running minimum chained
  // every load through one register and took half of the pass.
  double mass[cap] = {}, moment[cap] = {}, low[cap];
  for (int i = 0; i < cap; ++i) low[i] = *lowest;
  double mismatch = 0.0, bulkExpected = 0.0;
  for (size_t c = 0; c < height.size(); ++c) {
    const PetscScalar *mc = m + c * nf;
    double bulk = 0.0;
    for (int i = 0; i < nf; ++i) {
      low[i % cap] = mc[i] < low[i % cap] ? mc[i] : low[i % cap];
      if constexpr (NF > 0) {
        mass[i] += mc[i];
        moment[i] += mc[i] * height[c];
      } else {
        sums[i] += mc[i];
        sums[nf + i] += mc[i] * height[c];
      }
      bulk += mc[i];
    }
    const double expected = rho * a[c] * volume[c];
    mismatch += std::fabs(bulk - expected);
    bulkExpected += expected;
  }
  if constexpr (NF > 0)
    for (int i = 0; i < NF; ++i) sums[i] = mass[i], sums[NF + i] = moment[i];
  sums[2 * nf] = mismatch;
  sums[2 * nf + 1] = bulkExpected;
  for (int i = 0; i < cap; ++i) *lowest = low[i] < *lowest ? low[i] : *lowest;
}

} // namespace

PetscErrorCode CentreOfGravity::measure(double time, Vec masses, Vec alpha, double rho,
                                        BedSample *s) const {
  PetscFunctionBeginUser;
  const PetscScalar *m, *a;
  // [mass_0..mass_nf-1, moment_0..moment_nf-1, |bulk mismatch|, database bulk]
  std::vector<double> sums(2 * nf + 2, 0.0);
  double lowest = PETSC_MAX_REAL;
  PetscCall(VecGetArrayRead(masses, &m));
  PetscCall(VecGetArrayRead(alpha, &a));
  switch (nf) {
  case 1: accumulate<1>(m, a, height, volume, rho, nf, sums.data(), &lowest); break;
  case 2: accumulate<2>(m, a, height, volume, rho, nf, sums.data(), &lowest); break;
  case 3: accumulate<3>(m, a, height, volume, rho, nf, sums.data(), &lowest); break;
  case 4: accumulate<4>(m, a, height, volume, rho, nf, sums.data(), &lowest); break;
  case 5: accumulate<5>(m, a, height, volume, rho, nf, sums.data(), &lowest); break;
  default: accumulate<0>(m, a, height, volume, rho, nf, sums.data(), &lowest); break;
  }
  PetscCall(VecRestoreArrayRead(alpha, &a));
  PetscCall(VecRestoreArrayRead(masses, &m));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums.data(), 2 * nf + 2, MPI_DOUBLE, MPI_SUM, comm));
  s->bulkMismatch = sums[2 * nf + 1] > 0 ? sums[2 * nf] / sums[2 * nf + 1] : 0.0;
  s->time = time;
  s->mass.assign(sums.begin(), sums.begin() + nf);
  s->zCog.resize(nf);
  // A fraction without mass has no centre of gravity: NaN, not a height of 0 m
  // that would read as "at the bottom" and make delta z meaningless.
  const double none = std::numeric_limits<double>::quiet_NaN();
  double total = 0.0, moment = 0.0;
  for (int i = 0; i < nf; ++i) {
    s->zCog[i] = sums[i] > 0 ? sums[nf + i] / sums[i] : none;
    total += sums[i];
    moment += sums[nf + i];
  }
  s->zCogBed = total > 0 ? moment / total : none;
  s->deltaZ = s->zCog[small] - s->zCog[large];
  PetscCallMPI(MPI_Allreduce(&lowest, &s->minMass, 1, MPI_DOUBLE, MPI_MIN, comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
