// The bed in horizontal cell layers: each fraction's mass per layer, reduced
// over the ranks in one call.  Vertical profiles, the size distribution of the
// bottom and top halves and the bottom layer's Sauter diameter all follow from
// these few numbers per layer (nLayers x nf), so a run that asks for all three
// pays for one pass over its cells and one reduction.
#pragma once

#include "rcfd/database.hpp"
#include "rcfd/fractions.hpp"

#include <vector>

namespace rcfd {

class HorizontalLayers {
public:
  /// Collective.  Layers are the box mesh's cell layers along gravity, counted
  /// from the bottom (where gravity points); refuses other meshes.
  PetscErrorCode setUp(const Database &db);
  int numLayers() const { return static_cast<int>(centre.size()); }
  /// Coordinate of layer l's centre along the vertical axis [m] (rcfd's z on a z-up mesh).
  double height(int l) const { return centre[l]; }
  /// The layer of local cell c (an owned cell, in the local order).
  int localLayer(PetscInt c) const { return layerOfLocal[c]; }
  /// Thickness of a layer along gravity [m].
  double thickness() const { return layerThickness; }
  /// Volume of layer l [m^3], whole mesh.
  double volume(int l) const { return layerVolume[l]; }
  /// Collective: mass [kg] of each fraction in each layer, [l * nf + i], the same on every rank.
  PetscErrorCode fractionMasses(Vec masses, int nf, std::vector<double> *perLayer) const;
  /// The same for the state, reading only the cells that may hold mass
  /// (FractionState::occupiedEnd; the empty ones add nothing, same bits).
  PetscErrorCode fractionMasses(const FractionState &state, std::vector<double> *perLayer) const;
  /// Collective: the scalars' amounts of layer l alone, [s * nf + i] (docs/scalars.md; a pass over
  /// the cells that may hold mass and a reduction of ns x nf numbers).
  PetscErrorCode layerAmounts(const FractionState &state, int l, std::vector<double> *amounts) const;
  /// Collective: solid volume sum(alpha_s V) [m^3] of each layer for one frame's alpha_s.
  PetscErrorCode solidVolumes(Vec alpha, std::vector<double> *perLayer) const;

private:
  PetscErrorCode sumLayers(Vec masses, int nf, PetscInt end, std::vector<double> *perLayer) const;
  MPI_Comm comm = MPI_COMM_NULL;
  std::vector<int> layerOfLocal;
  std::vector<double> localVolume, centre, layerVolume;
  double layerThickness = 0.0;
};

/// What follows from the masses per layer ([l * nf + i]).
namespace layers {

/// Sauter diameter 1 / sum_i(w_i / d_i) of layer l's solid (w_i its mass shares);
/// NaN when the layer holds no solid.
double sauterDiameter(const std::vector<double> &perLayer, int l, const FractionSet &fractions);
/// The bed's mass-median layer: the first layer, counted from the bottom, at which
/// the mass summed from the bottom reaches half of the total (-1 for an empty bed).
int medianLayer(const std::vector<double> &perLayer, int nf);
/// Mass shares of each fraction below and at the split layer (bottom) and above it
/// (top); each sums to 1 (NaN when that half is empty).
void halves(const std::vector<double> &perLayer, int nf, int splitLayer, std::vector<double> *bottom,
            std::vector<double> *top);

} // namespace layers
} // namespace rcfd
