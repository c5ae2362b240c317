// The drift the particle data show, per frame, region of cells and size
// class (issue 21): what `-drift_model measured` replays in place of a size
// law.  `rcfd build` (from particles) stores it in the database
// (/extra/measured_drift_field and /extra/measured_drift_field_layout,
// docs/database-format.md); a run reads it here and hands the drift sweep
// each gathered cell's speeds for the frame it applies (docs/drift.md,
// "Measured-drift replay").
#pragma once

#include "rcfd/database.hpp"

#include <string>
#include <vector>

namespace rcfd {

class FaceExchange;

/// The stored datasets (under /extra) and their columns.
inline constexpr const char *kMeasuredDriftFieldName = "measured_drift_field";
inline constexpr const char *kMeasuredDriftLayoutName = "measured_drift_field_layout";
/// Per class: velocity relative to the bulk [m/s, up positive], particles, mass [kg].
inline constexpr int kMeasuredDriftValuesPerClass = 3;

/// Regions of a box mesh: blocks of rx x ry x rz cells from the origin (the
/// last block of an axis is smaller when the cells do not divide evenly).
/// Region numbers follow the cells' natural order: (bx, by, bz) is
/// bx + Bx (by + By bz), B the blocks per axis.
struct DriftRegions {
  int rx = 1, ry = 1, rz = 1;
  int count(const BoxSpec &box) const;
  /// The region of natural cell `cell`.
  int regionOf(const BoxSpec &box, int cell) const;
};

/// The measured velocities of a run's fractions at the cells a drift sweep
/// reads, one frame at a time.
class MeasuredDriftField {
public:
  /// Collective.  Reads the field of `db`'s file and matches each fraction
  /// (its diameter) to the stored class within 1 %.  Refuses, in one
  /// sentence naming the file, a database without the field, a field of
  /// another size than the loaded frames and the mesh, a fraction no class
  /// matches and values that are not finite.
  PetscErrorCode setUp(const Database &db, const std::vector<double> &diameters, FaceExchange &exchange);
  /// Database::identity() of the database the field was read from.
  const std::string &databaseIdentity() const { return madeFrom; }
  int numFrames() const { return frames; }
  /// The upward and downward speed (max(u, 0), max(-u, 0)) of every fraction
  /// at every gathered cell of the exchange, for frame k (nf numbers per cell,
  /// in `up` and `down`).  A region where the class had no particle in that
  /// frame gives 0.
  void speeds(int k, double *up, double *down) const;
  /// The largest |u| of frame k over all regions and the run's fractions
  /// (the same on every rank: each holds the whole field).
  double largestSpeed(int k) const { return largest[k]; }
  /// Stored classes' diameters [m] and the class of each fraction.
  const std::vector<double> &classDiameters() const { return stored; }
  const DriftRegions &regions() const { return blocks; }

private:
  std::string madeFrom;
  DriftRegions blocks;
  int frames = 0, numRegions = 0, nf = 0;
  std::vector<double> stored;
  std::vector<int> regionOfGathered;
  std::vector<double> velocity; // frame-major, then region, then fraction
  std::vector<double> largest;  // per frame
};

} // namespace rcfd
