// Continuous feed into the feed zone; held back while the zone is empty.
#include "rcfd/granulation.hpp"
#include "base/checked_options.hpp"
#include "base/petsc_compat.hpp"

#include <cmath>

namespace rcfd {

PetscErrorCode FeedOperator::setFromOptions(MPI_Comm c) {
  PetscReal values[kMaxFractions];
  PetscInt n = kMaxFractions;
  PetscBool set = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscOptionsBegin(c, prefix.c_str(), "Feed into the feed zone (granulation)", "rcfd");
  PetscCall(readZone(PetscOptionsObject, c));
  PetscCall(readKeepBulk(PetscOptionsObject));
  PetscCall(checkedReal(PetscOptionsObject, "-rate", "Feed rate m_f [kg/s]", &rate, kNonNegative));
  PetscCall(checkedRealArray(PetscOptionsObject, "-mass_shares",
                             "Mass shares of the feed per fraction (default: the inventory's)", values, &n,
                             &set));
  PetscOptionsEnd();
  if (set) shares.assign(values, values + n);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FeedOperator::setUp(const RunContext &ctx) {
  PetscFunctionBeginUser;
  PetscCall(setUpZone(ctx));
  if (shares.empty())
    for (int i = 0; i < nf; ++i) shares.push_back(ctx.fractions.massShare(i));
  double sum = 0.0;
  bool valid = static_cast<int>(shares.size()) == nf;
  for (double w : shares) {
    valid = valid && std::isfinite(w) && w >= 0;
    sum += w;
  }
  PetscCheck(valid && std::fabs(sum - 1.0) <= 1e-6, comm, PETSC_ERR_USER_INPUT,
             "-%smass_shares needs %d shares >= 0 (one per fraction) that sum to 1; got %zu summing to %g",
             prefix.c_str(), nf, shares.size(), sum);
  held.assign(nf, 0.0);
  heldSteps = 0;
  // The feed's values of the scalars: -feed_scalar_NAME, required for each when feeding (a
  // temperature of 0 K is no default); read here, where the names are known.
  if (ns > 0 && static_cast<int>(scalarValues.size()) != ns) {
    scalarValues.assign(ns, 0.0);
    for (int k = 0; k < ns; ++k) {
      const std::string option = "-scalar_" + (*ctx.scalarNames)[k];
      PetscBool given = PETSC_FALSE;
      PetscReal v = 0.0;
      PetscCall(PetscOptionsGetReal(nullptr, prefix.c_str(), option.c_str(), &v, &given));
      PetscCheck(given || rate == 0.0, comm, PETSC_ERR_USER_INPUT,
                 "-%sscalar_%s is not given; the feed needs the value of every scalar it brings (-scalars)",
                 prefix.c_str(), (*ctx.scalarNames)[k].c_str());
      PetscCheck(v >= 0.0 && std::isfinite(v), comm, PETSC_ERR_USER_INPUT,
                 "-%sscalar_%s %g: expected a value >= 0 (no negative or NaN values)", prefix.c_str(),
                 (*ctx.scalarNames)[k].c_str(), (double)v);
      scalarValues[k] = v;
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

// Cost: the zone's cells and one reduction (its sums; the bed's totals too
// with -keep_bulk when the run's ledger or the operator before does not give
// them; what the growth before it moved; the discharge's zone sums when it
// follows); with -keep_bulk one pass over the occupied cells for the bed's
// factors, whose sums the next reader of the totals gets for free, or none
// when the discharge after it settles the rescale in its own pass.
PetscErrorCode FeedOperator::apply(const StepInfo &step, FractionState &state) {
  std::vector<double> inZone, bed;
  double solid;
  PetscInt end;
  PetscFunctionBeginUser;
  PetscCheck(!defersRescale() || !owedPending(), PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "The feed's rescale of the last step was not settled by the discharge");
  for (int i = 0; i < nf; ++i) held[i] += rate * step.dt * shares[i];
  PetscCall(state.occupiedEnd(&end));
  bool bedValid;
  PetscCall(zoneMasses(step, state, &inZone, &solid, &bed, keepBulk, &bedValid));
  if (!(solid > 0.0)) { // nowhere to put it: held back for the next step with solid in the zone
    ++heldSteps;
    if (bedValid) leaveBed(step, bed);
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  // Each cell of the zone takes its share of the zone's solid; empty cells take none.
  // The scalars' amounts come with the fed mass at the feed's values, and are
  // scaled back to the bulk with the masses (the same coefficients).
  const int w = ns * nf;
  std::vector<double> amountsBefore, zoneAmountChange(w, 0.0), fedAmount(w);
  for (int k = 0; k < w; ++k) fedAmount[k] = held[k % nf] * scalarValues[k / nf];
  if (ns > 0 && keepBulk) PetscCall(state.localAmountTotals(&amountsBefore));
  PetscScalar *m, *a = nullptr;
  PetscCall(VecGetArray(state.masses(), &m));
  if (ns > 0) PetscCall(VecGetArray(state.amounts(), &a));
  for (PetscInt c : zone->localCells()) {
    PetscScalar *cell = m + c * nf;
    double cellSolid = 0.0;
    for (int i = 0; i < nf; ++i) cellSolid += cell[i];
    const double share = cellSolid / solid;
    for (int i = 0; i < nf; ++i) cell[i] += held[i] * share;
    double back = 1.0;
    if (keepBulk) {
      double bulk = 0.0; // back to the cell's bulk before, its new composition kept
      for (int i = 0; i < nf; ++i) bulk += cell[i];
      if (bulk > 0.0) {
        back = cellSolid / bulk;
        for (int i = 0; i < nf; ++i) cell[i] *= back;
      }
    }
    for (int k = 0; k < w; ++k) {
      PetscScalar &x = a[c * w + k];
      const double before = x;
      x = (x + fedAmount[k] * share) * back;
      zoneAmountChange[k] += x - before;
    }
  }
  PetscCall(VecRestoreArray(state.masses(), &m));
  if (ns > 0) PetscCall(VecRestoreArray(state.amounts(), &a));
  if (keepBulk) {
    // Every cell that holds solid took held * cellSolid / solid and was scaled by
    // solid / (solid + fed): the zone now holds (inZone + held) solid / (solid + fed).
    double fed = 0.0;
    for (double h : held) fed += h;
    std::vector<double> zoneChange(nf);
    for (int i = 0; i < nf; ++i) zoneChange[i] = (inZone[i] + held[i]) * (solid / (solid + fed)) - inZone[i];
    std::vector<double> factor = bedFactors(bed, held, zoneChange);
    if (defersRescale()) oweRescale(step, state, std::move(factor), end); // the discharge's pass settles it
    else PetscCall(scaleBed(state, factor, end));
  } else PetscCall(state.setOccupiedEnd(end)); // mass went only where there was some
  if (ns > 0 && keepBulk) PetscCall(rescaleAmounts(state, amountsBefore, zoneAmountChange, fedAmount, end));
  for (int k = 0; k < w; ++k) addedAmount[k] += fedAmount[k];
  for (int i = 0; i < nf; ++i) {
    added[i] += held[i];
    if (bedValid) bed[i] += held[i];
    held[i] = 0.0;
  }
  if (bedValid) leaveBed(step, bed);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FeedOperator::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  std::string list;
  char item[32];
  for (double w : shares) {
    std::snprintf(item, sizeof item, "%s%.4g", list.empty() ? "" : ",", w);
    list += item;
  }
  PetscCall(PetscViewerASCIIPrintf(viewer, "feed: %g kg/s, mass shares %s\n", rate, list.c_str()));
  PetscCall(viewZone(viewer, true));
  if (added.empty()) PetscFunctionReturn(PETSC_SUCCESS);
  double in = 0.0, back = 0.0;
  for (int i = 0; i < nf; ++i) in += added[i], back += held[i];
  PetscCall(PetscViewerASCIIPrintf(viewer, "  delivered %.6g kg; held back in %ld steps with an empty zone, %.3g kg "
                                           "still to deliver\n", in, heldSteps, back));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// State: {added..., held..., held steps}.
std::vector<double> FeedOperator::saveState() const {
  std::vector<double> s = added;
  s.insert(s.end(), held.begin(), held.end());
  s.push_back(static_cast<double>(heldSteps));
  saveAmounts(&s);
  return s;
}

PetscErrorCode FeedOperator::restoreState(const std::vector<double> &s) {
  PetscFunctionBeginUser;
  PetscCheck(s.size() == static_cast<std::size_t>(2 * nf + 1 + ns * nf), comm, PETSC_ERR_USER_INPUT,
             "The checkpoint's feed state has %zu numbers, this run needs %d (other fractions or scalars?)", s.size(),
             2 * nf + 1 + ns * nf);
  added.assign(s.begin(), s.begin() + nf);
  held.assign(s.begin() + nf, s.begin() + 2 * nf);
  heldSteps = static_cast<long>(s[2 * nf]);
  restoreAmounts(s, 2 * nf + 1);
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
