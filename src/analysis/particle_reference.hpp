// Reference answers from DEM particle snapshots: the numbers an rcfd run
// on a database built from the same snapshots should reproduce.
//
// - Centre of gravity, mass-weighted, of the bed and of each size class per
//   snapshot, and delta_z = z_CoG(smallest class) - z_CoG(largest class).
// - Vertical profiles of each class's solid volume fraction per mesh layer
//   (class volume in the layer / layer volume, i.e. averaged over x and y),
//   averaged over a time window.  ReferenceOptions::volume says which
//   volume a layer holds, as for rcfd build: overlap, the part of each
//   sphere between the layer's planes (the parts below and above the mesh
//   in the bottom and top layers); centre, the particles centred in it.
// - Size (mass) distribution in the bottom and top halves of the bed, split
//   at the bed's mass-median height z_med (the height of the particle at
//   which the mass counted from the bottom first reaches half the total),
//   averaged over the same window.  Overlap: each particle's mass split by
//   the part of the sphere below z_med; centre: bottom z <= z_med, top z > z_med.
// All heights are rcfd z (after the AxisMap), SI units.
#pragma once

#include "particles/cell_shares.hpp"
#include "particles/particle_dump.hpp"
#include "particles/size_classes.hpp"
#include "rcfd/mesh.hpp"

#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace rcfd {

struct ReferenceOptions {
  /// With no diameters given, the classes are clustered from the first
  /// snapshot's diameters with classes.relTol.  A later particle that fits
  /// no class is an error.
  SizeClasses classes;
  AxisMap axes;                       // file -> rcfd coordinates, z up
  std::optional<BoxSpec> profileMesh; // layers of the profiles; none: no profiles
  /// Time window [s], ends included, for the profiles and the halves.
  double windowBegin = -std::numeric_limits<double>::infinity();
  double windowEnd = std::numeric_limits<double>::infinity();
  ParticleVolume volume = ParticleVolume::Centre; // how a particle is shared among layers
};

/// Per-snapshot numbers.
struct CogSample {
  double time = 0.0;
  double zBed = 0.0;              // m
  std::vector<double> zClass;     // m, NaN for a class without particles
  double zMedian = 0.0;           // bed's mass-median height, m
  std::vector<double> lowerShare; // share of each class's mass below zMedian (see volume)
};

class ParticleReference {
public:
  explicit ParticleReference(ReferenceOptions opt);

  /// Takes one snapshot at physical time `time` [s].  Any order of times is
  /// accepted; the CSV keeps the order of the calls.
  void add(double time, const ParticleSnapshot &snap);

  const SizeClasses &classes() const { return opt.classes; }
  const std::vector<CogSample> &series() const { return samples; }
  /// z_CoG of the smallest class minus that of the largest (0 with one class).
  double deltaZ(const CogSample &s) const;

  /// Snapshots that fell inside the window.
  std::size_t windowSnapshots() const { return inWindow; }
  /// Particles (summed over window snapshots) outside the profile mesh.
  std::size_t outsideProfileMesh() const { return outsideProfile; }
  /// [class][layer]: window mean of the class's volume fraction per layer
  /// (empty when no snapshot fell in the window or there is no profile mesh).
  std::vector<std::vector<double>> profiles() const;
  /// Window means of the per-snapshot mass fractions of each class in the
  /// bottom (z <= median) and top (z > median) halves; each sums to 1
  /// (empty when no snapshot fell in the window).
  struct Halves {
    std::vector<double> bottom, top;
  };
  Halves halves() const;

  /// Header time_s,z_cog_bed_m,z_cog_d<D>mm_m,...,delta_z_m (as rcfd run's
  /// cog.csv), then one row per snapshot; delta_z is 0 with one class.
  void writeCogCsv(const std::string &path) const;
  /// `# ` line, then z,alpha_d<D>mm,...,alpha_total (layer centres).
  void writeProfilesCsv(const std::string &path) const;
  /// `# ` line, then class,diameter,bottom_mass_fraction,top_mass_fraction.
  void writeHalvesCsv(const std::string &path) const;

private:
  void accumulateWindow(const std::vector<Vec3> &pos, const std::vector<int> &cls,
                        const ParticleSnapshot &snap, double zMedian);
  /// Share of a particle (centre height z, diameter d) below zMedian.
  double shareBelow(double z, double d, double zMedian) const;

  ReferenceOptions opt;
  std::vector<CogSample> samples;
  std::size_t inWindow = 0, outsideProfile = 0;
  std::vector<std::vector<double>> profileSum; // [class][layer], summed volume fractions
  std::vector<double> bottomSum, topSum;       // summed mass fractions
};

} // namespace rcfd
