// Lacey's mixing index of one fraction over the cells that hold solid.
//
//   M = (s0^2 - s^2) / (s0^2 - sR^2)
// with p the fraction's share of all solid mass, s^2 the solid-mass-weighted
// variance of the cells' shares around p, s0^2 = p (1 - p) the variance of a
// completely segregated bed, and sR^2 the variance of a random mixture sampled
// n_c particles at a time: p (1 - p) / n_c, mass-weighted over the cells, where
// n_c is the cell's solid volume over the mean particle volume of the inventory.
// M is 0 for a segregated bed and 1 for a random mixture (it can exceed 1 a
// little for a bed more even than random).  See docs/answers.md.
#pragma once

namespace rcfd {

/// Sums over cells; add cells on each rank, reduce data() (size doubles) with
/// MPI_SUM, then take index().  Order of the cells changes only round-off.
class LaceySums {
public:
  /// One cell: `fractionMass` of the watched fraction among `solidMass`, and
  /// `particles` particles in the cell.  Cells without solid are skipped.
  void addCell(double fractionMass, double solidMass, double particles);
  /// The index for the inventory share p in (0, 1); NaN when p is 0 or 1
  /// (a single fraction is neither mixed nor segregated) or no cell holds solid.
  double index(double p) const;
  static constexpr int size = 4; ///< doubles in data(), for MPI reductions
  double *data() { return sums; }
  const double *data() const { return sums; }

private:
  // weight, weighted share, weighted share^2, weighted 1/n
  double sums[4] = {0.0, 0.0, 0.0, 0.0};
};

} // namespace rcfd
