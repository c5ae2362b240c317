// A time series of particle snapshot files: finding the files, pairing them
// with physical times, and the mesh box and size classes they imply.
// Serial and PETSc-free; every fault throws std::runtime_error (or
// std::invalid_argument for bad arguments) with one sentence naming the file.
#pragma once

#include "particles/cell_shares.hpp"
#include "particles/particle_dump.hpp"
#include "particles/size_classes.hpp"
#include "rcfd/mesh.hpp"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace rcfd {

/// Files matching a shell glob pattern (e.g. "dump/dump.*.gz"), in natural
/// order: runs of digits compare as numbers, so dump.9 comes before dump.10.
/// Throws when nothing matches.
std::vector<std::string> globSnapshotFiles(const std::string &pattern);

/// A list file: one snapshot path a line, in time order; blank lines and
/// lines starting with '#' are skipped.  Relative paths are taken relative to
/// the list file's directory.  Throws when the list is empty.
std::vector<std::string> readSnapshotList(const std::string &path);

/// The time between consecutive snapshots of `selected` (indices into
/// `times`), which must be equally spaced within 1e-3 of the interval and
/// increasing; throws otherwise.  Needs at least two snapshots.
double uniformInterval(const std::vector<double> &times, const std::vector<std::size_t> &selected);

/// How to lay a box mesh over the particles, in rcfd coordinates (after the
/// AxisMap).  Missing bounds come from the snapshot's box; the cells come
/// from `cells` or else from `cellSize` (each count rounded to the nearest
/// integer, at least 1).
struct MeshRequest {
  std::optional<std::array<int, 3>> cells;
  double cellSize = 0.0; // m; used when cells is not given
  std::optional<Vec3> lo, hi;
};

/// The box mesh a request asks for; a snapshot without BOX BOUNDS needs
/// explicit bounds.  Throws naming what is missing or inconsistent.
BoxSpec resolveMesh(const MeshRequest &request, const ParticleSnapshot &first, const AxisMap &axes);

/// Masses [kg] of each size class per cell, [cell * classes + class], in
/// natural cell order, each particle's mass shared among its cells by `rule`
/// (as the database's alpha_s).  Particles whose centre is outside the mesh
/// are counted in *outside (may be null) and left out; a particle that fits
/// no class throws.
std::vector<double> classMassesPerCell(const ParticleSnapshot &snap, const AxisMap &axes,
                                       const BoxSpec &mesh, const SizeClasses &classes,
                                       ParticleVolume rule, std::size_t *outside);

} // namespace rcfd
