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
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FeedOperator::apply(const StepInfo &step, FractionState &state) {
  std::vector<double> inZone;
  double solid;
  PetscFunctionBeginUser;
  for (int i = 0; i < nf; ++i) held[i] += rate * step.dt * shares[i];
  PetscCall(zoneMasses(state.masses(), &inZone, &solid));
  if (!(solid > 0.0)) { // nowhere to put it: held back for the next step with solid in the zone
    ++heldSteps;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  // Each cell of the zone takes its share of the zone's solid; empty cells take none.
  if (keepBulk) PetscCall(rememberBulk(state));
  PetscScalar *m;
  PetscCall(VecGetArray(state.masses(), &m));
  for (PetscInt c : zone->localCells()) {
    double cellSolid = 0.0;
    for (int i = 0; i < nf; ++i) cellSolid += m[c * nf + i];
    const double share = cellSolid / solid;
    for (int i = 0; i < nf; ++i) m[c * nf + i] += held[i] * share;
  }
  PetscCall(VecRestoreArray(state.masses(), &m));
  if (keepBulk) PetscCall(restoreBulk(state, held));
  for (int i = 0; i < nf; ++i) {
    added[i] += held[i];
    held[i] = 0.0;
  }
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
  return s;
}

PetscErrorCode FeedOperator::restoreState(const std::vector<double> &s) {
  PetscFunctionBeginUser;
  PetscCheck(s.size() == static_cast<std::size_t>(2 * nf + 1), comm, PETSC_ERR_USER_INPUT,
             "The checkpoint's feed state has %zu numbers, this run needs %d (other fractions?)", s.size(), 2 * nf + 1);
  added.assign(s.begin(), s.begin() + nf);
  held.assign(s.begin() + nf, s.begin() + 2 * nf);
  heldSteps = static_cast<long>(s[2 * nf]);
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
