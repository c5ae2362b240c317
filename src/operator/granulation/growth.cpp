// Growth in the spray zone: mass moves from each class to the next larger
// one, shared by projected area (paper Sec. 3.4).
#include "rcfd/granulation.hpp"
#include "base/checked_options.hpp"
#include "base/petsc_compat.hpp"

#include <algorithm>
#include <numeric>

namespace rcfd {

PetscErrorCode GrowthOperator::setFromOptions(MPI_Comm c) {
  PetscBool set = PETSC_FALSE;
  char text[32] = "transfer", top[32] = "closed";
  PetscFunctionBeginUser;
  PetscOptionsBegin(c, prefix.c_str(), "Growth in the spray zone (granulation)", "rcfd");
  PetscCall(readZone(PetscOptionsObject, c));
  PetscCall(checkedReal(PetscOptionsObject, "-rate", "Granulation rate m_g over the spray zone [kg/s]", &rate,
                        kNonNegative));
  PetscCall(checkedReal(PetscOptionsObject, "-transfer_fraction",
                        "Share c of each class's growth rate that moves its mass to the next larger class",
                        &fraction, kUnitInterval));
  PetscCall(PetscOptionsString("-mass", "What moved particles weigh in the larger class: transfer (mass kept) or "
                               "number (number kept, coating added)", "", text, text, sizeof text, &set));
  PetscCall(PetscOptionsString("-top", "The largest class: closed (keeps what it receives) or open (its growth "
                               "leaves the bed as oversize)", "", top, top, sizeof top, &set));
  PetscCall(readKeepBulk(PetscOptionsObject));
  PetscOptionsEnd();
  const std::string m = text;
  PetscCheck(m == "transfer" || m == "number", c, PETSC_ERR_USER_INPUT,
             "-%smass %s is not known; use transfer (the paper: mass moves, the bulk is the database's) or number",
             prefix.c_str(), text);
  mass = m == "number" ? Mass::Number : Mass::Transfer;
  const std::string t = top;
  PetscCheck(t == "closed" || t == "open", c, PETSC_ERR_USER_INPUT,
             "-%stop %s is not known; use closed (the largest class keeps what it receives) or open (its growth "
             "leaves as oversize)", prefix.c_str(), top);
  openTop = t == "open";
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode GrowthOperator::setUp(const RunContext &ctx) {
  PetscFunctionBeginUser;
  PetscCall(setUpZone(ctx));
  diameter.resize(nf);
  for (int i = 0; i < nf; ++i) diameter[i] = ctx.fractions.diameter(i);
  std::vector<int> order(nf);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return diameter[a] < diameter[b]; });
  next.assign(nf, -1);
  for (int k = 0; k + 1 < nf; ++k) next[order[k]] = order[k + 1];
  moved.assign(nf, 0.0);
  limitedMass = missedMass = coating = oversizeMass = 0.0;
  emptySteps = 0;
  amountChange.assign(ns * nf, 0.0);
  PetscFunctionReturn(PETSC_SUCCESS);
}

