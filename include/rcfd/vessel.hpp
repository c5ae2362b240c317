// A vessel that is not a box: analytic shapes (box, vertical cylinder, cone
// or frustum, horizontal tubes) united and subtracted, cut out of a box mesh
// (docs/vessels.md).  Each box cell gets the share of its volume inside the
// vessel and each face the share of its area; the cells with nothing inside
// are left out of the mesh (vesselMesh), so that nothing stores, partitions
// or answers for them.
//
// Options (collective, read by Vessel::setFromOptions):
//   -vessel box                        the whole box (the default: today's mesh, bit for bit)
//   -vessel cylinder                   a vertical cylinder in the box:
//       -vessel_axis x,y               its axis [m] (default: the box's centre)
//       -vessel_radius R               its radius [m] (default: half the narrower side)
//   -vessel NAME1,NAME2,...            the union of named shapes, each given by one of
//       -vessel_NAME_box xmin,xmax,ymin,ymax,zmin,zmax          [m]
//       -vessel_NAME_cylinder x,y,radius[,low,high]             vertical axis [m]
//       -vessel_NAME_cone x,y,low,radius_low,high,radius_high   vertical frustum [m]
//       -vessel_NAME_tube_x y,z,radius    a horizontal cylinder along x (through the box) [m]
//       -vessel_NAME_tube_y x,z,radius    the same along y [m]
//   -vessel_minus NAME,...             shapes taken out of the union (a tube bank)
//   -vessel_samples n                  sub-samples per cell edge for cut cells (default 8)
//   -vessel_merge_below S              a cut cell with less than S of its box cell inside
//                                      joins a neighbour (default 0: none; vesselMesh)
// rcfd build from particle dumps also takes -vessel from-particles [-vessel_margin M]: the
// box cells the particles reached (src/builders/particles/particle_vessel.hpp), not a Vessel.
// Positions are absolute, in the mesh's coordinates; z is the vertical axis.
#pragma once

#include "rcfd/mesh.hpp"

#include <petscsys.h>

#include <limits>
#include <string>
#include <vector>

namespace rcfd {

class Vessel {
public:
  enum class Kind { Box, Cylinder, Cone, TubeX, TubeY };
  /// One shape: its kind and its numbers in the order of its option.
  struct Shape {
    Kind kind;
    std::vector<double> p;
    bool subtract = false;
  };

  /// The whole box (every cell inside, every face open).
  Vessel() = default;
  /// Collective: reads the options above for a mesh of `box`; refuses, with one
  /// sentence naming the option, a name without a shape or with two, and wrong
  /// numbers (a vessel that holds no cell of the box is vesselMesh's to refuse).
  PetscErrorCode setFromOptions(MPI_Comm comm, const BoxSpec &box);
  /// The same before the box is known (rcfd build finds it from the particles):
  /// `-vessel cylinder`'s defaults are left to in(box).
  PetscErrorCode setFromOptions(MPI_Comm comm);
  /// Not collective.  This vessel in `box`, in `*out`: `-vessel cylinder` gets its
  /// axis (the box's centre) and radius (half the narrower side) where not given.
  PetscErrorCode in(const BoxSpec &box, Vessel *out) const;

  /// Not collective.  Adds a shape united with (or, with subtract, taken from)
  /// what is there; refuses (PETSC_ERR_USER_INPUT, one sentence) wrong numbers.
  PetscErrorCode add(Kind kind, std::vector<double> numbers, bool subtract = false);
  /// Shapes in the order they apply; none: the whole box.
  const std::vector<Shape> &shapes() const { return shapes_; }
  bool isWholeBox() const { return shapes_.empty() && !fitted_; }
  /// Sub-samples per cell edge for cells the wall cuts (n^3 per cell, n^2 per face).
  int samples() const { return samples_; }
  /// Not collective; refuses n outside 1..64.
  PetscErrorCode setSamples(int n);
  /// The inside share below which a cut cell is merged into its open neighbour
  /// of the largest open area (0: no merging, today's mesh bit for bit).
  double mergeBelow() const { return mergeBelow_; }
  /// Not collective; refuses S outside [0, 1].
  PetscErrorCode setMergeBelow(double S);

  /// A lower bound of the distance from p to the wall, positive inside and
  /// negative outside (1-Lipschitz), so that a cell whose centre is further
  /// from the wall than its half diagonal is wholly inside or outside.
  double level(const Vec3 &p) const;
  bool contains(const Vec3 &p) const { return level(p) > 0.0; }

  /// One line that names this vessel exactly (each number in the fewest digits that read back to it), recorded
  /// in databases; "box" for the whole box.  parse(describe()) == *this.
  std::string describe() const;
  /// Not collective.  The vessel a describe() line names, in `*out`; refuses
  /// (PETSC_ERR_USER_INPUT, one sentence) a text that names none.
  static PetscErrorCode parse(const std::string &text, Vessel *out);

  bool operator==(const Vessel &o) const { return describe() == o.describe(); }
  bool operator!=(const Vessel &o) const { return !(*this == o); }

private:
  std::vector<Shape> shapes_;
  int samples_ = 8;
  double mergeBelow_ = 0.0;
  bool fitted_ = false;        // -vessel cylinder, its defaults still to take from a box (in())
  double fitAxis_[2] = {kUnset, kUnset}, fitRadius_ = kUnset; // kUnset: not given
  static constexpr double kUnset = std::numeric_limits<double>::quiet_NaN();
};

/// The vessel cut out of a box: the share of each box cell's volume inside it,
/// and of each internal face's area (exact for cells and faces the wall does not
/// cross; sub-sampled at the centres of n x n x n sub-cells where it does, so a
/// cut cell's share is a multiple of 1/n^3 and off by at most the share of its
/// sub-cells the wall crosses, docs/vessels.md).
struct VesselCut {
  std::vector<double> cellShare; ///< per box cell (natural index), in [0, 1]
  /// Per internal face of the box in the box mesh's order (owner cell, then axis x, y, z),
  /// the share of its area inside the vessel; 0 where either cell is outside.
  std::vector<double> faceShare;
  /// Per boundary face of the box in the box mesh's order, the share inside.
  std::vector<double> boundaryShare;
  /// Centroid of each box cell's inside part (its centre when wholly inside).
  std::vector<Vec3> centroid;
};

/// Not collective; deterministic.  The cut of `vessel` out of `box`.
PetscErrorCode cutVessel(const Vessel &vessel, const BoxSpec &box, VesselCut *cut);

/// The mesh of the vessel: the box cells with a share inside, numbered
/// compactly in the box's order (Mesh::boxCell maps back), each with its
/// inside volume; internal faces only where open, with their open area;
/// boundary faces of the box where open.  A vessel that holds every box cell
/// whole (the whole box) gives Mesh::createBox's mesh itself, bit for bit.
/// With mergeBelow() = S > 0, a cell whose inside volume is below S of its box
/// cell's joins the neighbour it shares the largest open area with, again until
/// every cell is at least S or has no open neighbour (docs/vessels.md): the
/// merged cell's volume is the sum, its centroid the volume-weighted one, its
/// faces the open faces to other cells (areas to the same neighbour along the
/// same axis added); Mesh::boxCell is the member that holds the centroid.
/// Not collective; refuses (PETSC_ERR_USER_INPUT) a vessel that holds no cell.
PetscErrorCode vesselMesh(const Vessel &vessel, const BoxSpec &box, Mesh *mesh);

} // namespace rcfd
