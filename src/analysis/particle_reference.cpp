#include "analysis/particle_reference.hpp"

#include "base/atomic_file.hpp"
#include "base/constants.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numeric>
#include <stdexcept>

namespace rcfd {
namespace {



/// Mass-median height: the height of the particle at which the cumulative
/// mass, counted from the bottom, first reaches half the total.  That
/// particle (and any at the same height) belongs to the bottom half.
double massMedianHeight(const std::vector<Vec3> &pos, const std::vector<double> &mass) {
  if (pos.empty()) return 0.0;
  std::vector<std::size_t> order(pos.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return pos[a][2] < pos[b][2]; });
  const double half = 0.5 * std::accumulate(mass.begin(), mass.end(), 0.0);
  double cum = 0.0;
  for (std::size_t p : order) {
    cum += mass[p];
    if (cum >= half) return pos[p][2];
  }
  return pos[order.back()][2];
}

} // namespace

// ---------------------------------------------------------------- reference

ParticleReference::ParticleReference(ReferenceOptions options) : opt(std::move(options)) {
  opt.axes.validate();
  std::sort(opt.classes.diameter.begin(), opt.classes.diameter.end());
  if (opt.profileMesh && opt.profileMesh->numCells() <= 0)
    throw std::invalid_argument("ParticleReference: the profile mesh has no cells");
}

double ParticleReference::deltaZ(const CogSample &s) const {
  if (s.zClass.size() < 2) return 0.0;
  return s.zClass.front() - s.zClass.back();
}

