// A vessel taken from where the particles ever were (rcfd build -vessel
// from-particles, docs/vessels.md), for users without a geometry: the box cells
// that held a particle centre, or came within the margin of one, in any of the
// snapshots the build reads.  Each such cell is inside whole (share 1), each face
// between two of them open whole: the particles say which cells the bed reached,
// not where a wall crosses a cell, so no share finer than a cell is claimed.
#pragma once

#include "particles/particle_dump.hpp"
#include "rcfd/mesh.hpp"

#include <string>
#include <vector>

namespace rcfd {

class VisitedCells {
public:
  /// Not collective.  `box` in rcfd coordinates (after `axes`); margin >= 0 [m].
  VisitedCells(const BoxSpec &box, const AxisMap &axes, double margin);
  /// Marks the cells the particles of `snap` reach: the cell of each centre, and
  /// with a margin every cell closer than it to the centre.
  void add(const ParticleSnapshot &snap);
  int count() const;
  /// The mesh of the marked cells, recorded as "particles(margin M) N cells mask H"
  /// (H a hash of the marked cells, so that two such vessels differ in their line
  /// when their cells do).  Throws std::invalid_argument when no cell is marked.
  Mesh mesh() const;
  /// Whether a database's vessel line is one of these (its shapes are its cells).
  static bool names(const std::string &line);

private:
  BoxSpec box_;
  AxisMap axes_;
  double margin_;
  std::vector<char> inside_;
};

} // namespace rcfd
