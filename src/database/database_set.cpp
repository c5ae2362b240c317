// A set of databases of one bed: one mesh, one partition, loaded on demand.
#include "rcfd/database_set.hpp"
#include "base/petsc_compat.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace rcfd {
namespace {

bool sameMesh(const Mesh &a, const Mesh &b) {
  if (a.numCells() != b.numCells() || a.isBox() != b.isBox() || a.vessel() != b.vessel()) return false;
  if (!a.onBoxLattice()) return true; // readMesh reads box meshes (and vessels cut from them) only
  const BoxSpec &p = a.boxSpec(), &q = b.boxSpec();
  return p.nx == q.nx && p.ny == q.ny && p.nz == q.nz && p.origin == q.origin && p.length == q.length;
}

std::string describeMesh(const Mesh &m) {
  if (!m.onBoxLattice()) return std::to_string(m.numCells()) + " cells";
  const BoxSpec &b = m.boxSpec();
  std::ostringstream out;
  out << b.nx << " x " << b.ny << " x " << b.nz << " cells of " << b.length[0] << " x " << b.length[1] << " x "
      << b.length[2] << " m from (" << b.origin[0] << ", " << b.origin[1] << ", " << b.origin[2] << ")";
  if (m.isMasked()) out << " cut to the vessel " << m.vessel() << " (" << m.numCells() << " cells)";
  return out.str();
}

} // namespace

PetscErrorCode DatabaseSet::open(MPI_Comm comm, const std::vector<std::string> &paths,
                                 const DatabaseLoadOptions &options,
                                 const std::vector<double> &superficialVelocities,
                                 std::unique_ptr<DatabaseSet> *out) {
  PetscFunctionBeginUser;
  PetscCheck(!paths.empty(), comm, PETSC_ERR_USER_INPUT, "-db names no database file");
  PetscCheck(superficialVelocities.empty() || superficialVelocities.size() == paths.size(), comm,
             PETSC_ERR_USER_INPUT, "-db_conditions has %zu superficial velocities for the %zu databases of -db",
             superficialVelocities.size(), paths.size());
  auto set = std::make_unique<DatabaseSet>();
  set->comm = comm;
  set->options = options;
  set->options.layout = nullptr;
  std::vector<int> work;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    DatabaseHeader h;
    PetscCall(Database::readHeader(comm, paths[i], options, &h));
    DatabaseEntry e{paths[i], h.identity, h.metadata.conditions, h.numFrames, h.metadata};
    if (!superficialVelocities.empty()) e.conditions.superficialVelocity = superficialVelocities[i];
    if (i == 0) {
      set->mesh_ = std::move(h.mesh);
      work = std::move(h.work);
    } else {
      const DatabaseEntry &first = set->entries.front();
      PetscCheck(set->mesh_.vessel() == h.mesh.vessel(), comm, PETSC_ERR_USER_INPUT,
                 "Databases '%s' and '%s' are of different vessels (%s and %s); the databases of a run must share "
                 "one vessel (docs/vessels.md)",
                 first.path.c_str(), e.path.c_str(), set->mesh_.vessel().c_str(), h.mesh.vessel().c_str());
      PetscCheck(sameMesh(set->mesh_, h.mesh), comm, PETSC_ERR_USER_INPUT,
                 "Databases '%s' and '%s' are on different meshes (%s and %s); the databases of a run must share one mesh",
                 first.path.c_str(), e.path.c_str(), describeMesh(set->mesh_).c_str(), describeMesh(h.mesh).c_str());
      PetscCheck(h.metadata.dtRec == first.metadata.dtRec, comm, PETSC_ERR_USER_INPUT,
                 "Databases '%s' and '%s' were recorded with different dt_rec (%g s and %g s); the databases of a run "
                 "must share one time step",
                 first.path.c_str(), e.path.c_str(), first.metadata.dtRec, h.metadata.dtRec);
      for (std::size_t c = 0; c < work.size(); ++c) work[c] += h.work[c];
    }
    set->entries.push_back(std::move(e));
  }
  // One partition for all: the state never moves between layouts at a switch.
  PetscCall(Layout::create(comm, set->mesh_, &set->layout_, &work));
  *out = std::move(set);
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::string DatabaseSet::identity() const {
  std::string text;
  char u[40];
  for (const DatabaseEntry &e : entries) {
    std::snprintf(u, sizeof u, "%.17g", e.conditions.superficialVelocity);
    text += (text.empty() ? "" : "; ") + e.identity + " at u_sup " + u;
  }
  return text;
}

