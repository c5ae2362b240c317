// Which cells a particle's volume is counted in (issue 12: beds with
// cell-sized particles).
//
// centre : the whole particle in the cell holding its centre (the paper's
//          rule); alpha_s can pass 1 where cells are barely larger than
//          the particles.
// overlap: each cell gets the part of the sphere it holds (exact sphere-box
//          overlap).  The part outside the mesh (a sphere touching a wall,
//          soft contacts) goes to the nearest inside cell: the boundary
//          cells reach to infinity for this purpose, so no volume is lost.
//          The shares are normalised to sum to 1 exactly, whatever the
//          quadrature error of the overlap volumes.
// Under both rules a particle whose centre is outside the mesh is in no
// cell, so the two rules agree on which particles a mesh holds.
#pragma once

#include "rcfd/mesh.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace rcfd {

enum class ParticleVolume { Centre, Overlap };

/// "centre" or "overlap"; throws std::invalid_argument naming the accepted words.
ParticleVolume parseParticleVolume(const std::string &word);
const char *particleVolumeName(ParticleVolume rule);

struct CellShare {
  int32_t cell;
  double share; // of the particle's volume (and mass); a particle's shares sum to 1
};

/// The cells of `mesh` holding the particle (centre, diameter d; rcfd
/// coordinates) and their shares, appended to `out` after clearing it; empty
/// when the centre is outside the mesh.
void cellShares(const BoxSpec &mesh, const Vec3 &centre, double d, ParticleVolume rule,
                std::vector<CellShare> &out);

/// Volume of a sphere of radius R below the height h above its centre
/// (0 for h <= -R, the whole sphere for h >= R).
double sphereVolumeBelow(double R, double h);

/// Shares of a particle (centre height z, diameter d) in the nz layers of
/// height dz from z0 upward, under `rule` (overlap: slab volumes, the parts
/// below and above the mesh counted in the bottom and top layers); appended
/// to `out` after clearing it as (layer, share).  Empty when z is outside.
void layerShares(double z0, double dz, int nz, double z, double d, ParticleVolume rule,
                 std::vector<CellShare> &out);

} // namespace rcfd
