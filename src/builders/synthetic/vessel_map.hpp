// The synthetic bed in a vessel of any shape (a conical bottom, a box minus
// tubes, docs/vessels.md): the kinematic bed runs in a *host* box of the
// vessel's volume, and a volume-preserving map carries each parcel into a cell
// of the vessel's mesh.  (One vertical cylinder through the box keeps its own
// map, CylinderMap in synthetic_bed.cpp, and its bits.)
//
// The map is a Knothe-Rosenblatt rearrangement on the mesh's cells, which are
// numbered in the box's order (layer, then row, then x): the host height picks
// the layer whose share of the vessel's volume it reaches, the host y the row
// of that layer by the rows' shares, the host x the cell of that row by the
// cells' shares.  Every host volume goes to the same inside volume (the
// Jacobian is 1), so the bed keeps its alpha_s on average; each coordinate is
// monotone, so neighbours stay neighbours; and only the mesh's cells, which lie
// inside the vessel, can be reached.  Where the vessel narrows (a cone, the
// layers a tube crosses) the host's layer is stretched upwards and squeezed
// sideways around the tube: bubbles and circulation stay inside.
#pragma once

#include "builders/synthetic/synthetic_bed.hpp"

#include <cstdint>
#include <vector>

namespace rcfd::synthetic {

/// The host box a vessel's bed runs in: the box's cells per side, the area of
/// the vessel's widest cell layer (in the box's aspect ratio), and the height
/// that gives it the vessel's volume; the settled bed holds the vessel's
/// volume below options.bedHeight.  Throws std::invalid_argument (one
/// sentence) when that bed would not fit.
SyntheticBedOptions hostBedOptions(const SyntheticBedOptions &options, const Mesh &mesh);

class VesselMap {
public:
  /// `host` is hostBedOptions(options, mesh).box; parcels of `parcelVolume`.
  VesselMap(const BoxSpec &box, const BoxSpec &host, const Mesh &mesh, double parcelVolume);
  /// Call before the parcels of each state: every cell's room is free again.
  VesselMap &start();
  /// The cell of the vessel a parcel at (x, y, z) of the host box goes to.  A
  /// cell takes at most the parcels that fill its inside volume (alpha_s <= 1,
  /// as in the cylinder: the map keeps the density on average, not in each
  /// cell, and a small cut cell would otherwise overfill from one parcel); the
  /// rest go to the nearest cell with room, across open faces.  (A cap at the
  /// packing moved most parcels every frame: the dense phase is at the packing
  /// on average, so every fluctuation overflowed.)
  int32_t operator()(double x, double y, double z);
  /// Parcels the packing sent to another cell than the map's, since construction.
  long relocated() const { return relocated_; }
  /// The height [m, from the box's floor] the host height z maps to.
  double height(double z) const;

private:
  int32_t cellAt(double x, double y, double z) const;
  int32_t nearestWithRoom(int32_t cell);

  const Mesh &mesh_;
  double hostArea_, hostLength_[2], layerHeight_;
  int nx_, ny_, nz_;
  std::vector<double> cumulative_;          // inside volume of the cells before each cell (numCells + 1)
  std::vector<int32_t> rowStart_;           // first cell of each (row, layer), ny nz + 1 of them
  std::vector<double> rowBound_;            // cumulative_ at each rowStart_
  std::vector<int32_t> capacity_, held_;
  std::vector<int32_t> adjacencyStart_, adjacency_; // open-face neighbours, by cell index
  std::vector<int32_t> queue_, seen_;
  int32_t stamp_ = 0;
  long relocated_ = 0;
};

} // namespace rcfd::synthetic
