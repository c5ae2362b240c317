// What the granulation operators share: their zone, found by name among the
// case's zones, and the check that it ever holds solid.
#include "rcfd/granulation.hpp"
#include "base/petsc_compat.hpp"
#include "state/cell_passes.hpp"

#include <algorithm>
#include <numeric>

namespace rcfd {

PetscErrorCode ZoneOperator::readZone(PetscOptionItems *PetscOptionsObject, MPI_Comm c) {
  char text[PETSC_MAX_PATH_LEN];
  PetscBool set = PETSC_FALSE;
  PetscFunctionBeginUser;
  comm = c;
  PetscCall(PetscOptionsString("-zone", "Name of the zone (of -zones) this operator acts in", "", zoneName_.c_str(),
                               text, sizeof text, &set));
  if (set) zoneName_ = text;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ZoneOperator::setUpZone(const RunContext &ctx) {
  PetscFunctionBeginUser;
  comm = ctx.db.layout().comm();
  nf = ctx.fractions.size();
  ZoneSet zones; // the case's zones; this operator keeps its own
  PetscCall(zones.setFromOptions(comm));
  const Zone *found = zones.find(zoneName_);
  std::string known;
  for (const Zone &z : zones.all()) known += (known.empty() ? "" : ",") + z.name();
  PetscCheck(found, comm, PETSC_ERR_USER_INPUT,
             "-%szone %s names no zone of the case (-zones %s); define it with -zones ...,%s and "
             "-zone_%s_box (or _layers, _heights, _halfspace, _cylinder)",
             prefix.c_str(), zoneName_.c_str(), known.empty() ? "is not given" : known.c_str(), zoneName_.c_str(),
             zoneName_.c_str());
  zone = std::make_unique<Zone>(*found);
  PetscCall(zone->setUp(ctx.db.mesh(), ctx.db.layout(), ctx.db.metadata().gravity));
  // The frames in which the zone holds no solid.
  frames = ctx.db.numFrames();
  std::vector<int> empty(frames, 1);
  for (int k = 0; k < frames; ++k) {
    const PetscScalar *a;
    PetscCall(VecGetArrayRead(ctx.db.alphaS(k), &a));
    for (PetscInt c : zone->localCells())
      if (a[c] > 0) {
        empty[k] = 0;
        break;
      }
    PetscCall(VecRestoreArrayRead(ctx.db.alphaS(k), &a));
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, empty.data(), frames, MPI_INT, MPI_LAND, comm));
  emptyFrames_ = std::accumulate(empty.begin(), empty.end(), 0);
  PetscCheck(emptyFrames_ < frames, comm, PETSC_ERR_USER_INPUT,
             "Zone '%s' of the %s operator (%s) holds no solid in any of the database's %d frames; "
             "move it where the bed is",
             zoneName_.c_str(), type().c_str(), zone->describe().c_str(), frames);
  added.assign(nf, 0.0);
  ns = ctx.numScalars;
  addedAmount.assign(ns * nf, 0.0);
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The zone's sums cell by cell and the bed's, reduced together with what
// the zone operators before and after leave for it: one meeting.
PetscErrorCode ZoneOperator::zoneMasses(const StepInfo &step, const FractionState &state,
                                        std::vector<double> *perFraction, double *total, std::vector<double> *bed,
                                        bool needBed, bool *bedValid) {
  const PetscScalar *m;
  PetscFunctionBeginUser;
  const bool carriedIn = previous && previous->carried.pending && previous->carried.step == step.step;
  bool known = !carriedIn && knownBed(step, bed);
  const bool willKnow = carriedIn ? previous->carried.leavesBed : known;
  const bool sumBed = needBed && !willKnow;
  const bool forNext = sumsForNext && following;
  std::vector<double> sums(nf, 0.0);
  PetscCall(VecGetArrayRead(state.masses(), &m));
  for (PetscInt c : zone->localCells())
    for (int i = 0; i < nf; ++i) sums[i] += m[c * nf + i];
  if (forNext) { // the next operator's zone, as it is now (this operator leaves it alone)
    sums.resize(2 * nf, 0.0);
    for (PetscInt c : following->zone->localCells())
      for (int i = 0; i < nf; ++i) sums[nf + i] += m[c * nf + i];
  }
  PetscCall(VecRestoreArrayRead(state.masses(), &m));
  const std::size_t bedAt = sums.size();
  if (sumBed) {
    std::vector<double> own;
    PetscCall(state.localTotals(&own));
    sums.insert(sums.end(), own.begin(), own.end());
  }
  const std::size_t carriedAt = sums.size();
  if (carriedIn) sums.insert(sums.end(), previous->carried.local.begin(), previous->carried.local.end());
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums.data(), static_cast<int>(sums.size()), MPI_DOUBLE, MPI_SUM, comm));
  perFraction->assign(sums.begin(), sums.begin() + nf);
  *total = 0.0;
  for (double v : *perFraction) *total += v;
  if (forNext) {
    nextSums.assign(sums.begin() + nf, sums.begin() + 2 * nf);
    nextSumsStep = step.step;
  }
  if (sumBed) bed->assign(sums.begin() + bedAt, sums.begin() + bedAt + nf);
  if (carriedIn) { // the operator before finishes its step, and says the bed after it
    previous->carried.pending = false;
    PetscCall(previous->sumsReduced(step, sums.data() + carriedAt));
    if (willKnow) known = knownBed(step, bed);
  }
  *bedValid = known || sumBed;
  PetscFunctionReturn(PETSC_SUCCESS);
}

