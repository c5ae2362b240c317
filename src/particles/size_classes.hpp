// Size classes of a particle inventory: which class a diameter belongs to,
// and classes clustered from the diameters of a snapshot.  Used by the
// builder (per-class shares and measured drift) and by the reference.
#pragma once

#include <string>
#include <vector>

namespace rcfd {

/// Size classes by diameter.  A particle of diameter d is in the class of
/// the nearest diameter D when |d - D| <= relTol * D.
struct SizeClasses {
  std::vector<double> diameter; // m, ascending
  double relTol = 0.01;

  /// Class index of diameter d, or -1 when no class is within tolerance.
  int classOf(double d) const;
  /// Column label, e.g. "d1.950mm".
  std::string label(int c) const;

  /// Automatic classes: the sorted diameters are cut into groups wherever a
  /// diameter exceeds its group's smallest by more than relTol (relative);
  /// each class diameter is the mean of its group (one entry per particle).
  /// Meant for a few distinct sizes; a continuous distribution gives
  /// classes relTol wide.
  static SizeClasses cluster(std::vector<double> diameters, double relTol);
};

} // namespace rcfd
