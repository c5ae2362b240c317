// Several databases of one bed in one run (docs/databases.md): recorded at
// different operating conditions on the same mesh, sharing one partition, and
// loaded only while the run uses them.
//
//   std::unique_ptr<DatabaseSet> set;
//   DatabaseSet::open(comm, {"slow.h5", "fast.h5"}, loadOptions, {}, &set);
//   std::shared_ptr<Database> db;
//   set->get(1, &db);                 // loaded onto set->layout() now
#pragma once

#include "rcfd/database.hpp"

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace rcfd {

/// One database of a set, as its header describes it.
struct DatabaseEntry {
  std::string path, identity;
  OperatingConditions conditions; ///< recorded in the file, or given by -db_conditions
  int numFrames = 0;
  DatabaseMetadata metadata;
};

class DatabaseSet {
public:
  /// Collective.  Reads the headers of `paths` and partitions the mesh once,
  /// by the work per cell summed over the databases.  Refuses, with one
  /// sentence naming both files, a database of another mesh or another dt_rec
  /// than the first; the numbers of frames may differ (a run takes the path's
  /// frame k modulo each database's length).  `superficialVelocities`
  /// (empty, or one per file) replaces the recorded u_sup.
  static PetscErrorCode open(MPI_Comm comm, const std::vector<std::string> &paths,
                             const DatabaseLoadOptions &options,
                             const std::vector<double> &superficialVelocities,
                             std::unique_ptr<DatabaseSet> *set);

  int size() const { return static_cast<int>(entries.size()); }
  const DatabaseEntry &entry(int i) const { return entries.at(i); }
  const Mesh &mesh() const { return mesh_; }
  const Layout &layout() const { return layout_; }
  /// Names, identities and conditions of every database, in order (a checkpoint records it).
  std::string identity() const;

  /// Collective.  Database i on the set's layout; read from its file unless it
  /// is held.  Memory policy: the set holds a database only while somebody
  /// else holds it too -- loading one drops every other that nobody uses, so
  /// a run holds what it uses now (docs/databases.md, "Memory").
  PetscErrorCode get(int i, std::shared_ptr<Database> *db);
  /// Drops every held database nobody else holds (after a switch).
  void dropUnused();
  /// Databases held now, the most held at once so far, and the loads so far
  /// with their wall time [s].
  int numHeld() const;
  int maxHeld() const { return peak; }
  int numLoads() const { return loads; }
  double loadSeconds() const { return seconds; }

private:
  MPI_Comm comm = MPI_COMM_NULL;
  DatabaseLoadOptions options;
  std::vector<DatabaseEntry> entries;
  Mesh mesh_;
  Layout layout_;
  std::map<int, std::shared_ptr<Database>> held;
  int loads = 0, peak = 0;
  double seconds = 0.0;
};

/// Collective.  The blend of databases a (weight w) and b (1 - w) on one
/// layout, as many frames as the shorter has, frame k of a paired with frame
/// (k + lag) mod K_b of b, combined as mass fluxes, not as matrices:
///   F = w T_a D_a + (1 - w) T_b D_b,  D = diag(alpha V) of the frame,
///   alpha = w alpha_a + (1 - w) alpha_b,  T = F diag(alpha V)^-1,
/// so T is column-stochastic and T alpha_k V = alpha_{k+1} V whenever a and b
/// are consistent (docs/databases.md, "Blend").  A cell empty in both keeps an
/// identity column.  Where b wraps inside the blend (a lag: the frame k =
/// K_b - 1 - lag), the blend's frame k + 1 does not follow k (nextFollows).
PetscErrorCode blendDatabases(const Database &a, const Database &b, double w, std::unique_ptr<Database> *blend,
                              int lag = 0);

/// Collective.  The lag L that pairs the frames of a and b by recurrence
/// similarity: the one that minimises sum_k sum_cells V (alpha_a,k -
/// alpha_b,(k+L) mod K_b)^2 (the smallest L of a tie).  One lag for all frames,
/// so that paired frames follow each other in both databases and the blend
/// stays consistent; a per-frame choice would not.  Costs K_a K_b cell passes.
PetscErrorCode pairingLag(const Database &a, const Database &b, int *lag);

} // namespace rcfd