bool ZoneOperator::carryOn(const StepInfo &step, std::vector<double> sums, bool leavesBed) {
  if (!following) return false;
  carried.pending = true;
  carried.leavesBed = leavesBed;
  carried.step = step.step;
  carried.local = std::move(sums);
  return true;
}

PetscErrorCode ZoneOperator::sumsReduced(const StepInfo &, const double *) { return PETSC_SUCCESS; }

bool ZoneOperator::presummed(const StepInfo &step, std::vector<double> *perFraction) const {
  if (!previous || !previous->sumsForNext || previous->nextSumsStep != step.step) return false;
  *perFraction = previous->nextSums;
  return true;
}

PetscErrorCode ZoneOperator::readKeepBulk(PetscOptionItems *PetscOptionsObject) {
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsBool("-keep_bulk",
                             "Keep each zone cell's bulk and spread the change over the bed by one factor per "
                             "fraction (0: the zone's cells gain or lose the mass)",
                             "", keepBulk, &keepBulk, nullptr));
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::vector<double> ZoneOperator::bedFactors(const std::vector<double> &bed, const std::vector<double> &change,
                                             const std::vector<double> &zoneChange) {
  std::vector<double> factor(bed.size(), 1.0);
  for (std::size_t i = 0; i < bed.size(); ++i) {
    const double now = bed[i] + zoneChange[i]; // the bed's total after the zone's cells changed
    if (now > 0.0) factor[i] = std::max(0.0, bed[i] + change[i]) / now;
  }
  return factor;
}