void DatabaseSet::dropUnused() {
  for (auto it = held.begin(); it != held.end();) // nobody but the set uses it
    it = it->second.use_count() == 1 ? held.erase(it) : std::next(it);
}

int DatabaseSet::numHeld() const { return static_cast<int>(held.size()); }

PetscErrorCode DatabaseSet::get(int i, std::shared_ptr<Database> *db) {
  PetscFunctionBeginUser;
  PetscCheck(i >= 0 && i < size(), comm, PETSC_ERR_ARG_OUTOFRANGE, "Database %d of a set of %d asked for", i, size());
  const auto found = held.find(i);
  if (found != held.end()) {
    *db = found->second;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  dropUnused();
  const double start = MPI_Wtime();
  DatabaseLoadOptions onLayout = options;
  onLayout.layout = &layout_;
  std::unique_ptr<Database> loaded;
  PetscCall(Database::load(comm, entries[i].path, onLayout, &loaded));
  double elapsed = MPI_Wtime() - start;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &elapsed, 1, MPI_DOUBLE, MPI_MAX, comm));
  seconds += elapsed;
  ++loads;
  held[i] = std::shared_ptr<Database>(std::move(loaded));
  peak = std::max(peak, numHeld());
  *db = held[i];
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode pairingLag(const Database &a, const Database &b, int *lag) {
  const int Ka = a.numFrames(), Kb = b.numFrames();
  std::vector<double> distance(Kb, 0.0);
  const std::vector<double> &V = a.localVolumes();
  PetscFunctionBeginUser;
  std::vector<const PetscScalar *> pa(Ka), pb(Kb);
  for (int k = 0; k < Ka; ++k) PetscCall(VecGetArrayRead(a.alphaS(k), &pa[k]));
  for (int k = 0; k < Kb; ++k) PetscCall(VecGetArrayRead(b.alphaS(k), &pb[k]));
  for (int L = 0; L < Kb; ++L)
    for (int k = 0; k < Ka; ++k) {
      const PetscScalar *x = pa[k], *y = pb[(k + L) % Kb];
      double sum = 0.0;
      for (std::size_t i = 0; i < V.size(); ++i) sum += V[i] * (x[i] - y[i]) * (x[i] - y[i]);
      distance[L] += sum;
    }
  for (int k = 0; k < Ka; ++k) PetscCall(VecRestoreArrayRead(a.alphaS(k), &pa[k]));
  for (int k = 0; k < Kb; ++k) PetscCall(VecRestoreArrayRead(b.alphaS(k), &pb[k]));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, distance.data(), Kb, MPI_DOUBLE, MPI_SUM, a.layout().comm()));
  *lag = static_cast<int>(std::min_element(distance.begin(), distance.end()) - distance.begin());
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode blendDatabases(const Database &a, const Database &b, double w, std::unique_ptr<Database> *blend,
                              int lag) {
  const MPI_Comm comm = a.layout().comm();
  PetscFunctionBeginUser;
  PetscCheck(w >= 0.0 && w <= 1.0, comm, PETSC_ERR_ARG_OUTOFRANGE, "A blend's weight must be in [0, 1], got %g", w);
  PetscCheck(lag >= 0 && lag < b.numFrames(), comm, PETSC_ERR_ARG_OUTOFRANGE,
             "A blend's frame lag must be in [0, %d), got %d", b.numFrames(), lag);
  PetscCheck(a.hasShifts() && b.hasShifts(), comm, PETSC_ERR_ARG_WRONGSTATE,
             "Blending needs both databases loaded with their shifts ('%s', '%s')", a.path().c_str(), b.path().c_str());
  PetscCheck(a.layout().numCells() == b.layout().numCells() && a.layout().rowStart() == b.layout().rowStart() &&
                 a.layout().rowEnd() == b.layout().rowEnd(),
             comm, PETSC_ERR_ARG_INCOMP, "Databases '%s' and '%s' are not on one layout; blend the databases of one set",
             a.path().c_str(), b.path().c_str());
  // As long as the shorter: with lag 0 no frame of the blend pairs the last
  // frame of one database with a frame of the other that does not follow it,
  // except the blend's own last (a wrap, which a run steps as a jump).  With a
  // lag, b wraps inside the blend: the frame where it does has no follower
  // (nextFollows), and a run steps it as a jump too.
  const int K = std::min(a.numFrames(), b.numFrames());
  std::vector<int> wrapsAfter;
  OwnedVec volume, massA, massB, mass, inverse, empty;
  PetscCall(VecDuplicate(a.alphaS(0), volume.put()));
  for (OwnedVec *v : {&massA, &massB, &mass, &inverse, &empty}) PetscCall(VecDuplicate(volume, v->put()));
  PetscScalar *pv;
  PetscCall(VecGetArrayWrite(volume, &pv));
  std::copy(a.localVolumes().begin(), a.localVolumes().end(), pv);
  PetscCall(VecRestoreArrayWrite(volume, &pv));
  std::vector<OwnedVec> alpha;
  std::vector<OwnedMat> shifts;
  for (int k = 0; k < K; ++k) {
    const int ka = k % a.numFrames(), kb = (k + lag) % b.numFrames();
    if (k + 1 < K && (!a.nextFollows(ka) || !b.nextFollows(kb))) wrapsAfter.push_back(k);
    OwnedVec blended;
    PetscCall(VecDuplicate(volume, blended.put()));
    PetscCall(VecCopy(a.alphaS(ka), blended)); // b's frame may be a's (a database blended with itself)
    PetscCall(VecScale(blended, w));
    PetscCall(VecAXPY(blended, 1.0 - w, b.alphaS(kb)));
    PetscCall(VecPointwiseMult(massA, a.alphaS(ka), volume)); // D_a: the frame's solid (per density)
    PetscCall(VecPointwiseMult(massB, b.alphaS(kb), volume));
    PetscCall(VecPointwiseMult(mass, blended, volume));
    PetscCall(VecScale(massA, w));
    PetscCall(VecScale(massB, 1.0 - w));
    OwnedMat F, fromB; // built on demand: copies the blend may change
    PetscCall(a.shiftMatrix(ka, &F));
    PetscCall(b.shiftMatrix(kb, &fromB));
    PetscCall(MatDiagonalScale(F, nullptr, massA));
    PetscCall(MatDiagonalScale(fromB, nullptr, massB));
    PetscCall(MatAXPY(F, 1.0, fromB, DIFFERENT_NONZERO_PATTERN)); // F = w T_a D_a + (1 - w) T_b D_b
    const PetscScalar *m;
    PetscScalar *inv, *e;
    PetscInt n;
    PetscCall(VecGetLocalSize(mass, &n));
    PetscCall(VecGetArrayRead(mass, &m));
    PetscCall(VecGetArrayWrite(inverse, &inv));
    PetscCall(VecGetArrayWrite(empty, &e));
    for (PetscInt i = 0; i < n; ++i) {
      inv[i] = m[i] > 0.0 ? 1.0 / m[i] : 0.0;
      e[i] = m[i] > 0.0 ? 0.0 : 1.0;
    }
    PetscCall(VecRestoreArrayWrite(empty, &e));
    PetscCall(VecRestoreArrayWrite(inverse, &inv));
    PetscCall(VecRestoreArrayRead(mass, &m));
    PetscCall(MatDiagonalScale(F, nullptr, inverse)); // T = F diag(alpha V)^-1
    PetscCall(MatSetOption(F, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE));
    PetscCall(MatDiagonalSet(F, empty, ADD_VALUES)); // a cell empty in both keeps its nothing
    alpha.push_back(std::move(blended));
    shifts.push_back(std::move(F));
  }
  char text[64];
  std::snprintf(text, sizeof text, "blend %.17g (lag %d) of ", w, lag);
  PetscCall(Database::fromFrames(a, text + a.identity() + " and " + b.identity(), std::move(alpha),
                                 std::move(shifts), blend, std::move(wrapsAfter)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
