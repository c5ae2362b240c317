// Continuous discharge from the discharge zone at its local concentrations;
// never more than the zone holds.
#include "rcfd/granulation.hpp"
#include "base/checked_options.hpp"
#include "base/petsc_compat.hpp"
#include "operator/granulation/product_monitor.hpp"

#include <algorithm>
#include <cmath>

namespace rcfd {

PetscErrorCode DischargeOperator::setFromOptions(MPI_Comm c) {
  PetscFunctionBeginUser;
  PetscOptionsBegin(c, prefix.c_str(), "Discharge from the discharge zone (granulation)", "rcfd");
  PetscCall(readZone(PetscOptionsObject, c));
  PetscCall(readKeepBulk(PetscOptionsObject));
  PetscCall(checkedReal(PetscOptionsObject, "-rate", "Discharge rate [kg/s] (the feed's for a steady holdup)", &rate,
                        kNonNegative));
  PetscCall(checkedReal(PetscOptionsObject, "-sample_interval", "Simulated time between rows of product.csv [s]",
                        &interval, kPositive));
  PetscCall(checkedReal(PetscOptionsObject, "-steady_tolerance",
                        "Steady product: L1 change of its size distribution per residence time below this",
                        &tolerance, kPositive));
  PetscOptionsEnd();
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode DischargeOperator::setUp(const RunContext &ctx) {
  PetscFunctionBeginUser;
  PetscCall(setUpZone(ctx));
  owedMass = 0.0;
  limitedCount = emptySteps = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

// Cost: the zone's cells and one reduction (its sums; the bed's totals too
// with -keep_bulk when the run's ledger or the operator before does not give
// them), none when the feed just before reduced its zone's sums; with -keep_bulk one pass over the occupied cells for the bed's
// factors (none when the zone was emptied: they are 1), which also settles the
// feed's rescale when the feed runs just before.  What leaves is known from
// the zone's sums: share * inZone, or all of it.
PetscErrorCode DischargeOperator::apply(const StepInfo &step, FractionState &state) {
  std::vector<double> inZone, bed, owedFactor;
  double solid;
  PetscInt end;
  PetscFunctionBeginUser;
  const double wanted = rate * step.dt + owedMass;
  PetscCall(state.occupiedEnd(&end));
  PetscCall(takeOwed(step, state, &owedFactor, &end)); // the feed's rescale, its zone's cells scaled now
  bool bedValid = false;
  if (presummed(step, &inZone) && ((bedValid = knownBed(step, &bed)) || !keepBulk)) {
    // The feed reduced this zone's sums with its own: no meeting; its rescale on top.
    solid = 0.0;
    for (int i = 0; i < nf; ++i) solid += (inZone[i] *= owedFactor.empty() ? 1.0 : owedFactor[i]);
  } else PetscCall(zoneMasses(step, state, &inZone, &solid, &bed, keepBulk, &bedValid));
  std::vector<double> factor(nf, 1.0), change(nf, 0.0);
  if (!(solid > 0.0)) { // nothing to take: owed
    owedMass = wanted;
    ++emptySteps;
  } else {
    const bool all = wanted >= solid; // the limit: the zone is emptied, the rest owed
    const double share = all ? 1.0 : wanted / solid;
    owedMass = all ? wanted - solid : 0.0;
    limitedCount += all;
    // The scalars leave with the mass at the cell's values (the same share), and
    // are scaled back to the bulk with the masses.
    const int w = ns * nf;
    std::vector<double> amountsBefore, zoneAmountChange(w, 0.0), left(w, 0.0);
    if (ns > 0 && keepBulk) PetscCall(state.localAmountTotals(&amountsBefore));
    PetscScalar *m, *a = nullptr;
    PetscCall(VecGetArray(state.masses(), &m));
    if (ns > 0) PetscCall(VecGetArray(state.amounts(), &a));
    for (PetscInt c : zone->localCells()) {
      PetscScalar *cell = m + c * nf;
      double bulkBefore = 0.0;
      for (int i = 0; i < nf; ++i) {
        bulkBefore += cell[i];
        cell[i] = all ? 0.0 : cell[i] - cell[i] * share; // never negative
      }
      double back = 1.0;
      if (keepBulk && !all) { // an emptied cell stays empty
        double bulk = 0.0; // back to the cell's bulk before: its composition is kept
        for (int i = 0; i < nf; ++i) bulk += cell[i];
        if (bulk > 0.0) {
          back = bulkBefore / bulk;
          for (int i = 0; i < nf; ++i) cell[i] *= back;
        }
      }
      for (int k = 0; k < w; ++k) {
        PetscScalar &x = a[c * w + k];
        const double before = x, leaving = all ? before : before * share;
        left[k] += leaving;
        x = all ? 0.0 : (x - leaving) * back;
        zoneAmountChange[k] += x - before;
      }
    }
    PetscCall(VecRestoreArray(state.masses(), &m));
    if (ns > 0) {
      PetscCall(VecRestoreArray(state.amounts(), &a));
      PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, left.data(), w, MPI_DOUBLE, MPI_SUM, comm));
      for (int k = 0; k < w; ++k) left[k] = -left[k], addedAmount[k] += left[k];
      if (keepBulk) PetscCall(rescaleAmounts(state, amountsBefore, zoneAmountChange, left, end));
    }
    for (int i = 0; i < nf; ++i) change[i] = -(all ? inZone[i] : inZone[i] * share);
    if (keepBulk) { // the zone keeps its masses (scaled back), or is emptied
      std::vector<double> zoneChange(nf, 0.0);
      if (all) zoneChange = change;
      factor = bedFactors(bed, change, zoneChange);
    }
  }
  if (keepBulk || !owedFactor.empty()) PetscCall(scaleBed(state, factor, end, &owedFactor));
  else PetscCall(state.setOccupiedEnd(end));
  for (int i = 0; i < nf; ++i) {
    added[i] += change[i];
    if (bedValid) bed[i] += change[i];
  }
  if (bedValid) leaveBed(step, bed);
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::vector<double> DischargeOperator::dischargedAmounts() const {
  std::vector<double> out(addedAmount.size());
  std::transform(addedAmount.begin(), addedAmount.end(), out.begin(), [](double a) { return -a; });
  return out;
}

std::vector<double> DischargeOperator::discharged() const {
  std::vector<double> out(added.size());
  std::transform(added.begin(), added.end(), out.begin(), [](double a) { return -a; });
  return out;
}

PetscErrorCode DischargeOperator::monitors(const RunContext &ctx, std::vector<OperatorMonitor> *list) {
  PetscFunctionBeginUser;
  const long every = std::max(1L, std::lround(interval / ctx.db.metadata().dtRec));
  list->push_back({std::make_unique<ProductMonitor>(*this), every, "product.csv"});
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode DischargeOperator::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer, "discharge: %g kg/s at the zone's local concentrations; product.csv every "
                                           "%g s, steady below an L1 change of %g per residence time\n",
                                   rate, interval, tolerance));
  PetscCall(viewZone(viewer, true));
  if (added.empty()) PetscFunctionReturn(PETSC_SUCCESS);
  double out = 0.0;
  for (double a : added) out -= a;
  PetscCall(PetscViewerASCIIPrintf(viewer, "  discharged %.6g kg; the zone held less than asked in %ld steps and "
                                           "nothing in %ld; %.3g kg still owed\n",
                                   out, limitedCount, emptySteps, owedMass));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// State: {added..., owed, limited steps, empty steps}.
std::vector<double> DischargeOperator::saveState() const {
  std::vector<double> s = added;
  s.insert(s.end(), {owedMass, static_cast<double>(limitedCount), static_cast<double>(emptySteps)});
  saveAmounts(&s);
  return s;
}

PetscErrorCode DischargeOperator::restoreState(const std::vector<double> &s) {
  PetscFunctionBeginUser;
  PetscCheck(s.size() == static_cast<std::size_t>(nf + 3 + ns * nf), comm, PETSC_ERR_USER_INPUT,
             "The checkpoint's discharge state has %zu numbers, this run needs %d (other fractions or scalars?)",
             s.size(), nf + 3 + ns * nf);
  added.assign(s.begin(), s.begin() + nf);
  owedMass = s[nf];
  limitedCount = static_cast<long>(s[nf + 1]);
  emptySteps = static_cast<long>(s[nf + 2]);
  restoreAmounts(s, nf + 3);
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
