// Options shared by the commands that read particle snapshots (build,
// reference): which files, their times, the axes, the mesh, the window.
#pragma once

#include "builders/particles/particle_builder.hpp"
#include "builders/particles/snapshot_series.hpp"
#include "rcfd/handle.hpp"
#include "base/constants.hpp"

#include <limits>
#include <string>
#include <vector>

namespace rcfd::cli {

struct ParticleInput {
  // As given on the command line.
  std::string dumps, dumpList, timesFile;
  double dumpDt = 0.0;
  int verticalAxis = 2, gravitySign = -1;
  MeshRequest mesh;
  int stride = 1;
  std::size_t first = 0, last = std::numeric_limits<std::size_t>::max();
  double solidDensity = kDefaultSolidDensity;
  double classTolerance = 0.01;
  ParticleVolume volume = ParticleVolume::Centre; // docs/validation.md: why not overlap by default

  // Filled by resolve() (rank 0 only): all files in time order, one time each.
  std::vector<std::string> files;
  std::vector<double> times;

  AxisMap axes() const { return AxisMap::verticalUp(verticalAxis, gravitySign); }
  /// Stride, window, axes and density for ParticleFrameBuilder; the mesh is
  /// set by the caller once it is resolved.
  ParticleBuildOptions buildOptions() const;
  /// Indices of the files the stride and window select.
  std::vector<std::size_t> selected() const { return selectSnapshots(files.size(), buildOptions()); }
  /// "dumps 'dir/dump.*.gz'" or "list 'FILE'", for messages and metadata.
  std::string origin() const;
  /// Lists the files and reads (or makes) their times; throws naming the fault.
  void resolve();
};

/// Reads -dumps, -dump_list, -times, -dump_dt, -vertical_axis, -gravity_sign,
/// -mesh_cells, -mesh_cell_size, -mesh_lo, -mesh_hi, -frame_stride, -window,
/// -solid_density, -class_tolerance and -particle_volume (collective).
PetscErrorCode readParticleInputOptions(MPI_Comm comm, ParticleInput *in);

} // namespace rcfd::cli
