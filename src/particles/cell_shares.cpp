#include "particles/cell_shares.hpp"

#include "particles/sphere_overlap.hpp"
#include "base/constants.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace rcfd {
namespace {

/// The cells along one axis that a sphere (centre c, radius R) reaches, and
/// their bounds; the first and last cell of the mesh reach beyond the mesh by
/// the sphere's diameter, which is as good as infinity for the sphere.
struct AxisCut {
  int first = 0, last = 0;
  double lo(int i) const { return i == 0 ? c - 2.0 * R : o + i * h; }
  double hi(int i) const { return i == n - 1 ? c + 2.0 * R : o + (i + 1) * h; }
  double o = 0.0, h = 1.0, c = 0.0, R = 0.0;
  int n = 1;
};

AxisCut cutAxis(double origin, double h, int n, double c, double R) {
  AxisCut a;
  a.o = origin, a.h = h, a.n = n, a.c = c, a.R = R;
  auto index = [&](double x) {
    return static_cast<int>(std::clamp(std::floor((x - origin) / h), 0.0, double(n - 1)));
  };
  a.first = index(c - R);
  a.last = index(c + R);
  return a;
}

void normalise(std::vector<CellShare> &out) {
  double sum = 0.0;
  for (const CellShare &s : out) sum += s.share;
  for (CellShare &s : out) s.share /= sum;
}

} // namespace

ParticleVolume parseParticleVolume(const std::string &word) {
  if (word == "overlap") return ParticleVolume::Overlap;
  if (word == "centre" || word == "center") return ParticleVolume::Centre;
  throw std::invalid_argument("-particle_volume " + word +
                              " is not known; use overlap (each cell gets the part of a particle "
                              "it holds) or centre (the whole particle in its centre's cell).");
}

const char *particleVolumeName(ParticleVolume rule) {
  return rule == ParticleVolume::Overlap ? "overlap" : "centre";
}

double sphereVolumeBelow(double R, double h) {
  if (h <= -R) return 0.0;
  if (h >= R) return 4.0 / 3.0 * kPi * R * R * R;
  const double t = R + h; // cap height
  return kPi * t * t * (3.0 * R - t) / 3.0;
}

void cellShares(const BoxSpec &mesh, const Vec3 &centre, double d, ParticleVolume rule,
                std::vector<CellShare> &out) {
  out.clear();
  const int cell = mesh.locate(centre);
  if (cell < 0) return;
  const double R = 0.5 * d;
  if (rule == ParticleVolume::Centre || !(R > 0.0)) {
    out.push_back({cell, 1.0});
    return;
  }
  const Vec3 h = mesh.spacing();
  const int n[3] = {mesh.nx, mesh.ny, mesh.nz};
  std::array<AxisCut, 3> ax;
  int crossed = -1, crossings = 0;
  for (int a = 0; a < 3; ++a) {
    ax[a] = cutAxis(mesh.origin[a], h[a], n[a], centre[a], R);
    if (ax[a].last > ax[a].first) crossed = a, ++crossings;
  }
  auto flat = [&](int i, int j, int k) { return static_cast<int32_t>((k * mesh.ny + j) * mesh.nx + i); };
  if (crossings == 0) {
    out.push_back({cell, 1.0});
    return;
  }
  int idx[3] = {ax[0].first, ax[1].first, ax[2].first};
  if (crossings == 1) { // slabs of one axis: spherical caps, in closed form
    const AxisCut &a = ax[crossed];
    for (int i = a.first; i <= a.last; ++i) {
      const double v = sphereVolumeBelow(R, a.hi(i) - a.c) - sphereVolumeBelow(R, a.lo(i) - a.c);
      idx[crossed] = i;
      if (v > 0.0) out.push_back({flat(idx[0], idx[1], idx[2]), v});
    }
  } else {
    for (int k = ax[2].first; k <= ax[2].last; ++k)
      for (int j = ax[1].first; j <= ax[1].last; ++j)
        for (int i = ax[0].first; i <= ax[0].last; ++i) {
          const Vec3 lo{ax[0].lo(i), ax[1].lo(j), ax[2].lo(k)};
          const Vec3 hi{ax[0].hi(i), ax[1].hi(j), ax[2].hi(k)};
          // One quadrature panel: within 1e-9 of the sphere, and the shares are
          // normalised below, so T_k alpha_k = alpha_{k+1} stays exact regardless.
          const double v = sphereBoxVolume(centre, R, lo, hi, 1);
          if (v > 0.0) out.push_back({flat(i, j, k), v});
        }
  }
  normalise(out);
}

void layerShares(double z0, double dz, int nz, double z, double d, ParticleVolume rule,
                 std::vector<CellShare> &out) {
  out.clear();
  if (!(z >= z0 && z <= z0 + nz * dz)) return;
  const double R = 0.5 * d;
  AxisCut a = cutAxis(z0, dz, nz, z, R);
  if (rule == ParticleVolume::Centre || !(R > 0.0) || a.first == a.last) {
    const int layer = std::min(nz - 1, static_cast<int>(std::floor((z - z0) / dz)));
    out.push_back({layer, 1.0});
    return;
  }
  for (int i = a.first; i <= a.last; ++i) {
    const double v = sphereVolumeBelow(R, a.hi(i) - z) - sphereVolumeBelow(R, a.lo(i) - z);
    if (v > 0.0) out.push_back({i, v});
  }
  normalise(out);
}

} // namespace rcfd
