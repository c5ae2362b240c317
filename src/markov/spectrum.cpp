#include "markov/spectrum.hpp"
#include "base/petsc_compat.hpp"

#include <slepceps.h>
#include <slepcsys.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace rcfd {

namespace {

// A cell is an absorbing state of the averaged chain when it keeps all its
// solid in every frame it holds some: Q(i, i) = 1 to round-off.
constexpr double kAbsorbing = 1e-12;

// SLEPc's classes need SlepcInitialize; after PetscInitialize it only loads
// SLEPc's solvers, and SlepcFinalize, called within PetscFinalize, leaves
// PETSc to it.  Whoever started PETSc (the program, a test) need not know.
PetscErrorCode startSlepc() {
  PetscBool started;
  PetscFunctionBeginUser;
  PetscCall(SlepcInitialized(&started));
  if (started) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(SlepcInitialize(nullptr, nullptr, nullptr, nullptr));
  PetscCall(PetscRegisterFinalize(SlepcFinalize));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

ChainEigensolver::~ChainEigensolver() {
  if (eps) (void)EPSDestroy(&eps);
}

PetscErrorCode ChainEigensolver::setFromOptions(MPI_Comm comm, const char *prefix) {
  PetscFunctionBeginUser;
  prefix_ = prefix;
  PetscCall(startSlepc());
  if (eps) PetscCall(EPSDestroy(&eps));
  PetscCall(EPSCreate(comm, &eps));
  PetscCall(EPSSetProblemType(eps, EPS_NHEP));
  PetscCall(EPSSetWhichEigenpairs(eps, EPS_LARGEST_MAGNITUDE));
  PetscCall(EPSSetDimensions(eps, 2, PETSC_DEFAULT, PETSC_DEFAULT));
  PetscCall(EPSSetTolerances(eps, 1e-10, PETSC_DEFAULT));
  PetscCall(EPSSetOptionsPrefix(eps, prefix));
  // The answers are the two eigenvalues largest in modulus of a matrix that
  // is not symmetric: SLEPc's spectrum slicing (an interval) is for symmetric
  // problems (SLEPc 3.18 crashed reading it for this one, so it is refused
  // before SLEPc reads it), and other eigenpairs are not what is reported as
  // lambda1 and lambda2.
  PetscBool interval = PETSC_FALSE;
  PetscCall(PetscOptionsHasName(nullptr, prefix, "-eps_interval", &interval));
  PetscCheck(!interval, comm, PETSC_ERR_USER_INPUT,
             "-%seps_interval: the chain's matrix is not symmetric, so SLEPc's spectrum slicing does not apply; "
             "rcfd markov needs its two eigenvalues largest in modulus", prefix);
  PetscCall(EPSSetFromOptions(eps));
  EPSWhich which;
  PetscCall(EPSGetWhichEigenpairs(eps, &which));
  PetscCheck(which == EPS_LARGEST_MAGNITUDE, comm, PETSC_ERR_USER_INPUT,
             "-%seps_*: rcfd markov needs the chain's eigenvalues largest in modulus (-%seps_largest_magnitude), "
             "not others", prefix, prefix);
  PetscInt nev;
  PetscCall(EPSGetDimensions(eps, &nev, &ncv_, &mpd_));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ChainEigensolver::solve(const FrameChain &chain, FrameChain::Average average, double alphaMeanMin,
                                       ChainSpectrum *out) {
  const MPI_Comm comm = chain.database().layout().comm();
  OwnedMat full, Q;
  OwnedIS cells;
  PetscFunctionBeginUser;
  PetscCheck(eps, comm, PETSC_ERR_ARG_WRONGSTATE, "ChainEigensolver::solve before setFromOptions");
  PetscCall(chain.averageChain(average, full.put()));
  {
    // Whether the mean mass share is stationary: the database's own check.
    OwnedVec moved;
    PetscCall(VecDuplicate(chain.meanShare(), moved.put()));
    PetscCall(MatMult(full, chain.meanShare(), moved));
    PetscCall(VecAXPY(moved, -1.0, chain.meanShare()));
    PetscReal r;
    PetscCall(VecNorm(moved, NORM_1, &r));
    out->residual = r;
    // The states: cells whose mean alpha_s reaches alphaMeanMin and whose
    // solid moves in some frame it is there (Q(i, i) < 1: not absorbing).
    OwnedVec diagonal;
    PetscCall(VecDuplicate(chain.meanShare(), diagonal.put()));
    PetscCall(MatGetDiagonal(full, diagonal));
    const PetscScalar *pa, *pm, *pd;
    PetscInt start, end;
    PetscCall(VecGetOwnershipRange(chain.meanAlpha(), &start, &end));
    PetscCall(VecGetArrayRead(chain.meanAlpha(), &pa));
    PetscCall(VecGetArrayRead(chain.meanShare(), &pm));
    PetscCall(VecGetArrayRead(diagonal, &pd));
    std::vector<PetscInt> rows;
    double left[3] = {0.0, 0.0, 0.0}; // share left out, absorbing cells, their share
    out->absorbingLocal.assign(end - start, 0);
    for (PetscInt i = 0; i < end - start; ++i) {
      const bool absorbing = pa[i] > 0 && pd[i] >= 1.0 - kAbsorbing;
      out->absorbingLocal[i] = absorbing;
      if (pa[i] >= alphaMeanMin && pa[i] > 0 && !absorbing) {
        rows.push_back(start + i);
        continue;
      }
      left[0] += pm[i];
      if (absorbing) left[1] += 1, left[2] += pm[i];
    }
    PetscCall(VecRestoreArrayRead(diagonal, &pd));
    PetscCall(VecRestoreArrayRead(chain.meanShare(), &pm));
    PetscCall(VecRestoreArrayRead(chain.meanAlpha(), &pa));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, left, 3, MPI_DOUBLE, MPI_SUM, comm));
    out->leftOut = left[0];
    out->absorbing = static_cast<int>(left[1]);
    out->absorbingShare = left[2];
    PetscCall(ISCreateGeneral(comm, static_cast<PetscInt>(rows.size()), rows.data(), PETSC_COPY_VALUES, cells.put()));
    PetscCall(MatCreateSubMatrix(full, cells, cells, MAT_INITIAL_MATRIX, Q.put()));
    full.reset();
  }
  PetscInt n;
  PetscCall(MatGetSize(Q, &n, nullptr));
  out->cells = static_cast<int>(n);
  PetscCheck(n > 0, comm, PETSC_ERR_USER_INPUT,
             "Database '%s': no cell has a mean alpha_s of at least %g and moving solid, so the averaged chain has no "
             "state (lower -markov_alpha_mean_min)",
             chain.database().path().c_str(), alphaMeanMin);
  LargestEigenpairs pairs;
  PetscCall(largest(Q, "the averaged chain", &pairs));
  out->lambda1 = pairs.lambda1;
  out->lambda2 = pairs.lambda2;
  out->lambda2Re = pairs.lambda2Re;
  out->lambda2Im = pairs.lambda2Im;
  out->iterations = pairs.iterations;
  out->relaxationTime = out->lambda2 > 0 && out->lambda2 < 1 ? -chain.dt() / std::log(out->lambda2)
                                                            : std::numeric_limits<double>::infinity();
  const Vec xr = pairs.first;
  {
    // Back onto all cells: the sub-matrix keeps each rank's rows of `cells`, in order.
    PetscCall(VecDuplicate(chain.meanShare(), out->stationary.put()));
    PetscCall(VecSet(out->stationary, 0.0));
    const PetscInt *rows;
    PetscInt nrows, start;
    const PetscScalar *px;
    PetscScalar *ps;
    PetscCall(ISGetLocalSize(cells, &nrows));
    PetscCall(ISGetIndices(cells, &rows));
    PetscCall(VecGetOwnershipRange(out->stationary, &start, nullptr));
    PetscCall(VecGetArrayRead(xr, &px));
    PetscCall(VecGetArray(out->stationary, &ps));
    for (PetscInt i = 0; i < nrows; ++i) ps[rows[i] - start] = px[i];
    PetscCall(VecRestoreArray(out->stationary, &ps));
    PetscCall(VecRestoreArrayRead(xr, &px));
    PetscCall(ISRestoreIndices(cells, &rows));
    PetscCall(distributionDistance(out->stationary, chain.meanShare(), &out->l1, &out->max));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode distributionDistance(Vec a, Vec b, double *l1, double *max) {
  OwnedVec diff;
  PetscReal n1, ninf;
  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(a, diff.put()));
  PetscCall(VecWAXPY(diff, -1.0, b, a));
  PetscCall(VecNorm(diff, NORM_1, &n1));
  PetscCall(VecNorm(diff, NORM_INFINITY, &ninf));
  *l1 = n1;
  *max = ninf;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ChainEigensolver::largest(Mat A, const char *what, LargestEigenpairs *out) {
  const MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(A));
  const char *prefix = prefix_.c_str();
  PetscInt n;
  PetscFunctionBeginUser;
  PetscCheck(eps, comm, PETSC_ERR_ARG_WRONGSTATE, "ChainEigensolver::largest before setFromOptions");
  PetscCall(MatGetSize(A, &n, nullptr));
  PetscCall(EPSSetOperators(eps, A, nullptr));
  // A chain of one or two states holds no larger Krylov space; the options'
  // dimensions are put back for the next chain (the solver serves several).
  if (n <= 2)
    PetscCall(EPSSetDimensions(eps, n > 1 ? 2 : 1, n, n));
  else
    PetscCall(EPSSetDimensions(eps, 2, ncv_, mpd_));
  PetscCall(EPSSolve(eps));
  PetscInt converged, its;
  PetscCall(EPSGetConverged(eps, &converged));
  PetscCall(EPSGetIterationNumber(eps, &its));
  out->iterations = static_cast<int>(its);
  PetscCheck(converged >= std::min<PetscInt>(n, 2), comm, PETSC_ERR_NOT_CONVERGED,
             "SLEPc found %d of the 2 largest eigenvalues of %s (%d cells) in %d restarts; "
             "give it more with -%seps_max_it or -%seps_ncv",
             static_cast<int>(converged), what, static_cast<int>(n), static_cast<int>(its), prefix, prefix);
  // The eigenvalue closest to 1 is the stationary one; the largest other modulus is lambda2.
  PetscInt first = 0;
  double best = std::numeric_limits<double>::infinity();
  std::vector<double> re(converged), im(converged);
  for (PetscInt i = 0; i < converged; ++i) {
    PetscScalar kr, ki;
    PetscCall(EPSGetEigenvalue(eps, i, &kr, &ki));
    re[i] = PetscRealPart(kr);
    im[i] = PetscRealPart(ki);
    const double d = std::hypot(re[i] - 1.0, im[i]);
    if (d < best) best = d, first = i;
  }
  out->lambda1 = re[first];
  out->lambda2 = 0.0;
  out->lambda2Re = out->lambda2Im = 0.0;
  for (PetscInt i = 0; i < converged; ++i)
    if (i != first && std::hypot(re[i], im[i]) > out->lambda2) {
      out->lambda2 = std::hypot(re[i], im[i]);
      out->lambda2Re = re[i];
      out->lambda2Im = im[i];
    }
  PetscCall(MatCreateVecs(A, out->first.put(), nullptr));
  PetscCall(EPSGetEigenvector(eps, first, out->first, nullptr));
  PetscScalar sum;
  PetscCall(VecSum(out->first, &sum));
  PetscCheck(std::abs(PetscRealPart(sum)) > 0, comm, PETSC_ERR_NOT_CONVERGED,
             "The eigenvector of %s's eigenvalue %g sums to 0; it is no distribution", what, out->lambda1);
  PetscCall(VecScale(out->first, 1.0 / sum));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
