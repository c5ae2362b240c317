#include "builders/particles/particle_builder.hpp"

#include "base/constants.hpp"
#include "database/csr.hpp"
#include "builders/particles/particle_vessel.hpp"
#include "mesh/vessel_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <utility>

namespace rcfd {
namespace {

double maxAbsDiff(const std::vector<double> &a, const std::vector<double> &b) {
  double m = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, std::fabs(a[i] - b[i]));
  return m;
}

} // namespace

std::string ParticleBuildReport::summary() const {
  char buf[1600];
  std::snprintf(
      buf, sizeof buf,
      "snapshots %zu, frames %zu, cells %d, particles %zu (%.6g kg), particle volume by %s\n"
      "nonzeros per column: mean %.3f (occupied cells %.3f), max %d\n"
      "appeared %zu (%.6g kg), vanished %zu (%.6g kg), entered mesh %zu (%.6g kg), left mesh %zu "
      "(%.6g kg)\n"
      "outside the mesh: %zu particle-snapshots, at most %zu in one snapshot\n"
      "alpha_s: max %.4f, %zu cell-snapshots with alpha_s >= 1\n"
      "max |T alpha_k - alpha_k+1| = %.3e, max |T m_k - m_k+1| = %.3e kg",
      snapshots, frames, cells, particles, totalMass, particleVolumeName(volume), meanNnzPerColumn, meanNnzPerOccupiedColumn,
      maxNnzPerColumn, appeared, appearedMass, vanished, vanishedMass, enteredMesh, enteredMeshMass,
      leftMesh, leftMeshMass, outside, maxOutsidePerSnapshot, maxAlphaS, cellsAlphaAtLeastOne,
      maxAlphaResidual, maxMassResidual);
  return buf;
}

std::vector<std::size_t> selectSnapshots(std::size_t available, const ParticleBuildOptions &opt) {
  if (opt.stride < 1) throw std::invalid_argument("particle build: the stride must be at least 1");
  if (opt.first >= available)
    throw std::invalid_argument("particle build: the window starts at snapshot " +
                                std::to_string(opt.first) + " but there are only " +
                                std::to_string(available));
  if (opt.last < opt.first)
    throw std::invalid_argument("particle build: the window ends before it starts");
  const std::size_t last = std::min(opt.last, available - 1);
  std::vector<std::size_t> sel;
  for (std::size_t s = opt.first; s <= last; s += static_cast<std::size_t>(opt.stride))
    sel.push_back(s);
  return sel;
}

ParticleFrameBuilder::ParticleFrameBuilder(const ParticleBuildOptions &options, FrameSink frameSink)
    : opt(options), sink(std::move(frameSink)) {
  opt.axes.validate();
  const int n = numCells = opt.vessel ? opt.vessel->numCells() : opt.mesh.numCells();
  if (n <= 0) throw std::invalid_argument("particle build: the mesh has no cells");
  if (opt.vessel && (!opt.vessel->onBoxLattice() || opt.vessel->boxSpec().numCells() != opt.mesh.numCells()))
    throw std::invalid_argument("particle build: the vessel's mesh is not cut from the build's box");
  // A vessel of the cells particles reached has no shapes: its cells are its inside.
  cellsVessel = opt.vessel && VisitedCells::names(opt.vessel->vessel());
  if (opt.vessel && !cellsVessel) vesselShape = parseVessel(opt.vessel->vessel());
  const Vec3 h = opt.mesh.spacing();
  cellVolume = h[0] * h[1] * h[2];
  if (!(cellVolume > 0.0))
    throw std::invalid_argument("particle build: the mesh cells have no volume");
  rep.cells = n;
  rep.volume = opt.volume;
}

