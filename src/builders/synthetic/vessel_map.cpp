// The synthetic bed's map into a vessel of any shape (vessel_map.hpp).
#include "builders/synthetic/vessel_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace rcfd::synthetic {
namespace {

/// The i in [0, n) with b(i) <= v < b(i + 1) for a non-decreasing b with b(0) <= v
/// and b(n) > b(0): the last bin starting at or below v, stepped back over empty
/// bins at the top.  Walked to from `guess` (bins of about equal size: a step
/// or two; a binary search over the cells, at random places, was most of a
/// frame's cost).
template <typename Bound> int binOf(int n, double v, int guess, Bound &&b) {
  int i = std::min(n - 1, std::max(0, guess));
  while (i > 0 && b(i) > v) --i;
  while (i + 1 < n && b(i + 1) <= v) ++i;
  while (i > 0 && !(b(i + 1) > b(i))) --i;
  return i;
}

/// The bin a share s in [0, 1] of n about equal bins falls in.
int guessOf(double s, int n) { return static_cast<int>(s * n); }

std::vector<double> layerVolumes(const BoxSpec &box, const Mesh &mesh) {
  std::vector<double> layer(box.nz, 0.0);
  const int perLayer = box.nx * box.ny;
  for (int c = 0; c < mesh.numCells(); ++c) layer[mesh.boxCell(c) / perLayer] += mesh.cellVolume[c];
  return layer;
}

} // namespace

SyntheticBedOptions hostBedOptions(const SyntheticBedOptions &options, const Mesh &mesh) {
  const BoxSpec &box = options.box;
  const std::vector<double> layer = layerVolumes(box, mesh);
  const double hz = box.spacing()[2];
  double total = 0.0, widest = 0.0, below = 0.0;
  for (int k = 0; k < box.nz; ++k) {
    total += layer[k];
    widest = std::max(widest, layer[k]);
    // The vessel's volume below the settled height (cells filled evenly along z).
    const double share = (options.bedHeight - k * hz) / hz;
    below += layer[k] * std::min(1.0, std::max(0.0, share));
  }
  const double area = widest / hz, scale = std::sqrt(area / (box.length[0] * box.length[1]));
  SyntheticBedOptions host = options;
  host.vessel = Vessel();
  host.box.length = {box.length[0] * scale, box.length[1] * scale, total / area};
  host.bedHeight = below / area;
  if (!(below <= 0.7 * total)) {
    char sentence[256];
    std::snprintf(sentence, sizeof sentence,
                  "synthetic bed: bedHeight must leave at least 30 %% of the vessel's volume above the settled bed "
                  "as freeboard for voids and splashes (the bed below %g m holds %.0f %% of it).",
                  options.bedHeight, 100.0 * below / total);
    throw std::invalid_argument(sentence);
  }
  validateSyntheticBedOptions(host);
  return host;
}

VesselMap::VesselMap(const BoxSpec &box, const BoxSpec &host, const Mesh &mesh, double parcelVolume)
    : mesh_(mesh), hostLength_{host.length[0], host.length[1]}, layerHeight_(box.spacing()[2]), nx_(box.nx),
      ny_(box.ny), nz_(box.nz) {
  const int n = mesh.numCells();
  hostArea_ = host.length[0] * host.length[1];
  cumulative_.assign(n + 1, 0.0);
  rowStart_.assign(static_cast<size_t>(ny_) * nz_ + 1, 0);
  capacity_.resize(n);
  for (int c = 0; c < n; ++c) {
    cumulative_[c + 1] = cumulative_[c] + mesh.cellVolume[c];
    ++rowStart_[mesh.boxCell(c) / nx_ + 1]; // cells are in the box's order: rows are contiguous
    capacity_[c] = static_cast<int32_t>(std::floor(mesh.cellVolume[c] / parcelVolume * (1.0 + 1e-12)));
  }
  for (size_t r = 0; r + 1 < rowStart_.size(); ++r) rowStart_[r + 1] += rowStart_[r];
  rowBound_.resize(rowStart_.size());
  for (size_t r = 0; r < rowStart_.size(); ++r) rowBound_[r] = cumulative_[rowStart_[r]];
  adjacencyStart_.assign(n + 1, 0);
  for (int f = 0; f < mesh.numFaces(); ++f) ++adjacencyStart_[mesh.faceOwner[f] + 1], ++adjacencyStart_[mesh.faceNeighbour[f] + 1];
  for (int c = 0; c < n; ++c) adjacencyStart_[c + 1] += adjacencyStart_[c];
  adjacency_.resize(adjacencyStart_[n]);
  std::vector<int32_t> fill(adjacencyStart_.begin(), adjacencyStart_.end() - 1);
  for (int f = 0; f < mesh.numFaces(); ++f) {
    adjacency_[fill[mesh.faceOwner[f]]++] = mesh.faceNeighbour[f];
    adjacency_[fill[mesh.faceNeighbour[f]]++] = mesh.faceOwner[f];
  }
  for (int c = 0; c < n; ++c) // a fixed order, whatever the faces' order
    std::sort(adjacency_.begin() + adjacencyStart_[c], adjacency_.begin() + adjacencyStart_[c + 1]);
  seen_.assign(n, 0);
}