void ParticleReference::add(double time, const ParticleSnapshot &snap) {
  if (opt.classes.diameter.empty()) {
    opt.classes = SizeClasses::cluster(snap.diameter, opt.classes.relTol);
    if (opt.classes.diameter.empty())
      throw std::runtime_error("particle snapshot '" + snap.source +
                               "' holds no particles, so no size classes can be found in it.");
  }
  const std::size_t nc = opt.classes.diameter.size();
  std::vector<Vec3> pos(snap.size());
  std::vector<int> cls(snap.size());
  for (std::size_t p = 0; p < snap.size(); ++p) {
    pos[p] = opt.axes.apply(snap.position[p]);
    cls[p] = opt.classes.classOf(snap.diameter[p]);
    if (cls[p] < 0) {
      char buf[96];
      std::snprintf(buf, sizeof buf, "%.4f mm", snap.diameter[p] * 1e3);
      throw std::runtime_error("particle snapshot '" + snap.source + "': particle id " +
                               std::to_string(snap.id[p]) + " has diameter " + buf +
                               ", which is within the tolerance of no size class.");
    }
  }

  CogSample s;
  s.time = time;
  std::vector<double> massClass(nc, 0.0), momentClass(nc, 0.0);
  double mass = 0.0, moment = 0.0;
  for (std::size_t p = 0; p < snap.size(); ++p) {
    mass += snap.mass[p];
    moment += snap.mass[p] * pos[p][2];
    massClass[cls[p]] += snap.mass[p];
    momentClass[cls[p]] += snap.mass[p] * pos[p][2];
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  s.zBed = mass > 0.0 ? moment / mass : nan;
  for (std::size_t c = 0; c < nc; ++c)
    s.zClass.push_back(massClass[c] > 0.0 ? momentClass[c] / massClass[c] : nan);

  s.zMedian = massMedianHeight(pos, snap.mass);
  std::vector<double> lower(nc, 0.0);
  for (std::size_t p = 0; p < snap.size(); ++p)
    lower[cls[p]] += snap.mass[p] * shareBelow(pos[p][2], snap.diameter[p], s.zMedian);
  for (std::size_t c = 0; c < nc; ++c)
    s.lowerShare.push_back(massClass[c] > 0.0 ? lower[c] / massClass[c] : nan);

  if (time >= opt.windowBegin && time <= opt.windowEnd) accumulateWindow(pos, cls, snap, s.zMedian);
  samples.push_back(std::move(s));
}

void ParticleReference::accumulateWindow(const std::vector<Vec3> &pos, const std::vector<int> &cls,
                                         const ParticleSnapshot &snap, double zMedian) {
  const std::size_t nc = opt.classes.diameter.size();
  ++inWindow;
  bottomSum.resize(nc, 0.0);
  topSum.resize(nc, 0.0);
  std::vector<double> bottom(nc, 0.0), top(nc, 0.0);
  for (std::size_t p = 0; p < snap.size(); ++p) {
    const double below = shareBelow(pos[p][2], snap.diameter[p], zMedian);
    if (below > 0.0) bottom[cls[p]] += snap.mass[p] * below;
    if (below < 1.0) top[cls[p]] += snap.mass[p] * (1.0 - below);
  }
  const double bottomTotal = std::accumulate(bottom.begin(), bottom.end(), 0.0);
  const double topTotal = std::accumulate(top.begin(), top.end(), 0.0);
  for (std::size_t c = 0; c < nc; ++c) {
    if (bottomTotal > 0.0) bottomSum[c] += bottom[c] / bottomTotal;
    if (topTotal > 0.0) topSum[c] += top[c] / topTotal;
  }

  if (!opt.profileMesh) return;
  const BoxSpec &m = *opt.profileMesh;
  const Vec3 h = m.spacing();
  const double layerVolume = m.length[0] * m.length[1] * h[2];
  profileSum.resize(nc);
  for (auto &layer : profileSum) layer.resize(m.nz, 0.0);
  std::vector<CellShare> layers;
  for (std::size_t p = 0; p < snap.size(); ++p) {
    if (m.locate(pos[p]) < 0) {
      ++outsideProfile;
      continue;
    }
    const double d = snap.diameter[p];
    layerShares(m.origin[2], h[2], m.nz, pos[p][2], d, opt.volume, layers);
    for (const CellShare &l : layers)
      profileSum[cls[p]][l.cell] += kPi / 6.0 * d * d * d / layerVolume * l.share;
  }
}

double ParticleReference::shareBelow(double z, double d, double zMedian) const {
  if (opt.volume == ParticleVolume::Centre || !(d > 0.0)) return z <= zMedian ? 1.0 : 0.0;
  const double R = 0.5 * d;
  return sphereVolumeBelow(R, zMedian - z) / sphereVolumeBelow(R, R);
}

std::vector<std::vector<double>> ParticleReference::profiles() const {
  if (inWindow == 0) return {};
  std::vector<std::vector<double>> mean = profileSum;
  for (auto &layer : mean)
    for (double &v : layer) v /= static_cast<double>(inWindow);
  return mean;
}

ParticleReference::Halves ParticleReference::halves() const {
  if (inWindow == 0) return {};
  Halves h{bottomSum, topSum};
  for (double &v : h.bottom) v /= static_cast<double>(inWindow);
  for (double &v : h.top) v /= static_cast<double>(inWindow);
  return h;
}

void ParticleReference::writeCogCsv(const std::string &path) const {
  // The columns and their names are those of rcfd run's cog.csv (SI units in
  // the names), so that the two files compare column by column.
  AtomicTextFile f(path); // complete under its name, or not there
  const std::size_t nc = opt.classes.diameter.size();
  std::fprintf(f.get(), "time_s,z_cog_bed_m");
  for (std::size_t c = 0; c < nc; ++c)
    std::fprintf(f.get(), ",z_cog_%s_m", opt.classes.label(static_cast<int>(c)).c_str());
  std::fprintf(f.get(), ",delta_z_m\n");
  for (const CogSample &s : samples) {
    std::fprintf(f.get(), "%.9g,%.9g", s.time, s.zBed);
    for (double z : s.zClass) std::fprintf(f.get(), ",%.9g", z);
    std::fprintf(f.get(), ",%.9g\n", deltaZ(s));
  }
  f.commit();
}

void ParticleReference::writeProfilesCsv(const std::string &path) const {
  if (!opt.profileMesh) throw std::logic_error("ParticleReference: no profile mesh was given");
  const BoxSpec &m = *opt.profileMesh;
  const auto prof = profiles();
  AtomicTextFile f(path); // complete under its name, or not there
  std::fprintf(
      f.get(),
      "# SI units: z [m] layer centre; alpha = solid volume of the class's particles %s "
      "the layer / layer volume, mean over %zu snapshots in [%g, %g] s\nz",
      opt.volume == ParticleVolume::Overlap ? "(the parts of them) in" : "centred in", inWindow, opt.windowBegin, opt.windowEnd);
  const std::size_t nc = opt.classes.diameter.size();
  for (std::size_t c = 0; c < nc; ++c)
    std::fprintf(f.get(), ",alpha_%s", opt.classes.label(static_cast<int>(c)).c_str());
  std::fprintf(f.get(), ",alpha_total\n");
  for (int k = 0; k < m.nz; ++k) {
    std::fprintf(f.get(), "%.9g", m.origin[2] + (k + 0.5) * m.spacing()[2]);
    double total = 0.0;
    for (std::size_t c = 0; c < nc; ++c) {
      const double v = prof.empty() ? 0.0 : prof[c][k];
      total += v;
      std::fprintf(f.get(), ",%.9g", v);
    }
    std::fprintf(f.get(), ",%.9g\n", total);
  }
  f.commit();
}

void ParticleReference::writeHalvesCsv(const std::string &path) const {
  const Halves h = halves();
  AtomicTextFile f(path); // complete under its name, or not there
  std::fprintf(
      f.get(),
      "# mass fractions of each size class below / above the bed's mass-median height, mean "
      "over %zu snapshots in [%g, %g] s; diameter [m]\n"
      "class,diameter,bottom_mass_fraction,top_mass_fraction\n",
      inWindow, opt.windowBegin, opt.windowEnd);
  for (std::size_t c = 0; c < opt.classes.diameter.size(); ++c)
    std::fprintf(f.get(), "%s,%.9g,%.9g,%.9g\n", opt.classes.label(static_cast<int>(c)).c_str(),
                 opt.classes.diameter[c], c < h.bottom.size() ? h.bottom[c] : 0.0,
                 c < h.top.size() ? h.top[c] : 0.0);
  f.commit();
}

} // namespace rcfd