// Cells of every particle, alpha_s and mass per cell; the list sorted by id
// so that two snapshots can be matched by a merge.
void ParticleFrameBuilder::place(const ParticleSnapshot &snap) {
  const int n = numCells;
  cur.particles.resize(snap.size());
  cur.shares.clear();
  alphaCur.assign(n, 0.0);
  massCur.assign(n, 0.0);
  std::size_t outside = 0;
  for (std::size_t p = 0; p < snap.size(); ++p) {
    const double d = snap.diameter[p];
    const Vec3 x = opt.axes.apply(snap.position[p]);
    cellShares(opt.mesh, x, d, opt.volume, scratch);
    if (opt.vessel && !scratch.empty()) toVesselCells(cellsVessel || vesselShape.contains(x) ? opt.mesh.locate(x) : -1);
    cur.particles[p] = {snap.id[p], snap.mass[p], cur.shares.size(), scratch.size()};
    if (scratch.empty()) ++outside;
    const double volume = kPi / 6.0 * d * d * d;
    for (const CellShare &s : scratch) {
      alphaCur[s.cell] += volume * s.share;
      massCur[s.cell] += snap.mass[p] * s.share;
      cur.shares.push_back(s);
    }
  }
  for (std::size_t c = 0; c < alphaCur.size(); ++c) {
    double &a = alphaCur[c];
    a /= opt.vessel ? opt.vessel->cellVolume[c] : cellVolume;
    rep.maxAlphaS = std::max(rep.maxAlphaS, a);
    if (a >= 1.0) ++rep.cellsAlphaAtLeastOne;
  }
  rep.outside += outside;
  rep.maxOutsidePerSnapshot = std::max(rep.maxOutsidePerSnapshot, outside);

  std::vector<Placement> &list = cur.particles;
  std::sort(list.begin(), list.end(),
            [](const Placement &a, const Placement &b) { return a.id < b.id; });
  const auto dup = std::adjacent_find(
      list.begin(), list.end(), [](const Placement &a, const Placement &b) { return a.id == b.id; });
  if (dup != list.end())
    throw std::runtime_error("particle snapshot '" + snap.source + "' lists particle id " +
                             std::to_string(dup->id) +
                             " more than once, so particles cannot be matched between snapshots.");
}

// The shares of a particle (box cells) as the vessel's cells: the parts in box
// cells outside the vessel, and beyond the wall of cut cells, go to the cell of
// its centre; a centre outside the
// vessel (its shapes, not only its cells: a particle beyond the wall of a cut
// cell would crowd that cell's small volume) puts the particle outside the
// mesh (no share).  Equal cells merged.
void ParticleFrameBuilder::toVesselCells(int centreBoxCell) {
  const Mesh &v = *opt.vessel;
  const int centre = centreBoxCell >= 0 ? v.cellOfBoxCell(centreBoxCell) : -1;
  if (centre < 0) {
    scratch.clear();
    return;
  }
  // Another cell keeps of its part only its inside share (its volume over its
  // box cell's, the part of the sphere's overlap with it that is not beyond
  // the wall, taken as uniform), so that a small cut cell is not crowded.
  const double boxVolume = cellVolume;
  double toCentre = 0.0;
  std::size_t kept = 0;
  for (std::size_t k = 0; k < scratch.size(); ++k) {
    const CellShare s = scratch[k]; // a copy: scratch[kept] may be this entry
    const int c = v.cellOfBoxCell(s.cell);
    if (c < 0 || c == centre) {
      toCentre += s.share;
      continue;
    }
    const double inside = std::min(1.0, v.cellVolume[c] / boxVolume);
    scratch[kept++] = {c, s.share * inside};
    toCentre += s.share * (1.0 - inside);
  }
  scratch.resize(kept);
  if (toCentre > 0.0) scratch.push_back({centre, toCentre});
}

// Merge the id-sorted lists of t_k (prev) and t_{k+1} (next) into transfers:
// every pair of a particle's cells at t_k and at t_{k+1}, weighted by the
// product of its shares and its mass.
CsrMatrix ParticleFrameBuilder::shiftTo(const Snapshot &next) {
  std::vector<int32_t> dest, src;
  std::vector<double> weight;
  dest.reserve(prev.shares.size());
  src.reserve(prev.shares.size());
  weight.reserve(prev.shares.size());
  auto stays = [&](const Placement &p) { // its mass stays in its cells at t_k
    for (std::size_t a = p.first; a < p.first + p.count; ++a) {
      const CellShare &from = prev.shares[a];
      dest.push_back(from.cell);
      src.push_back(from.cell);
      weight.push_back(p.mass * from.share);
    }
  };
  std::vector<double> leaving, arriving;
  auto moves = [&](const Placement &p, const Placement &q) {
    if (p.count == 1 && q.count == 1) { // whole particle from one cell to one cell
      dest.push_back(next.shares[q.first].cell);
      src.push_back(prev.shares[p.first].cell);
      weight.push_back(p.mass * prev.shares[p.first].share * next.shares[q.first].share);
      return;
    }
    // The share a cell holds at both times stays in it; only what one cell
    // loses and others gain moves, in proportion (any split with these sums
    // keeps T m_k = m_{k+1}; this one leaves a resting particle in place).
    leaving.assign(p.count, 0.0);
    arriving.assign(q.count, 0.0);
    double moved = 0.0;
    for (std::size_t a = 0; a < p.count; ++a) {
      const CellShare &from = prev.shares[p.first + a];
      leaving[a] = from.share;
      for (std::size_t b = 0; b < q.count; ++b)
        if (next.shares[q.first + b].cell == from.cell) {
          const double kept = std::min(from.share, next.shares[q.first + b].share);
          leaving[a] -= kept;
          arriving[b] -= kept;
          dest.push_back(from.cell);
          src.push_back(from.cell);
          weight.push_back(p.mass * kept);
        }
      moved += leaving[a];
    }
    if (!(moved > 0.0)) return;
    for (std::size_t b = 0; b < q.count; ++b) arriving[b] += next.shares[q.first + b].share;
    for (std::size_t a = 0; a < p.count; ++a)
      for (std::size_t b = 0; b < q.count; ++b)
        if (leaving[a] > 0.0 && arriving[b] > 0.0) {
          dest.push_back(next.shares[q.first + b].cell);
          src.push_back(prev.shares[p.first + a].cell);
          weight.push_back(p.mass * leaving[a] * arriving[b] / moved);
        }
  };
  const std::vector<Placement> &before = prev.particles, &after = next.particles;
  std::size_t a = 0, b = 0;
  while (a < before.size() || b < after.size()) {
    if (b == after.size() || (a < before.size() && before[a].id < after[b].id)) { // vanished
      const Placement &p = before[a++];
      ++rep.vanished;
      rep.vanishedMass += p.mass;
      stays(p);                                                   // where it was last seen
    } else if (a == before.size() || after[b].id < before[a].id) { // appeared
      const Placement &q = after[b++];
      ++rep.appeared;
      rep.appearedMass += q.mass;
    } else { // the same particle at t_k and t_{k+1}
      const Placement &p = before[a++], &q = after[b++];
      if (p.count > 0 && q.count > 0) {
        moves(p, q);
      } else if (p.count > 0) {
        ++rep.leftMesh;
        rep.leftMeshMass += p.mass;
        stays(p);
      } else if (q.count > 0) {
        ++rep.enteredMesh;
        rep.enteredMeshMass += q.mass;
      }
    }
  }
  return shiftFromTransfers(numCells, std::move(dest), std::move(src),
                            std::move(weight));
}

