// The drift the particle data show per frame, region of cells and size
// class (issue 21): what rcfd build stores as /extra/measured_drift_field for
// `-drift_model measured` (rcfd/measured_drift_field.hpp reads it).  In each
// frame (snapshot pair, dt apart) a particle's vertical velocity relative to
// the bulk is (dz - dz_cell) / dt, dz_cell the mass-weighted mean
// displacement of the matched particles of its cell at the first snapshot
// (the shift already moves each cell's bulk; relative to the cell is what a
// cell's face swaps carry).  A region averages these over its cells,
// mass-weighted per class, to trade resolution for noise; so per cell and
// per region sum_i m_i u_i = 0 (no net mass flux relative to the bulk).
#pragma once

#include "analysis/measured_drift.hpp"
#include "rcfd/measured_drift_field.hpp"

#include <vector>

namespace rcfd {

class RegionalDrift {
public:
  /// Throws std::invalid_argument for a region size below 1.
  RegionalDrift(SizeClasses classes, AxisMap axes, BoxSpec mesh, DriftRegions regions);
  /// One frame: the snapshots `before` and `after`, dt apart [s].
  void add(const ParticleSnapshot &before, const ParticleSnapshot &after, double dt);
  int framesAdded() const { return frames; }
  /// Rows frame-major then region; per class velocity [m/s] (0 where the
  /// class has no particle), particles, mass [kg] (kMeasuredDriftValuesPerClass).
  const std::vector<double> &table() const { return rows; }
  int columns() const { return kMeasuredDriftValuesPerClass * static_cast<int>(classes.diameter.size()); }
  /// The layout row: rx, ry, rz, then the class diameters [m].
  std::vector<double> layoutRow() const;
  /// Share of the (frame, region, class) entries holding particles that rest
  /// on fewer than `n` particles (how noisy the field is).
  double shareBelow(long n) const;

private:
  SizeClasses classes;
  AxisMap axes;
  BoxSpec mesh;
  DriftRegions regions;
  int frames = 0;
  std::vector<double> rows;
};

} // namespace rcfd
