// What the granulation operators share: their zone, found by name among the
// case's zones, and the check that it ever holds solid.
#include "rcfd/granulation.hpp"
#include "base/petsc_compat.hpp"

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
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ZoneOperator::zoneMasses(Vec masses, std::vector<double> *perFraction, double *total) const {
  const PetscScalar *m;
  PetscFunctionBeginUser;
  perFraction->assign(nf, 0.0);
  PetscCall(VecGetArrayRead(masses, &m));
  for (PetscInt c : zone->localCells())
    for (int i = 0; i < nf; ++i) (*perFraction)[i] += m[c * nf + i];
  PetscCall(VecRestoreArrayRead(masses, &m));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, perFraction->data(), nf, MPI_DOUBLE, MPI_SUM, comm));
  *total = 0.0;
  for (double v : *perFraction) *total += v;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ZoneOperator::readKeepBulk(PetscOptionItems *PetscOptionsObject) {
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsBool("-keep_bulk",
                             "Keep each zone cell's bulk and spread the change over the bed by one factor per "
                             "fraction (0: the zone's cells gain or lose the mass)",
                             "", keepBulk, &keepBulk, nullptr));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ZoneOperator::rememberBulk(const FractionState &state) {
  const PetscScalar *m;
  PetscFunctionBeginUser;
  PetscCall(state.totals(&totalsBefore));
  cellBulkBefore.assign(zone->localCells().size(), 0.0);
  PetscCall(VecGetArrayRead(state.masses(), &m));
  for (std::size_t k = 0; k < zone->localCells().size(); ++k)
    for (int i = 0; i < nf; ++i) cellBulkBefore[k] += m[zone->localCells()[k] * nf + i];
  PetscCall(VecRestoreArrayRead(state.masses(), &m));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ZoneOperator::restoreBulk(FractionState &state, const std::vector<double> &change) const {
  PetscScalar *m;
  PetscInt n;
  std::vector<double> now;
  PetscFunctionBeginUser;
  PetscCall(VecGetArray(state.masses(), &m));
  for (std::size_t k = 0; k < zone->localCells().size(); ++k) {
    PetscScalar *cell = m + zone->localCells()[k] * nf;
    double bulk = 0.0;
    for (int i = 0; i < nf; ++i) bulk += cell[i];
    if (bulk > 0.0)
      for (int i = 0; i < nf; ++i) cell[i] *= cellBulkBefore[k] / bulk;
  }
  PetscCall(VecRestoreArray(state.masses(), &m));
  PetscCall(state.totals(&now));
  std::vector<double> factor(nf, 1.0);
  for (int i = 0; i < nf; ++i)
    if (now[i] > 0.0) factor[i] = std::max(0.0, totalsBefore[i] + change[i]) / now[i];
  PetscCall(VecGetLocalSize(state.masses(), &n));
  PetscCall(VecGetArray(state.masses(), &m));
  for (PetscInt c = 0; c < n; c += nf)
    for (int i = 0; i < nf; ++i) m[c + i] *= factor[i];
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