// Column statistics and the residuals of T_k against the next snapshot.
void ParticleFrameBuilder::account(const CsrMatrix &T, const std::vector<double> &alphaK,
                                   const std::vector<double> &massK) {
  std::vector<int> perColumn(T.n, 0);
  for (int32_t c : T.col) ++perColumn[c];
  for (int i = 0; i < T.n; ++i) {
    rep.maxNnzPerColumn = std::max(rep.maxNnzPerColumn, perColumn[i]);
    nnzTotal += perColumn[i];
    if (massK[i] > 0.0) {
      nnzOccupied += perColumn[i];
      ++occupiedColumns;
    }
  }
  const double columns = static_cast<double>(rep.frames) * T.n;
  rep.meanNnzPerColumn = nnzTotal / columns;
  rep.meanNnzPerOccupiedColumn = occupiedColumns ? double(nnzOccupied) / occupiedColumns : 0.0;

  std::vector<double> y;
  multiply(T, alphaK, y);
  rep.maxAlphaResidual = std::max(rep.maxAlphaResidual, maxAbsDiff(y, alphaCur));
  multiply(T, massK, y);
  rep.maxMassResidual = std::max(rep.maxMassResidual, maxAbsDiff(y, massCur));
}

void ParticleFrameBuilder::add(const ParticleSnapshot &snap) {
  if (rep.snapshots > 0 && snap.timestep >= 0 && prevTimestep >= 0 && snap.timestep <= prevTimestep)
    throw std::runtime_error("particle snapshot '" + snap.source + "' has timestep " +
                             std::to_string(snap.timestep) + ", not after the previous one (" +
                             std::to_string(prevTimestep) +
                             "); snapshots must come in time order.");
  place(snap);
  if (rep.snapshots == 0) {
    rep.particles = snap.size();
    for (double m : snap.mass) rep.totalMass += m;
  } else {
    ++rep.frames;
    frame.shift = shiftTo(cur);
    account(frame.shift, alphaPrev, massPrev);
    frame.alphaS.swap(alphaPrev);
    if (sink) sink(frame);
  }
  ++rep.snapshots;
  prevTimestep = snap.timestep;
  std::swap(prev, cur);
  std::swap(alphaPrev, alphaCur);
  std::swap(massPrev, massCur);
}

ParticleBuildReport buildFramesFromSnapshots(const std::vector<std::string> &files,
                                             const ParticleBuildOptions &opt,
                                             const FrameSink &sink) {
  const std::vector<std::size_t> sel = selectSnapshots(files.size(), opt);
  if (sel.size() < 2)
    throw std::invalid_argument("particle build: the window and stride select " +
                                std::to_string(sel.size()) + " snapshot(s); a frame needs two");
  ParticleFrameBuilder builder(opt, sink);
  for (std::size_t s : sel) builder.add(readParticleSnapshot(files[s], opt.read));
  return builder.report();
}

} // namespace rcfd