// Cost: the zone's cells and two reductions (its projected area before, what
// moved after; the second one the feed's when the feed follows: carryOn); an
// open top keeping the bulk adds the bed's totals to the first (unless the
// run's ledger gives them) and a pass over the occupied cells for the bed's
// factors.  It says the bed's totals after it (leaveBed) when it knows them,
// so the feed after it need not sum the bed.
PetscErrorCode GrowthOperator::apply(const StepInfo &step, FractionState &state) {
  PetscScalar *m;
  PetscInt end;
  PetscFunctionBeginUser;
  PetscCheck(!carriedPending(), PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "What growth moved in the last step was not reduced by the operator after it");
  const bool restore = openTop && keepBulk && mass == Mass::Transfer; // number mode departs from the bulk anyway
  PetscCall(state.occupiedEnd(&end));
  std::vector<double> bed;
  const bool known = knownBed(step, &bed);
  std::vector<double> first(1, 0.0); // the sum over the zone of m_i / d_i (proportional to N_i d_i^2), the bed's totals
  if (restore && !known) {
    std::vector<double> own;
    PetscCall(state.localTotals(&own));
    first.insert(first.end(), own.begin(), own.end());
  }
  PetscCall(VecGetArray(state.masses(), &m));
  double zoneArea = 0.0; // in a register: first[0] may alias the masses for the compiler
  for (PetscInt c : zone->localCells())
    for (int i = 0; i < nf; ++i) zoneArea += m[c * nf + i] / diameter[i];
  first[0] = zoneArea;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, first.data(), static_cast<int>(first.size()), MPI_DOUBLE, MPI_SUM, comm));
  const double area = first[0];
  const double toMove = fraction * rate * step.dt;
  if (!(area > 0.0)) { // nothing in the spray zone: nothing grows this step
    PetscCall(VecRestoreArray(state.masses(), &m));
    PetscCall(state.setOccupiedEnd(end));
    missedMass += toMove;
    ++emptySteps;
    if (restore && !known) bed.assign(first.begin() + 1, first.end());
    if (known || restore) leaveBed(step, bed);
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  const double k = toMove / area;
  const auto grows = [&](int i) { return next[i] >= 0 || openTop; }; // an open top's growth leaves
  // Moved per class, the limited mass, then (restore) what the zone's cells gained, then (scalars)
  // the amount moved out of each scalar and class: a moved mass takes its class's value in the cell.
  const int w = ns * nf;
  const std::size_t amountsAt = restore ? 2 * nf + 1 : nf + 1;
  std::vector<double> sums(amountsAt + w, 0.0), out(nf), amountsBefore, zoneAmountChange(w, 0.0), cellAmounts(w);
  double *zoneChange = sums.data() + nf + 1;
  if (ns > 0 && restore) PetscCall(state.localAmountTotals(&amountsBefore));
  PetscScalar *a = nullptr;
  if (ns > 0) PetscCall(VecGetArray(state.amounts(), &a));
  for (PetscInt c : zone->localCells()) {
    PetscScalar *cell = m + c * nf;
    double bulkBefore = 0.0;
    for (int i = 0; i < nf; ++i) { // from the cell's masses before this step's transfers
      const double wanted = grows(i) ? k * cell[i] / diameter[i] : 0.0;
      out[i] = std::min(wanted, static_cast<double>(cell[i]));
      sums[nf] += wanted - out[i];
      bulkBefore += cell[i];
    }
    if (ns > 0) {
      if (restore) std::copy(a + c * w, a + c * w + w, cellAmounts.begin());
      moveAmounts(cell, out, a + c * w, sums.data() + amountsAt);
    }
    for (int i = 0; i < nf; ++i) {
      if (!grows(i)) continue;
      cell[i] -= out[i];
      sums[i] += out[i];
      if (next[i] < 0) continue; // oversize: leaves the bed
      const double ratio = diameter[next[i]] / diameter[i];
      cell[next[i]] += mass == Mass::Number ? out[i] * ratio * ratio * ratio : out[i];
    }
    if (!restore) continue;
    double bulk = 0.0; // the oversize left a hole: back to the cell's bulk, composition kept
    for (int i = 0; i < nf; ++i) bulk += cell[i];
    const double back = bulk > 0.0 ? bulkBefore / bulk : 1.0;
    for (int i = 0; i < nf; ++i) {
      const double before = cell[i];
      cell[i] *= back;
      zoneChange[i] += cell[i] - before; // the transfers within the cell sum to nothing but the oversize
    }
    for (int j = 0; j < w; ++j) { // the amounts' change in the cell: transfers, oversize and rescale
      a[c * w + j] *= back;
      zoneAmountChange[j] += a[c * w + j] - cellAmounts[j];
    }
  }
  if (ns > 0) PetscCall(VecRestoreArray(state.amounts(), &a));
  PetscCall(VecRestoreArray(state.masses(), &m));
  bedKnown = known || restore;
  if (restore && !known) bed.assign(first.begin() + 1, first.end());
  bedBefore = bed;
  if (!restore) {
    PetscCall(state.setOccupiedEnd(end)); // mass moved only within cells
    if (carryOn(step, sums, bedKnown)) PetscFunctionReturn(PETSC_SUCCESS); // the feed reduces them with its own
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums.data(), static_cast<int>(sums.size()), MPI_DOUBLE, MPI_SUM, comm));
    PetscCall(sumsReduced(step, sums.data()));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums.data(), static_cast<int>(sums.size()), MPI_DOUBLE, MPI_SUM, comm));
  const std::vector<double> change = account(sums.data(), sums.data() + amountsAt);
  if (ns > 0) PetscCall(rescaleAmounts(state, amountsBefore, zoneAmountChange, amountChange, end));
  std::vector<double> gained(nf);
  for (int i = 0; i < nf; ++i) gained[i] = change[i] + zoneChange[i]; // the transfers, then the rescale
  PetscCall(scaleBed(state, bedFactors(bed, change, gained), end));
  for (int i = 0; i < nf; ++i) bed[i] += change[i];
  leaveBed(step, bed);
  PetscFunctionReturn(PETSC_SUCCESS);
}

void GrowthOperator::moveAmounts(const PetscScalar *cell, const std::vector<double> &out, PetscScalar *amount,
                                 double *moved) {
  const int w = ns * nf;
  going.assign(w, 0.0); // from the amounts before this cell's transfers, as the masses' out
  for (int i = 0; i < nf; ++i) {
    if (!(out[i] > 0.0)) continue;
    const double q = out[i] / cell[i]; // out <= cell, so q <= 1; all of it when the class is emptied
    for (int s = 0; s < ns; ++s) going[s * nf + i] = out[i] >= cell[i] ? amount[s * nf + i] : amount[s * nf + i] * q;
  }
  for (int i = 0; i < nf; ++i) {
    if (!(out[i] > 0.0)) continue;
    const double ratio = next[i] < 0 ? 0.0 : diameter[next[i]] / diameter[i];
    for (int s = 0; s < ns; ++s) {
      const double go = going[s * nf + i];
      amount[s * nf + i] -= go;
      moved[s * nf + i] += go;
      // Number kept: the coating takes the particle's value (a source the ledger counts).
      if (next[i] >= 0) amount[s * nf + next[i]] += mass == Mass::Number ? go * ratio * ratio * ratio : go;
    }
  }
}

