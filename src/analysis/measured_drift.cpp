#include "analysis/measured_drift.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <unordered_map>

namespace rcfd {

MeasuredDrift::MeasuredDrift(SizeClasses c, AxisMap a, BoxSpec m)
    : classes(std::move(c)), axes(a), mesh(m) {
  const std::size_t nc = classes.diameter.size();
  frameSum.assign(nc, 0.0);
  frameSumSq.assign(nc, 0.0);
  frameCount.assign(nc, 0);
  particleCount.assign(nc, 0);
}

void MeasuredDrift::add(const ParticleSnapshot &before, const ParticleSnapshot &after, double dt) {
  if (!(dt > 0.0)) throw std::invalid_argument("measured drift: the time between snapshots must be positive");
  std::unordered_map<int64_t, std::size_t> later;
  later.reserve(after.size());
  for (std::size_t q = 0; q < after.size(); ++q) later.emplace(after.id[q], q);
  // Particles seen in both: cell at `before`, class, mass and vertical displacement.
  struct Moved {
    int cell, cls;
    double mass, dz;
  };
  std::vector<Moved> moved;
  moved.reserve(before.size());
  for (std::size_t p = 0; p < before.size(); ++p) {
    const auto it = later.find(before.id[p]);
    if (it == later.end()) continue;
    const int cls = classes.classOf(before.diameter[p]);
    const Vec3 x0 = axes.apply(before.position[p]), x1 = axes.apply(after.position[it->second]);
    const int cell = mesh.locate(x0);
    if (cls < 0 || cell < 0) continue;
    moved.push_back({cell, cls, before.mass[p], x1[2] - x0[2]});
  }
  // The bulk's displacement per cell, mass-weighted.
  std::unordered_map<int, std::pair<double, double>> bulk; // cell -> (sum m dz, sum m)
  for (const auto &m : moved) {
    auto &b = bulk[m.cell];
    b.first += m.mass * m.dz;
    b.second += m.mass;
  }
  const std::size_t nc = classes.diameter.size();
  std::vector<double> sum(nc, 0.0);
  std::vector<long> count(nc, 0);
  for (const auto &m : moved) {
    const auto &b = bulk[m.cell];
    sum[m.cls] += (m.dz - b.first / b.second) / dt;
    ++count[m.cls];
  }
  for (std::size_t c = 0; c < nc; ++c) {
    if (count[c] == 0) continue;
    const double mean = sum[c] / static_cast<double>(count[c]);
    frameSum[c] += mean;
    frameSumSq[c] += mean * mean;
    ++frameCount[c];
    particleCount[c] += count[c];
  }
  ++frames;
}

std::vector<MeasuredDrift::ClassDrift> MeasuredDrift::result() const {
  std::vector<ClassDrift> out(classes.diameter.size());
  for (std::size_t c = 0; c < out.size(); ++c) {
    ClassDrift &r = out[c];
    r.diameter = classes.diameter[c];
    r.frames = frameCount[c];
    r.particles = particleCount[c];
    if (frameCount[c] == 0) {
      r.velocity = r.standardError = std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    const double n = frameCount[c];
    r.velocity = frameSum[c] / n;
    const double variance = n > 1 ? std::max(0.0, (frameSumSq[c] - n * r.velocity * r.velocity) / (n - 1)) : 0.0;
    r.standardError = std::sqrt(variance / n);
  }
  return out;
}

DriftFit fitDriftCoefficient(const std::vector<MeasuredDrift::ClassDrift> &drift, double d32,
                             DriftLawShape shape) {
  double sxx = 0.0, sxu = 0.0;
  std::vector<std::pair<double, double>> used; // (x, u) with weight
  std::vector<double> weights;
  for (const auto &c : drift) {
    if (c.frames < 2 || !(c.standardError > 0.0) || !std::isfinite(c.velocity)) continue;
    const double dd = c.diameter - d32;
    const double x = shape == DriftLawShape::A ? c.diameter * c.diameter - d32 * d32 : dd * std::fabs(dd);
    const double w = 1.0 / (c.standardError * c.standardError);
    sxx += w * x * x;
    sxu += w * x * c.velocity;
    used.emplace_back(x, c.velocity);
    weights.push_back(w);
  }
  if (used.empty() || !(sxx > 0.0))
    throw std::invalid_argument("the measured drift has no size class with a spread over at least two "
                                "frames and a diameter other than d32: no k_d can be fitted");
  DriftFit fit;
  fit.kd = -sxu / sxx;
  fit.standardError = std::sqrt(1.0 / sxx);
  double chi2 = 0.0;
  for (std::size_t k = 0; k < used.size(); ++k) {
    const double r = used[k].second + fit.kd * used[k].first;
    chi2 += weights[k] * r * r;
  }
  fit.chiSquarePerDof = used.size() > 1 ? chi2 / static_cast<double>(used.size() - 1) : 0.0;
  return fit;
}

} // namespace rcfd
