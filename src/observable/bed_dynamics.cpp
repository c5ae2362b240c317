#include "observable/bed_dynamics.hpp"
#include "base/petsc_compat.hpp"

#include "rcfd/zone.hpp"

#include <cmath>
#include <stdexcept>

namespace rcfd {

double bedDynamics(const std::vector<double> &zCog) {
  if (zCog.empty()) throw std::invalid_argument("bed dynamics need at least one centre of gravity");
  double mean = 0.0;
  for (double z : zCog) {
    if (!std::isfinite(z)) throw std::invalid_argument("bed dynamics: a centre of gravity is not finite");
    mean += z;
  }
  mean /= static_cast<double>(zCog.size());
  double deviation = 0.0;
  for (double z : zCog) deviation += std::fabs(z - mean);
  return deviation / static_cast<double>(zCog.size());
}

double databaseDistance(double a, double b) {
  if (!(b > 0.0) || !std::isfinite(b) || !std::isfinite(a))
    throw std::invalid_argument("the database distance needs a positive, finite bed dynamics of the "
                                "second (denominator) database");
  return std::fabs(a - b) / b;
}

PetscErrorCode databaseBedCentres(const Database &db, std::vector<double> *zCog) {
  PetscFunctionBeginUser;
  int axis = 2;
  bool upward = true;
  verticalAxis(db.metadata().gravity, &axis, &upward);
  const Mesh &mesh = db.mesh();
  const auto &owned = db.layout().ownedNatural();
  const auto &volume = db.localVolumes();
  const int K = db.numFrames();
  std::vector<double> sums(2 * static_cast<std::size_t>(K), 0.0); // sum(alpha V h), sum(alpha V)
  for (int k = 0; k < K; ++k) {
    const PetscScalar *alpha;
    PetscCall(VecGetArrayRead(db.alphaS(k), &alpha));
    for (std::size_t i = 0; i < owned.size(); ++i) {
      const double h = upward ? mesh.cellCentre[owned[i]][axis] : -mesh.cellCentre[owned[i]][axis];
      sums[2 * k] += alpha[i] * volume[i] * h;
      sums[2 * k + 1] += alpha[i] * volume[i];
    }
    PetscCall(VecRestoreArrayRead(db.alphaS(k), &alpha));
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums.data(), 2 * K, MPI_DOUBLE, MPI_SUM, db.layout().comm()));
  zCog->resize(K);
  for (int k = 0; k < K; ++k) {
    PetscCheck(sums[2 * k + 1] > 0, db.layout().comm(), PETSC_ERR_FILE_UNEXPECTED,
               "Database '%s': frame %d holds no solid, so it has no centre of gravity", db.path().c_str(), k);
    (*zCog)[k] = sums[2 * k] / sums[2 * k + 1];
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
