// Readers for DEM particle snapshots: LIGGGHTS/LAMMPS `dump custom` text
// files (plain or gzip) and plain CSV files.  Positions are returned as they
// are in the file; AxisMap turns them into rcfd coordinates (z up).
//
// Every malformed input throws std::runtime_error with one sentence that
// names the file, the line number and what was expected.
#pragma once

#include "rcfd/mesh.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace rcfd {

/// One snapshot of a particle system, stored column by column.
struct ParticleSnapshot {
  std::string source;    // file it was read from, for messages
  int64_t timestep = -1; // ITEM: TIMESTEP; -1 when the file has none (CSV)
  bool hasBox = false;   // ITEM: BOX BOUNDS was present
  bool triclinic = false;
  Vec3 boxLo{0.0, 0.0, 0.0},
      boxHi{0.0, 0.0, 0.0}; // bounds as written (the *_bound values if triclinic)

  std::vector<int64_t> id;
  std::vector<int> type;        // 1 when the file has no type column
  std::vector<Vec3> position;   // m, file axes
  std::vector<double> diameter; // m
  std::vector<double> mass;     // kg

  std::size_t size() const { return id.size(); }
};

struct SnapshotReadOptions {
  /// Particle density [kg/m^3] used when the file has neither a `density`
  /// nor a `mass` column; reading such a file with a value <= 0 is an error.
  double defaultDensity = 0.0;
};

/// Reads a `dump custom` file holding one snapshot:
///   ITEM: TIMESTEP / ITEM: NUMBER OF ATOMS / ITEM: BOX BOUNDS ... /
///   ITEM: ATOMS id type x y z radius ...
/// Columns may come in any order.  Required: id, x y z (or xu yu zu), and
/// radius or diameter.  Optional: type, density, mass; other columns are
/// skipped.  Mass is density * pi/6 d^3 when a density column is present,
/// else the mass column, else defaultDensity * pi/6 d^3.  A file holding
/// further snapshots is rejected (use DumpStream for those).
ParticleSnapshot readDumpSnapshot(const std::string &path, const SnapshotReadOptions &opt);

/// Reads a CSV snapshot: a header line naming the columns (any order; id,
/// x, y, z and one of d / diameter / radius are required; type, density and
/// mass are optional, same mass rule as above), then one particle a line.
/// SI units.  Blank lines and lines starting with '#' are skipped.
ParticleSnapshot readCsvSnapshot(const std::string &path, const SnapshotReadOptions &opt);

/// Reads either kind: a file whose first non-blank line starts with "ITEM:"
/// is a dump, anything else is CSV.
ParticleSnapshot readParticleSnapshot(const std::string &path, const SnapshotReadOptions &opt);

/// Sequential reader for a dump file that holds several snapshots one after
/// another (LAMMPS' default when a dump is not split per timestep).
class DumpStream {
public:
  DumpStream(const std::string &path, const SnapshotReadOptions &opt);
  ~DumpStream();
  DumpStream(const DumpStream &) = delete;
  DumpStream &operator=(const DumpStream &) = delete;

  /// Reads the next snapshot into snap; false at the end of the file.
  bool next(ParticleSnapshot &snap);

private:
  struct Impl;
  std::unique_ptr<Impl> impl;
};

/// Maps file coordinates to rcfd coordinates (z up):
/// rcfd[a] = sign[a] * file[from[a]].  `from` must be a permutation of 0,1,2.
struct AxisMap {
  std::array<int, 3> from{0, 1, 2};
  std::array<int, 3> sign{1, 1, 1};

  /// The map for a file whose vertical axis is `verticalAxis` (0, 1, 2 for
  /// x, y, z) with gravity pointing along `gravitySign` (-1: towards -axis,
  /// the usual case; +1: towards +axis).  The two other file axes become
  /// rcfd x and y in cyclic order (vertical y: x <- z, y <- x; vertical x:
  /// x <- y, y <- z); only the vertical axis is ever flipped.
  static AxisMap verticalUp(int verticalAxis, int gravitySign);

  Vec3 apply(const Vec3 &p) const {
    return {sign[0] * p[from[0]], sign[1] * p[from[1]], sign[2] * p[from[2]]};
  }
  bool isIdentity() const;
  /// Throws std::invalid_argument unless from is a permutation and signs are +-1.
  void validate() const;
};

/// Reads a two-column "index time" file (such as dump/times.txt: snapshot
/// index, physical time in s); '#' lines and blank lines are skipped.
/// Returns the times in file order.
std::vector<double> readSnapshotTimes(const std::string &path);

} // namespace rcfd
