// The vessel cut out of a box: each cell's and face's share inside
// (exact where the wall does not cross them, sub-sampled where it does), and
// the masked mesh made of the cells with a share (include/rcfd/vessel.hpp).
#include "mesh/vessel_mesh.hpp"
#include "base/petsc_compat.hpp"

#include "base/collective.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>
#include <stdexcept>
#include <utility>
#include <vector>

namespace rcfd {
namespace {

// How much of a sub-cell of extent hs around x lies inside: 0 or 1 where the
// wall is further than its half diagonal, else the share a plane wall at the
// level's distance would leave, 0.5 + level / width, width the sub-cell's
// extent along the wall's normal (the level's gradient).  Against counting
// sub-cell centres (0 or 1 each) this takes a cylinder's volume from 3e-3 to
// 1e-4 at 8 samples per edge (docs/vessels.md).
double subCellShare(const Vessel &v, const Vec3 &x, const Vec3 &hs, double halfDiagonal) {
  const double level = v.level(x);
  if (level >= halfDiagonal) return 1.0;
  if (level <= -halfDiagonal) return 0.0;
  double width = 0.0;
  Vec3 far = x; // the sub-cell's corner furthest along the gradient (into the vessel), or against it
  for (int a = 0; a < 3; ++a) {
    if (!(hs[a] > 0)) continue;
    const double e = 1e-3 * hs[a];
    Vec3 up = x, down = x;
    up[a] += e;
    down[a] -= e;
    const double g = (v.level(up) - v.level(down)) / (2 * e);
    width += std::fabs(g) * hs[a];
    far[a] += ((g >= 0) == (level <= 0) ? 0.5 : -0.5) * hs[a];
  }
  if (!(width > 0)) return level > 0 ? 1.0 : 0.0;
  // On a plane wall that corner is inside exactly when part of an outside
  // sub-cell is (and outside when part of an inside one is not); where two
  // walls meet (a cone's rim) the plane is wrong and the corner tells.
  const double farLevel = v.level(far);
  if (level <= 0 && farLevel <= 0) return 0.0;
  if (level > 0 && farLevel >= 0) return 1.0;
  const double share = 0.5 + level / width;
  // Round-off of a wall on a sub-cell's face (a box's own walls): whole or nothing.
  return share >= 1.0 - 1e-9 ? 1.0 : share <= 1e-9 ? 0.0 : share;
}

// Share of the box [lo, lo + h] (h[a] = 0 on a face's normal axis) inside the
// vessel, and the centroid of that part: exact (0 or 1) when the level at the
// centre says the wall is further than the half diagonal, else the mean of
// subCellShare over the n^dim sub-cells.
double shareOf(const Vessel &v, const Vec3 &lo, const Vec3 &h, Vec3 *centroid) {
  const Vec3 centre{lo[0] + 0.5 * h[0], lo[1] + 0.5 * h[1], lo[2] + 0.5 * h[2]};
  if (centroid) *centroid = centre;
  const double level = v.level(centre);
  const double halfDiagonal = 0.5 * std::sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
  if (level > halfDiagonal) return 1.0;
  if (level < -halfDiagonal) return 0.0;
  const int n = v.samples();
  const int m[3] = {h[0] > 0 ? n : 1, h[1] > 0 ? n : 1, h[2] > 0 ? n : 1};
  const Vec3 hs{h[0] / m[0], h[1] / m[1], h[2] / m[2]};
  const double subHalfDiagonal = halfDiagonal / n;
  double inside = 0.0;
  Vec3 sum{0.0, 0.0, 0.0};
  for (int c = 0; c < m[2]; ++c)
    for (int b = 0; b < m[1]; ++b)
      for (int a = 0; a < m[0]; ++a) {
        const Vec3 x{lo[0] + (a + 0.5) / m[0] * h[0], lo[1] + (b + 0.5) / m[1] * h[1],
                     lo[2] + (c + 0.5) / m[2] * h[2]};
        const double w = subCellShare(v, x, hs, subHalfDiagonal);
        inside += w;
        for (int d = 0; d < 3; ++d) sum[d] += w * x[d];
      }
  const double total = static_cast<double>(m[0]) * m[1] * m[2];
  if (inside == total) return 1.0;
  if (centroid && inside > 0)
    for (int d = 0; d < 3; ++d) (*centroid)[d] = sum[d] / inside;
  return inside / total;
}

/// Whether a cell [lo, lo + h] lies wholly inside (1) or wholly outside (0) the
/// vessel, or neither is settled (-1), shape by shape in the vessel's order: a
/// box shape by its faces, exactly, and any other by its level at the centre
/// against the half diagonal.  Only a shortcut past the sub-sampling: a cell
/// on the wall of a box shape (every cell along the mesh's walls when the
/// vessel's box is the mesh's, as for a tube bank) lies within a half diagonal
/// of the vessel's wall, so shareOf samples it, and its samples give 1 (or 0)
/// all the same (a tube bank of 56,000 cells: 2.2 s of cutting before).
class WholeCells {
public:
  explicit WholeCells(const Vessel &vessel) {
    for (const auto &s : vessel.shapes()) {
      Vessel one;
      throwOnError([&] { return one.add(s.kind, s.p); });
      single_.emplace_back(s, std::move(one));
    }
  }
  int operator()(const Vec3 &lo, const Vec3 &h, double halfDiagonal) const {
    const Vec3 centre{lo[0] + 0.5 * h[0], lo[1] + 0.5 * h[1], lo[2] + 0.5 * h[2]};
    int state = -1;
    for (std::size_t k = 0; k < single_.size(); ++k) {
      const Vessel::Shape &s = single_[k].first;
      int in = -1; // this shape: 1 holds the cell, 0 misses it
      if (s.kind == Vessel::Kind::Box) {
        bool holds = true, misses = false;
        for (int a = 0; a < 3; ++a) {
          holds = holds && lo[a] >= s.p[2 * a] && lo[a] + h[a] <= s.p[2 * a + 1];
          misses = misses || lo[a] >= s.p[2 * a + 1] || lo[a] + h[a] <= s.p[2 * a];
        }
        in = holds ? 1 : misses ? 0 : -1;
      } else {
        const double level = single_[k].second.level(centre);
        in = level >= halfDiagonal ? 1 : level <= -halfDiagonal ? 0 : -1;
      }
      if (k == 0) state = in; // as Vessel::level: the first shape, then each united or taken away
      else if (!s.subtract) state = state == 1 || in == 1 ? 1 : state == 0 && in == 0 ? 0 : -1;
      else state = state == 0 || in == 1 ? 0 : state == 1 && in == 0 ? 1 : -1;
    }
    return state;
  }

private:
  std::vector<std::pair<Vessel::Shape, Vessel>> single_;
};

} // namespace

namespace {

// The cut over the box mesh `full` (Mesh::createBox of `box`): its faces in its own order.
VesselCut cutOf(const Vessel &vessel, const BoxSpec &box, const Mesh &full) {
  VesselCut cut;
  const Vec3 h = box.spacing();
  const int N = box.numCells();
  cut.cellShare.resize(N);
  cut.centroid.resize(N);
  // The lower corner of box cell c, moved by `shift` cells along axis a.
  auto corner = [&](int c, int a, double shift) {
    const int ijk[3] = {c % box.nx, (c / box.nx) % box.ny, c / (box.nx * box.ny)};
    Vec3 x{box.origin[0] + ijk[0] * h[0], box.origin[1] + ijk[1] * h[1], box.origin[2] + ijk[2] * h[2]};
    x[a] += shift * h[a];
    return x;
  };
  auto axisOf = [](const Vec3 &area) { return area[0] != 0.0 ? 0 : area[1] != 0.0 ? 1 : 2; };
  const WholeCells whole(vessel);
  const double halfDiagonal = 0.5 * std::sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
  for (int c = 0; c < N; ++c) {
    const Vec3 lo = corner(c, 0, 0.0);
    const int settled = whole(lo, h, halfDiagonal);
    if (settled >= 0) {
      cut.cellShare[c] = settled;
      cut.centroid[c] = {lo[0] + 0.5 * h[0], lo[1] + 0.5 * h[1], lo[2] + 0.5 * h[2]};
    } else {
      cut.cellShare[c] = shareOf(vessel, lo, h, &cut.centroid[c]);
    }
  }
  cut.faceShare.assign(full.numFaces(), 0.0);
  for (int f = 0; f < full.numFaces(); ++f) {
    const int o = full.faceOwner[f], a = axisOf(full.faceArea[f]);
    if (!(cut.cellShare[o] > 0 && cut.cellShare[full.faceNeighbour[f]] > 0)) continue;
    Vec3 face = h;
    face[a] = 0.0;
    cut.faceShare[f] = shareOf(vessel, corner(o, a, 1.0), face, nullptr);
  }
  cut.boundaryShare.assign(full.numBoundaryFaces(), 0.0);
  for (int f = 0; f < full.numBoundaryFaces(); ++f) {
    const int o = full.boundaryOwner[f], a = full.boundaryPatch[f] / 2, side = full.boundaryPatch[f] % 2;
    if (!(cut.cellShare[o] > 0)) continue;
    // Half a sub-cell inside: a wall of the box that is also the vessel's
    // (a box shape) leaves its faces open.
    Vec3 face = h;
    face[a] = 0.0;
    const double half = 0.5 / vessel.samples();
    cut.boundaryShare[f] = shareOf(vessel, corner(o, a, side == 0 ? half : 1.0 - half), face, nullptr);
  }
  return cut;
}

} // namespace

PetscErrorCode cutVessel(const Vessel &vessel, const BoxSpec &box, VesselCut *cut) {
  Mesh full;
  PetscFunctionBeginUser;
  PetscCall(Mesh::createBox(box, &full));
  PetscCallCXX(*cut = cutOf(vessel, box, full));
  PetscFunctionReturn(PETSC_SUCCESS);
}

namespace {

// The masked mesh of `cut` over the box mesh `full` (vesselMesh's work).
Mesh maskedOf(const std::string &line, const BoxSpec &box, const Mesh &full, const VesselCut &cut,
              const std::vector<int> &kept) {
  Mesh m = Mesh::masked(box, kept, line);
  m.cellCentre.reserve(kept.size());
  m.cellVolume.reserve(kept.size());
  for (int b : kept) {
    m.cellCentre.push_back(cut.centroid[b]);
    m.cellVolume.push_back(cut.cellShare[b] * full.cellVolume[b]);
  }
  auto scaled = [](Vec3 s, double share) {
    for (double &x : s) x *= share;
    return s;
  };
  for (int f = 0; f < full.numFaces(); ++f) {
    if (!(cut.faceShare[f] > 0)) continue;
    m.faceOwner.push_back(m.cellOfBoxCell(full.faceOwner[f]));
    m.faceNeighbour.push_back(m.cellOfBoxCell(full.faceNeighbour[f]));
    m.faceArea.push_back(scaled(full.faceArea[f], cut.faceShare[f]));
  }
  for (int f = 0; f < full.numBoundaryFaces(); ++f) {
    if (!(cut.boundaryShare[f] > 0)) continue;
    m.boundaryOwner.push_back(m.cellOfBoxCell(full.boundaryOwner[f]));
    m.boundaryPatch.push_back(full.boundaryPatch[f]);
    m.boundaryArea.push_back(scaled(full.boundaryArea[f], cut.boundaryShare[f]));
  }
  return m;
}

// The masked mesh of `cut` with its tiny cut cells merged (-vessel_merge_below S,
// docs/vessels.md): a group of box cells whose inside volume is below S of a box
// cell's joins the neighbouring group it shares the largest open area with (ties:
// the group of the lowest box cell), in passes over the groups in the box's
// order until none below S has an open neighbour.  A group that is one cell
// keeps that cell's numbers exactly (volume, centroid, faces' areas, in their
// order), so a mesh with nothing to merge is the unmerged one.
Mesh mergedOf(const std::string &line, double S, const BoxSpec &box, const Mesh &full, const VesselCut &cut,
              const std::vector<int> &kept) {
  const int N = box.numCells();
  auto volumeOf = [&](int b) { return cut.cellShare[b] * full.cellVolume[b]; };
  auto areaOf = [](const Vec3 &a) { return std::fabs(a[0]) + std::fabs(a[1]) + std::fabs(a[2]); };
  // Open faces of each kept box cell (the box's internal face numbers).
  std::vector<std::vector<int>> facesOf(N);
  for (int f = 0; f < full.numFaces(); ++f)
    if (cut.faceShare[f] > 0) {
      facesOf[full.faceOwner[f]].push_back(f);
      facesOf[full.faceNeighbour[f]].push_back(f);
    }
  std::vector<int> root(N, -1);
  std::vector<double> groupVolume(N, 0.0);
  std::vector<std::vector<int>> members(N);
  for (int b : kept) root[b] = b, groupVolume[b] = volumeOf(b), members[b] = {b};
  const double floor = S * full.cellVolume[kept.front()]; // every box cell has the same volume
  std::vector<std::pair<int, double>> shared;             // (neighbouring group, open area to it)
  for (bool changed = true; changed;) {
    changed = false;
    for (int g : kept) {
      if (root[g] != g || !(groupVolume[g] < floor)) continue;
      shared.clear();
      for (int b : members[g])
        for (int f : facesOf[b]) {
          const int other = root[full.faceOwner[f] == b ? full.faceNeighbour[f] : full.faceOwner[f]];
          if (other == g) continue;
          const double a = cut.faceShare[f] * areaOf(full.faceArea[f]);
          auto it = std::find_if(shared.begin(), shared.end(), [&](const auto &p) { return p.first == other; });
          if (it == shared.end()) shared.emplace_back(other, a);
          else it->second += a;
        }
      if (shared.empty()) continue; // no open neighbour: it stays alone
      auto best = shared.begin();
      for (auto it = shared.begin(); it != shared.end(); ++it)
        if (it->second > best->second || (it->second == best->second && it->first < best->first)) best = it;
      const int into = best->first;
      for (int b : members[g]) root[b] = into;
      members[into].insert(members[into].end(), members[g].begin(), members[g].end());
      members[g].clear();
      groupVolume[into] += groupVolume[g];
      groupVolume[g] = 0.0;
      changed = true;
    }
  }
  // Each group's centroid, and the member that stands for it: the one holding the centroid
  // (layers, columns and field files place the cell there), else the largest.
  struct Group {
    int own;
    double volume;
    Vec3 centre;
    std::vector<int> others;
  };
  std::vector<Group> groups;
  for (int g : kept) {
    if (root[g] != g) continue;
    std::vector<int> &m = members[g];
    std::sort(m.begin(), m.end());
    if (m.size() == 1) {
      groups.push_back({g, volumeOf(g), cut.centroid[g], {}});
      continue;
    }
    double volume = 0.0;
    Vec3 sum{0.0, 0.0, 0.0};
    for (int b : m) {
      volume += volumeOf(b);
      for (int d = 0; d < 3; ++d) sum[d] += volumeOf(b) * cut.centroid[b][d];
    }
    const Vec3 centre{sum[0] / volume, sum[1] / volume, sum[2] / volume};
    int own = box.locate(centre);
    if (!std::binary_search(m.begin(), m.end(), own)) {
      own = m.front();
      for (int b : m)
        if (volumeOf(b) > volumeOf(own)) own = b;
    }
    std::vector<int> others;
    for (int b : m)
      if (b != own) others.push_back(b);
    groups.push_back({own, volume, centre, std::move(others)});
  }
  std::sort(groups.begin(), groups.end(), [](const Group &a, const Group &b) { return a.own < b.own; });
  std::vector<int> cells;
  for (const Group &g : groups) cells.push_back(g.own);
  Mesh m = Mesh::masked(box, cells, line);
  std::vector<std::pair<int, int>> merged;
  for (std::size_t c = 0; c < groups.size(); ++c) {
    m.cellCentre.push_back(groups[c].centre);
    m.cellVolume.push_back(groups[c].volume);
    for (int b : groups[c].others) merged.emplace_back(b, static_cast<int>(c));
  }
  std::sort(merged.begin(), merged.end());
  for (const auto &[b, c] : merged) m.addMergedBoxCell(b, c);
  auto scaled = [](Vec3 s, double share) {
    for (double &x : s) x *= share;
    return s;
  };
  // Faces between two cells: one per (owner, neighbour, axis) in the order the box's first
  // gives it, with the open areas of the box's faces it gathers added.
  std::map<std::tuple<int, int, int>, int> faceOf;
  for (int f = 0; f < full.numFaces(); ++f) {
    if (!(cut.faceShare[f] > 0)) continue;
    const int o = m.cellOfBoxCell(full.faceOwner[f]), n = m.cellOfBoxCell(full.faceNeighbour[f]);
    if (o == n) continue; // inside a merged cell
    const Vec3 a = scaled(full.faceArea[f], cut.faceShare[f]);
    const int axis = a[0] != 0.0 ? 0 : a[1] != 0.0 ? 1 : 2;
    const auto [it, added] = faceOf.try_emplace({o, n, axis}, m.numFaces());
    if (added) {
      m.faceOwner.push_back(o);
      m.faceNeighbour.push_back(n);
      m.faceArea.push_back(a);
    } else {
      for (int d = 0; d < 3; ++d) m.faceArea[it->second][d] += a[d];
    }
  }
  std::map<std::pair<int, int>, int> boundaryOf;
  for (int f = 0; f < full.numBoundaryFaces(); ++f) {
    if (!(cut.boundaryShare[f] > 0)) continue;
    const int o = m.cellOfBoxCell(full.boundaryOwner[f]), patch = full.boundaryPatch[f];
    const Vec3 a = scaled(full.boundaryArea[f], cut.boundaryShare[f]);
    const auto [it, added] = boundaryOf.try_emplace({o, patch}, m.numBoundaryFaces());
    if (added) {
      m.boundaryOwner.push_back(o);
      m.boundaryPatch.push_back(patch);
      m.boundaryArea.push_back(a);
    } else {
      for (int d = 0; d < 3; ++d) m.boundaryArea[it->second][d] += a[d];
    }
  }
  return m;
}

bool whole(const std::vector<double> &shares) {
  for (double x : shares)
    if (x != 1.0) return false;
  return true;
}

} // namespace

PetscErrorCode vesselMesh(const Vessel &vessel, const BoxSpec &box, Mesh *mesh) {
  Mesh full; // its cells, faces and their order, kept where open
  VesselCut cut;
  std::vector<int> kept;
  PetscFunctionBeginUser;
  PetscCall(Mesh::createBox(box, &full));
  PetscCallCXX(cut = cutOf(vessel, box, full));
  if (whole(cut.cellShare) && whole(cut.faceShare) && whole(cut.boundaryShare)) {
    *mesh = std::move(full);
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  for (int c = 0; c < box.numCells(); ++c)
    if (cut.cellShare[c] > 0) PetscCallCXX(kept.push_back(c));
  PetscCheck(!kept.empty(), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "the vessel '%s' holds no cell of the box mesh",
             vessel.describe().c_str());
  if (vessel.mergeBelow() > 0)
    PetscCallCXX(*mesh = mergedOf(vessel.describe(), vessel.mergeBelow(), box, full, cut, kept));
  else
    PetscCallCXX(*mesh = maskedOf(vessel.describe(), box, full, cut, kept));
  PetscFunctionReturn(PETSC_SUCCESS);
}

Mesh cellsVesselMesh(const BoxSpec &box, const std::vector<char> &inside, const std::string &line) {
  if (inside.size() != static_cast<std::size_t>(box.numCells()))
    throw std::invalid_argument("a vessel of box cells needs one flag per cell of the box");
  Mesh full;
  throwOnError([&] { return Mesh::createBox(box, &full); });
  // Whole cells: share 1 inside, 0 outside; a face is open, whole, where both its cells are inside.
  VesselCut cut;
  cut.cellShare.resize(inside.size());
  std::vector<int> kept;
  for (std::size_t c = 0; c < inside.size(); ++c)
    if ((cut.cellShare[c] = inside[c] ? 1.0 : 0.0) > 0) kept.push_back(static_cast<int>(c));
  if (kept.empty()) throw std::invalid_argument("the vessel '" + line + "' holds no cell of the box mesh");
  cut.faceShare.resize(full.faceOwner.size());
  for (std::size_t f = 0; f < cut.faceShare.size(); ++f)
    cut.faceShare[f] = inside[full.faceOwner[f]] && inside[full.faceNeighbour[f]] ? 1.0 : 0.0;
  cut.boundaryShare.resize(full.boundaryOwner.size());
  for (std::size_t f = 0; f < cut.boundaryShare.size(); ++f) cut.boundaryShare[f] = inside[full.boundaryOwner[f]] ? 1.0 : 0.0;
  cut.centroid = full.cellCentre;
  return maskedOf(line, box, full, cut, kept);
}

Mesh cutVesselMesh(const Vessel &vessel, const BoxSpec &box) {
  Mesh mesh;
  throwOnError([&] { return vesselMesh(vessel, box, &mesh); });
  return mesh;
}

Vessel parseVessel(const std::string &text) {
  Vessel v;
  throwOnError([&] { return Vessel::parse(text, &v); });
  return v;
}

Vessel vesselInBox(const Vessel &vessel, const BoxSpec &box) {
  Vessel v;
  throwOnError([&] { return vessel.in(box, &v); });
  return v;
}

int Mesh::cellOfBoxCell(int b) const {
  if (cellOfBox.empty()) return b >= 0 && b < numCells() ? b : -1;
  return b >= 0 && b < static_cast<int>(cellOfBox.size()) ? cellOfBox[b] : -1;
}

Mesh Mesh::masked(const BoxSpec &spec, std::vector<int> cells, std::string vessel) {
  Mesh m;
  m.spec = spec;
  m.cellOfBox.assign(spec.numCells(), -1);
  for (std::size_t c = 0; c < cells.size(); ++c) m.cellOfBox[cells[c]] = static_cast<int>(c);
  m.boxCells = std::move(cells);
  m.vesselText = std::move(vessel);
  return m;
}

void Mesh::addMergedBoxCell(int b, int c) {
  cellOfBox.at(b) = c;
  merged.emplace_back(b, c);
}

} // namespace rcfd