VesselMap &VesselMap::start() {
  held_.assign(capacity_.size(), 0);
  return *this;
}

int32_t VesselMap::cellAt(double x, double y, double z) const {
  auto clamp01 = [](double s) { return std::min(1.0, std::max(0.0, s)); };
  const double total = cumulative_.back(), sz = clamp01(z * hostArea_ / total);
  const int k = binOf(nz_, sz * total, guessOf(sz, nz_), [&](int layer) { return rowBound_[layer * ny_]; });
  const double layerLow = rowBound_[k * ny_], layerHigh = rowBound_[(k + 1) * ny_], sy = clamp01(y / hostLength_[1]);
  const int j = binOf(ny_, layerLow + sy * (layerHigh - layerLow), guessOf(sy, ny_),
                      [&](int row) { return rowBound_[k * ny_ + row]; });
  const int32_t first = rowStart_[k * ny_ + j], count = rowStart_[k * ny_ + j + 1] - first;
  const double rowLow = cumulative_[first], rowHigh = cumulative_[first + count], sx = clamp01(x / hostLength_[0]);
  return first + binOf(count, rowLow + sx * (rowHigh - rowLow), guessOf(sx, count),
                       [&](int i) { return cumulative_[first + i]; });
}

int32_t VesselMap::nearestWithRoom(int32_t cell) {
  if (++stamp_ == 0) std::fill(seen_.begin(), seen_.end(), 0), stamp_ = 1;
  queue_.assign(1, cell);
  seen_[cell] = stamp_;
  for (size_t q = 0; q < queue_.size(); ++q) {
    const int32_t c = queue_[q];
    if (held_[c] < capacity_[c]) return c;
    for (int32_t e = adjacencyStart_[c]; e < adjacencyStart_[c + 1]; ++e)
      if (seen_[adjacency_[e]] != stamp_) seen_[adjacency_[e]] = stamp_, queue_.push_back(adjacency_[e]);
  }
  // A cut cell with no open face (a corner the wall leaves): the nearest cell
  // with room in the mesh's order, which is the box's (its row, then its layer).
  const int32_t n = static_cast<int32_t>(capacity_.size());
  for (int32_t d = 1; d < n; ++d)
    for (const int32_t c : {cell - d, cell + d})
      if (c >= 0 && c < n && held_[c] < capacity_[c]) return c;
  throw std::logic_error("synthetic bed: the vessel has no room left for a parcel");
}

int32_t VesselMap::operator()(double x, double y, double z) {
  int32_t cell = cellAt(x, y, z);
  if (held_[cell] >= capacity_[cell]) cell = nearestWithRoom(cell), ++relocated_;
  ++held_[cell];
  return cell;
}

double VesselMap::height(double z) const {
  const double total = cumulative_.back();
  const double v = std::min(1.0, std::max(0.0, z * hostArea_ / total)) * total;
  auto atLayer = [&](int layer) { return cumulative_[rowStart_[layer * ny_]]; };
  const int k = binOf(nz_, v, guessOf(v / total, nz_), atLayer);
  return (k + std::min(1.0, (v - atLayer(k)) / (atLayer(k + 1) - atLayer(k)))) * layerHeight_;
}

} // namespace rcfd::synthetic
