// The drift the particle data show (issue 12): every particle's vertical
// displacement during dt relative to the mean displacement of the solid in its
// cell, averaged per size class.  The drift is tens of micrometres per frame
// against millimetres of bulk motion, so the estimate comes with a standard
// error from the spread of the per-frame means (particles in one frame move
// together; frames are closer to independent).
#pragma once

#include "analysis/particle_reference.hpp"

#include <limits>
#include <string>
#include <vector>

namespace rcfd {

class MeasuredDrift {
public:
  /// Cells of `mesh` (rcfd coordinates, z up after `axes`) define "the solid of its cell".
  MeasuredDrift(SizeClasses classes, AxisMap axes, BoxSpec mesh);

  /// The pair of snapshots `before` and `after`, dt apart [s].  Particles are
  /// matched by id; those in only one snapshot, outside the mesh, or of no class
  /// are left out.  Throws std::invalid_argument for dt <= 0.
  void add(const ParticleSnapshot &before, const ParticleSnapshot &after, double dt);

  struct ClassDrift {
    double diameter = 0.0;      ///< [m]
    double velocity = 0.0;      ///< mean drift velocity relative to the bulk, up positive [m/s]
    double standardError = 0.0; ///< of the mean, from the spread of per-frame means [m/s]
    long particles = 0;         ///< particle displacements counted
    int frames = 0;             ///< frames in which the class was seen
    double massShare = std::numeric_limits<double>::quiet_NaN(); ///< of the matched particles' mass
  };
  /// One entry per class (velocity NaN for a class never seen).
  std::vector<ClassDrift> result() const;
  int framesAdded() const { return frames; }

private:
  SizeClasses classes;
  AxisMap axes;
  BoxSpec mesh;
  int frames = 0;
  // Per class: count, sum and sum of squares of per-frame mean velocities; particles.
  std::vector<double> frameSum, frameSumSq;
  std::vector<int> frameCount;
  std::vector<long> particleCount;
  std::vector<double> classMass;
};

/// The measured drift as a table, one row per class: diameter [m], velocity
/// [m/s], standard error [m/s], particles, frames, mass share (the columns
/// of the database's /measured_drift, docs/database-format.md).
constexpr int kMeasuredDriftColumns = 6;
std::vector<double> measuredDriftTable(const std::vector<MeasuredDrift::ClassDrift> &drift);
/// Back from such a table; throws std::invalid_argument for another column count.
std::vector<MeasuredDrift::ClassDrift> measuredDriftFromTable(const std::vector<double> &rowMajor, int cols);

/// A drift law's shape: u_i = -k_d x_i with x_i = d_i^2 - d32^2 (model A) or
/// (d_i - d32)|d_i - d32| (model B).
enum class DriftLawShape { A, B };

struct DriftFit {
  double kd = 0.0;            ///< [1/(m s)]
  double standardError = 0.0; ///< of kd
  double chiSquarePerDof = 0.0;
};

/// Weighted least squares of u_i = -k_d x_i through the origin, weights
/// 1/se_i^2 (classes with se 0 or fewer than two frames are left out).
/// With relativeToBulk, x_i - sum_j s_j x_j instead (s_j the classes' mass
/// shares): the drift relative to the bulk that rcfd's face swaps realise,
/// since what the sending side lacks the bulk tops up (docs/drift.md), and
/// the form the measured velocities have (their mass-weighted mean is zero).
/// Throws std::invalid_argument when fewer than one class can be used.
DriftFit fitDriftCoefficient(const std::vector<MeasuredDrift::ClassDrift> &drift, double d32,
                             DriftLawShape shape, bool relativeToBulk = false);

} // namespace rcfd
