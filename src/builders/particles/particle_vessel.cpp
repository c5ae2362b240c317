// The vessel of the cells the particles reached (particle_vessel.hpp).
#include "builders/particles/particle_vessel.hpp"

#include "mesh/vessel_mesh.hpp"

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <sstream>

namespace rcfd {

VisitedCells::VisitedCells(const BoxSpec &box, const AxisMap &axes, double margin)
    : box_(box), axes_(axes), margin_(margin), inside_(static_cast<std::size_t>(box.numCells()), 0) {}

void VisitedCells::add(const ParticleSnapshot &snap) {
  const Vec3 h = box_.spacing();
  const int n[3] = {box_.nx, box_.ny, box_.nz};
  for (std::size_t p = 0; p < snap.size(); ++p) {
    const Vec3 x = axes_.apply(snap.position[p]);
    const int c = box_.locate(x);
    if (c >= 0) inside_[c] = 1;
    if (!(margin_ > 0.0)) continue;
    // Every cell whose nearest point lies closer than the margin to the centre.
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::max(0, static_cast<int>(std::floor((x[a] - margin_ - box_.origin[a]) / h[a])));
      hi[a] = std::min(n[a] - 1, static_cast<int>(std::floor((x[a] + margin_ - box_.origin[a]) / h[a])));
    }
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i) {
          const int idx[3] = {i, j, k};
          double d2 = 0.0;
          for (int a = 0; a < 3; ++a) {
            const double low = box_.origin[a] + idx[a] * h[a], gap = std::max({low - x[a], x[a] - low - h[a], 0.0});
            d2 += gap * gap;
          }
          if (d2 < margin_ * margin_) inside_[box_.cellIndex(i, j, k)] = 1;
        }
  }
}

int VisitedCells::count() const { return static_cast<int>(std::count(inside_.begin(), inside_.end(), 1)); }

Mesh VisitedCells::mesh() const {
  std::uint64_t hash = 1469598103934665603ull; // FNV-1a over the box's size and the marked cells
  auto mix = [&](std::uint64_t v) {
    for (int b = 0; b < 8; ++b) hash = (hash ^ ((v >> (8 * b)) & 0xffu)) * 1099511628211ull;
  };
  mix(static_cast<std::uint64_t>(box_.nx)), mix(static_cast<std::uint64_t>(box_.ny)), mix(static_cast<std::uint64_t>(box_.nz));
  for (std::size_t c = 0; c < inside_.size(); ++c)
    if (inside_[c]) mix(c);
  char h[17];
  std::snprintf(h, sizeof h, "%016" PRIx64, hash);
  std::ostringstream line;
  line.precision(17);
  line << "particles(margin " << margin_ << ") " << count() << " cells mask " << h;
  return cellsVesselMesh(box_, inside_, line.str());
}

bool VisitedCells::names(const std::string &line) { return line.rfind("particles(", 0) == 0; }

} // namespace rcfd