PetscErrorCode ZoneOperator::rescaleAmounts(FractionState &state, std::vector<double> before,
                                           const std::vector<double> &zoneChange,
                                           const std::vector<double> &change, PetscInt end) const {
  PetscFunctionBeginUser;
  const int w = ns * nf;
  before.insert(before.end(), zoneChange.begin(), zoneChange.end());
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, before.data(), 2 * w, MPI_DOUBLE, MPI_SUM, comm));
  const std::vector<double> bed(before.begin(), before.begin() + w), gained(before.begin() + w, before.end());
  PetscCall(state.scaleAmounts(bedFactors(bed, change, gained), end));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ZoneOperator::scaleBed(FractionState &state, const std::vector<double> &factor, PetscInt end,
                                      const std::vector<double> *owed) const {
  PetscFunctionBeginUser;
  const bool settle = owed && !owed->empty();
  if (!settle && std::all_of(factor.begin(), factor.end(), [](double f) { return f == 1.0; })) {
    PetscCall(state.setOccupiedEnd(end));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  std::vector<double> sums(nf, 0.0); // as FractionState::localTotals adds: cell by cell
  PetscScalar *m;
  PetscCall(VecGetArray(state.masses(), &m));
  byFractions(nf, [&](auto n) {
    constexpr int N = decltype(n)::value;
    if (!settle) scaleAndSumCells<N>(nf, m, 0, end, nullptr, factor.data(), sums.data());
    else { // the owed factor first, as the pass of the operator before would have (its zone's cells have it)
      PetscInt c = 0;
      for (PetscInt z : zone->localCells()) { // ascending
        if (z >= end) break;
        scaleAndSumCells<N>(nf, m, c, z, owed->data(), factor.data(), sums.data());
        scaleAndSumCells<N>(nf, m, z, z + 1, nullptr, factor.data(), sums.data());
        c = z + 1;
      }
      scaleAndSumCells<N>(nf, m, c, end, owed->data(), factor.data(), sums.data());
    }
  });
  PetscCall(VecRestoreArray(state.masses(), &m));
  PetscCall(state.setOccupiedEnd(end)); // an empty cell stays empty
  PetscCall(state.setLocalTotals(sums));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ZoneOperator::setUpInPipeline(const std::vector<Operator *> &before) {
  PetscFunctionBeginUser;
  previous = before.empty() ? nullptr : dynamic_cast<ZoneOperator *>(before.back());
  // The ledger's totals at the step's start hold here while no operator before changes mass.
  ledgerTotals = std::all_of(before.begin(), before.end(), [](const Operator *op) { return op->conservesMass(); });
  if (!previous) PetscFunctionReturn(PETSC_SUCCESS);
  previous->following = this;
  // With scalars each operator rescales its own amounts with its masses: no rescale is handed on.
  previous->defers = settlesRescale() && previous->mayDeferRescale() && ns == 0;
  // The feed reduces the discharge's zone sums with its own when the zones share
  // no cell: its change leaves them as they are, its rescale is owed on top.
  int shared = 0;
  const std::vector<PetscInt> &a = zone->localCells(), &b = previous->zone->localCells(); // ascending
  for (std::size_t i = 0, j = 0; i < a.size() && j < b.size() && !shared;) {
    if (a[i] < b[j]) ++i;
    else if (b[j] < a[i]) ++j;
    else shared = 1;
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &shared, 1, MPI_INT, MPI_LOR, comm));
  previous->sumsForNext = previous->defers && !shared;
  PetscFunctionReturn(PETSC_SUCCESS);
}

bool ZoneOperator::knownBed(const StepInfo &step, std::vector<double> *bed) const {
  if (previous && previous->bedStep == step.step && static_cast<int>(previous->bedAfter.size()) == nf) {
    *bed = previous->bedAfter;
    return true;
  }
  if (ledgerTotals && step.expectedTotals && static_cast<int>(step.expectedTotals->size()) == nf) {
    *bed = *step.expectedTotals;
    return true;
  }
  return false;
}

void ZoneOperator::oweRescale(const StepInfo &step, const FractionState &state, std::vector<double> factor,
                              PetscInt end) {
  owed.pending = true;
  owed.step = step.step;
  owed.factor = std::move(factor);
  owed.end = end;
  owed.of = state.masses();
  PetscObjectStateGet((PetscObject)owed.of, &owed.state);
}

PetscErrorCode ZoneOperator::takeOwed(const StepInfo &step, FractionState &state, std::vector<double> *factor,
                                      PetscInt *end) {
  PetscObjectState now = 0;
  PetscFunctionBeginUser;
  factor->clear();
  if (!previous || !previous->owed.pending) PetscFunctionReturn(PETSC_SUCCESS);
  Owed &o = previous->owed;
  PetscCall(PetscObjectStateGet((PetscObject)state.masses(), &now));
  PetscCheck(o.step == step.step && o.of == state.masses() && o.state == now, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "The %s operator's rescale of the bed is owed from another step or state (step %ld, now %ld)",
             previous->type().c_str(), o.step, step.step);
  o.pending = false;
  *factor = std::move(o.factor);
  *end = o.end;
  PetscScalar *m;
  PetscCall(VecGetArray(state.masses(), &m));
  for (PetscInt c : zone->localCells()) { // as the pass below will scale the others
    if (c >= *end) break;
    for (int i = 0; i < nf; ++i) m[c * nf + i] *= (*factor)[i];
  }
  PetscCall(VecRestoreArray(state.masses(), &m));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ZoneOperator::viewZone(PetscViewer viewer, bool bulkNote) const {
  PetscFunctionBeginUser;
  if (zone)
    PetscCall(PetscViewerASCIIPrintf(viewer, "  zone %s; without solid in %d of %d frames%s\n",
                                     zone->describe().c_str(), emptyFrames_, frames,
                                     !bulkNote ? ""
                                     : keepBulk ? "; cells keep their bulk, the change spread over the bed by fraction"
                                                : "; the zone's cells take the change"));
  else PetscCall(PetscViewerASCIIPrintf(viewer, "  zone %s (not set up)\n", zoneName_.c_str()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
