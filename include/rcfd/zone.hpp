// Named zones: pieces of the domain given by geometry in a case (a box, cell
// layers from the bottom, a band of heights, a half-space, a vertical
// cylinder), resolved onto the mesh at set-up.  A cell belongs to a zone when
// its centre does (boundaries included).  Observables are asked per zone; the
// granulation operators use zones for spray, feed and discharge.
//
// Options, for each NAME in -zones NAME1,NAME2,... (prefix zone_NAME_):
//   -zone_NAME_box xmin,xmax,ymin,ymax,zmin,zmax      [m]
//   -zone_NAME_layers first,last       cell layers counted from the bottom (0-based,
//                                       inclusive; "bottom" is where gravity points)
//   -zone_NAME_heights low,high        heights above the bottom of the mesh [m]
//   -zone_NAME_halfspace nx,ny,nz,c    cells with n . x <= c
//   -zone_NAME_cylinder x,y,radius,low,high   vertical (along gravity) cylinder
// Exactly one shape per zone.
#pragma once

#include "rcfd/handle.hpp"
#include "rcfd/layout.hpp"
#include "rcfd/mesh.hpp"

#include <string>
#include <vector>

namespace rcfd {

class Zone {
public:
  enum class Shape { Box, Layers, Heights, HalfSpace, Cylinder };
  /// A shape and its numbers, in the order of the option that gives it.
  Zone(std::string name, Shape shape, std::vector<double> parameters);

  const std::string &name() const { return name_; }
  Shape shape() const { return shape_; }
  /// One line: name, shape, numbers and (after setUp) the cells it holds.
  std::string describe() const;

  /// Whether the natural cell lies in the zone.  `vertical` is the mesh axis
  /// along gravity (0, 1, 2) and `upward` whether the axis points against it.
  bool contains(const Mesh &mesh, int cell, int vertical, bool upward) const;

  /// Collective: finds this rank's cells and the zone's size over all ranks.
  /// Refuses, naming the zone, a shape with wrong numbers or a zone that holds
  /// no cell of the mesh.
  PetscErrorCode setUp(const Mesh &mesh, const Layout &layout, const Vec3 &gravity);
  /// This rank's cells of the zone as local indices (PETSc row - row start), ascending.
  const std::vector<PetscInt> &localCells() const { return local; }
  /// Cells and volume of the whole zone, over all ranks.
  PetscInt numCells() const { return total; }
  double volume() const { return totalVolume; }

private:
  std::string checkParameters() const; // empty when fine
  std::string name_;
  Shape shape_;
  std::vector<double> p;
  std::vector<PetscInt> local;
  PetscInt total = 0;
  double totalVolume = 0.0;
  double bottom = 0.0; // height of the mesh's bottom along the vertical, for Heights
};

/// The zones of a case, by name.
class ZoneSet {
public:
  /// Reads -zones and each zone's shape option (collective).
  PetscErrorCode setFromOptions(MPI_Comm comm);
  /// Adds a zone given in code (before setUp).
  void add(Zone zone) { zones.push_back(std::move(zone)); }
  PetscErrorCode setUp(const Mesh &mesh, const Layout &layout, const Vec3 &gravity);
  /// The zone of that name, or nullptr.
  const Zone *find(const std::string &name) const;
  const std::vector<Zone> &all() const { return zones; }
  PetscErrorCode view(PetscViewer viewer) const;

private:
  std::vector<Zone> zones;
};

/// The mesh axis along gravity and whether that axis points upward (against gravity).
void verticalAxis(const Vec3 &gravity, int *axis, bool *upward);

} // namespace rcfd