std::vector<double> GrowthOperator::account(const double *sums, const double *amountSums) {
  for (int s = 0; s < ns; ++s) { // the amounts moved with the mass, per scalar as per class below
    for (int i = 0; i < nf; ++i) amountChange[s * nf + i] = 0.0;
    for (int i = 0; i < nf; ++i) {
      if (!(next[i] >= 0 || openTop)) continue;
      const double go = amountSums[s * nf + i];
      amountChange[s * nf + i] -= go;
      if (next[i] < 0) continue;
      const double ratio = diameter[next[i]] / diameter[i];
      amountChange[s * nf + next[i]] += mass == Mass::Number ? go * ratio * ratio * ratio : go;
    }
  }
  for (int k = 0; k < ns * nf; ++k) addedAmount[k] += amountChange[k];
  std::vector<double> change(nf, 0.0); // this step's, per class
  for (int i = 0; i < nf; ++i) {
    if (!(next[i] >= 0 || openTop)) continue; // a closed top's own growth moves nothing
    moved[i] += sums[i];
    change[i] -= sums[i];
    if (next[i] < 0) {
      oversizeMass += sums[i];
      continue;
    }
    const double ratio = diameter[next[i]] / diameter[i], gain = ratio * ratio * ratio;
    if (mass == Mass::Number) change[next[i]] += sums[i] * gain;
    else {
      change[next[i]] += sums[i];
      coating += sums[i] * (gain - 1.0);
    }
  }
  for (int i = 0; i < nf; ++i) added[i] += change[i];
  limitedMass += sums[nf];
  return change;
}

// What moved, reduced here or by the feed after it (carryOn); the bed's totals after it when known.
PetscErrorCode GrowthOperator::sumsReduced(const StepInfo &step, const double *global) {
  PetscFunctionBeginUser;
  const std::vector<double> change = account(global, global + nf + 1);
  if (bedKnown) {
    std::vector<double> bed = bedBefore;
    for (int i = 0; i < nf; ++i) bed[i] += change[i];
    leaveBed(step, std::move(bed));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode GrowthOperator::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer,
                                   "growth: rate %g kg/s, transfer fraction %g to the next larger class, %s (%s)\n",
                                   rate, fraction, mass == Mass::Number ? "number kept" : "mass kept",
                                   mass == Mass::Number ? "coating added: the bulk departs from the database"
                                                        : "the bulk is the database's"));
  PetscCall(PetscViewerASCIIPrintf(viewer, "  top class %s\n",
                                   !openTop ? "closed: the largest class keeps what it receives"
                                   : keepBulk ? "open: the largest class's growth leaves the bed as oversize (the "
                                                "growth_ columns of mass_account.csv sum to minus the oversize); "
                                                "spray cells keep their bulk, the loss spread over the bed by fraction"
                                              : "open: the largest class's growth leaves the bed as oversize (the "
                                                "growth_ columns of mass_account.csv sum to minus the oversize); "
                                                "the spray cells lose it"));
  PetscCall(viewZone(viewer, false));
  if (moved.empty()) PetscFunctionReturn(PETSC_SUCCESS);
  double total = 0.0;
  for (double v : moved) total += v;
  PetscCall(PetscViewerASCIIPrintf(viewer,
                                   "  moved %.6g kg to larger classes; limited by a class's mass %.3g kg; missed in "
                                   "%ld steps with an empty spray zone %.3g kg; coating the moved particles imply "
                                   "%.6g kg (%s); oversize left the bed %.6g kg\n",
                                   total, limitedMass, emptySteps, missedMass, coating,
                                   mass == Mass::Number ? "added" : "not added", oversizeMass));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// State: {added..., moved..., limited, missed, coating, empty steps, oversize}.
std::vector<double> GrowthOperator::saveState() const {
  std::vector<double> s = added;
  s.insert(s.end(), moved.begin(), moved.end());
  s.insert(s.end(), {limitedMass, missedMass, coating, static_cast<double>(emptySteps), oversizeMass});
  saveAmounts(&s);
  return s;
}

PetscErrorCode GrowthOperator::restoreState(const std::vector<double> &s) {
  PetscFunctionBeginUser;
  PetscCheck(s.size() == static_cast<std::size_t>(2 * nf + 5 + ns * nf), comm, PETSC_ERR_USER_INPUT,
             "The checkpoint's growth state has %zu numbers, this run needs %d (other fractions or scalars?)", s.size(),
             2 * nf + 5 + ns * nf);
  added.assign(s.begin(), s.begin() + nf);
  moved.assign(s.begin() + nf, s.begin() + 2 * nf);
  limitedMass = s[2 * nf];
  missedMass = s[2 * nf + 1];
  coating = s[2 * nf + 2];
  emptySteps = static_cast<long>(s[2 * nf + 3]);
  oversizeMass = s[2 * nf + 4];
  restoreAmounts(s, 2 * nf + 5);
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
