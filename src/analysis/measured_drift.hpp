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

class SizeLaw;
/// A particle seen in two snapshots: its cell and class at the first, its
/// mass, its vertical displacement [m] and whether it is in another cell (or
/// outside the mesh) at the second.
struct MatchedParticle {
  int cell, cls;
  double mass, dz;
  bool left;
};
/// The particles of `before` matched by id in `after` (rcfd coordinates
/// after `axes`, cells of `mesh`); those in only one snapshot, outside the
/// mesh at `before` or of no class are left out.
std::vector<MatchedParticle> matchParticles(const ParticleSnapshot &before, const ParticleSnapshot &after,
                                            const SizeClasses &classes, const AxisMap &axes, const BoxSpec &mesh);

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

  /// The same by the agitation of the particle's cell: the share of the
  /// matched solid mass of the cell that is in another cell (or outside)
  /// after dt, which is 1 - T[i,i] of the shift counted by centre.  Bins of
  /// width 1/kAgitationBins; per bin and class, like result(), with the
  /// mass-weighted mean agitation of the bin.
  static constexpr int kAgitationBins = 10;
  struct BinDrift {
    double agitation = 0.0; ///< mass-weighted mean leaving share of the bin's particles [-]
    ClassDrift drift;
  };
  /// kAgitationBins x classes entries, bin-major.
  std::vector<BinDrift> byAgitation() const;
  /// Mass-weighted mean leaving share of all matched particles (a bar) [-].
  double meanAgitation() const { return agitationMass > 0.0 ? agitationSum / agitationMass : 0.0; }
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
  // Per (bin, class): the same sums; per bin: sum m a and sum m.
  std::vector<double> binFrameSum, binFrameSumSq, binClassMass;
  std::vector<int> binFrameCount;
  std::vector<long> binParticles;
  std::vector<double> binAgitationSum, binMass;
  double agitationSum = 0.0, agitationMass = 0.0;
};

/// The drift by agitation as a table, one row per bin and class: mean
/// agitation of the bin, then the columns of measuredDriftTable (mass share
/// within the bin).
constexpr int kDriftByAgitationColumns = 7;
std::vector<double> driftByAgitationTable(const std::vector<MeasuredDrift::BinDrift> &bins);
std::vector<MeasuredDrift::BinDrift> driftByAgitationFromTable(const std::vector<double> &rowMajor, int cols);



/// The measured drift as a table, one row per class: diameter [m], velocity
/// [m/s], standard error [m/s], particles, frames, mass share (the columns
/// of the database's /measured_drift, docs/database-format.md).
constexpr int kMeasuredDriftColumns = 6;
std::vector<double> measuredDriftTable(const std::vector<MeasuredDrift::ClassDrift> &drift);
/// Back from such a table; throws std::invalid_argument for another column count.
std::vector<MeasuredDrift::ClassDrift> measuredDriftFromTable(const std::vector<double> &rowMajor, int cols);

/// A size law's fit to the measured drift.  The law's shape is its velocity
/// at k = 1, g_i = g(d_i, d32) (rcfd/size_law.hpp): u_i = k g_i, or relative
/// to the bulk u_i = k (g_i - sum_j s_j g_j).  For A and B, g = -x with x the
/// paper's size term, so k is the paper's k_d.
struct DriftFit {
  double kd = 0.0;            ///< [the law's unit of k]
  double standardError = 0.0; ///< of kd
  double chiSquare = 0.0;     ///< sum of w (u - fit)^2 over the classes used
  double chiSquarePerDof = 0.0;
  double shape = std::numeric_limits<double>::quiet_NaN(); ///< the shape parameter fitted (fitDriftLaw), NaN: none
  std::vector<double> predicted; ///< per class: the law's u at the fitted k [m/s]
  std::vector<double> residual;  ///< per class: measured u - predicted [m/s] (NaN where not measured)
};

/// Weighted least squares of u_i = k g_i through the origin, weights
/// 1/se_i^2 (classes with se 0 or fewer than two frames are left out).
/// With relativeToBulk, g_i - sum_j s_j g_j instead (s_j the classes' mass
/// shares): the drift relative to the bulk that rcfd's face swaps realise,
/// since what the sending side lacks the bulk tops up (docs/drift.md), and
/// the form the measured velocities have (their mass-weighted mean is zero).
/// Throws std::invalid_argument when fewer than one class can be used.
DriftFit fitDriftCoefficient(const std::vector<MeasuredDrift::ClassDrift> &drift, double d32, const SizeLaw &law,
                             bool relativeToBulk = false);

/// fitDriftCoefficient relative to the bulk; for a law with a shape
/// parameter (power: m) also that parameter, by a scan of its range in
/// steps of 0.01 (k by least squares at each), the smallest chi^2.  Leaves
/// the law at the fitted parameter; chiSquarePerDof counts it as a parameter.
/// With fewer than three usable classes the shape is not fitted (any value
/// fits two classes exactly): shape stays NaN and the law at its value.
DriftFit fitDriftLaw(const std::vector<MeasuredDrift::ClassDrift> &drift, double d32, SizeLaw &law);

/// u_b,i = k (g_i - sum_j s_j g_j) (a_b / a_bar)^n over bins b and classes i
/// (x and the mass shares s of the whole bed, as fitDriftCoefficient with
/// relativeToBulk), weights 1/se^2: k_d by least squares for each n of a scan
/// of [0, nMax] in steps of 0.01, the n of the smallest chi^2.
struct AgitationDriftFit {
  double kd = 0.0, exponent = 0.0, chiSquarePerDof = 0.0;
};
AgitationDriftFit fitAgitationExponent(const std::vector<MeasuredDrift::BinDrift> &bins,
                                       const std::vector<MeasuredDrift::ClassDrift> &bed, double aBar,
                                       double d32, const SizeLaw &law, double nMax = 6.0);

} // namespace rcfd
