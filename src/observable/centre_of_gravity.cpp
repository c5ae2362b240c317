#include "rcfd/observables.hpp"

#include <cmath>

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
  for (PetscInt c : db.layout().ownedNatural()) {
    const Vec3 &x = db.mesh().cellCentre[c];
    height.push_back(-(g[0] * x[0] + g[1] * x[1] + g[2] * x[2]) / gn);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode CentreOfGravity::measure(double time, Vec masses, BedSample *s) const {
  PetscFunctionBeginUser;
  const PetscScalar *m;
  // [mass_0..mass_nf-1, moment_0..moment_nf-1]
  std::vector<double> sums(2 * nf, 0.0);
  PetscCall(VecGetArrayRead(masses, &m));
  for (size_t c = 0; c < height.size(); ++c)
    for (int i = 0; i < nf; ++i) {
      sums[i] += m[c * nf + i];
      sums[nf + i] += m[c * nf + i] * height[c];
    }
  PetscCall(VecRestoreArrayRead(masses, &m));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums.data(), 2 * nf, MPI_DOUBLE, MPI_SUM, comm));
  s->time = time;
  s->mass.assign(sums.begin(), sums.begin() + nf);
  s->zCog.resize(nf);
  double total = 0.0, moment = 0.0;
  for (int i = 0; i < nf; ++i) {
    s->zCog[i] = sums[i] > 0 ? sums[nf + i] / sums[i] : 0.0;
    total += sums[i];
    moment += sums[nf + i];
  }
  s->zCogBed = total > 0 ? moment / total : 0.0;
  s->deltaZ = s->zCog[small] - s->zCog[large];
  PetscCall(VecMin(masses, nullptr, &s->minMass));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
