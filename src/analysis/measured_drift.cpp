#include "analysis/measured_drift.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace rcfd {

MeasuredDrift::MeasuredDrift(SizeClasses c, AxisMap a, BoxSpec m)
    : classes(std::move(c)), axes(a), mesh(m) {
  const std::size_t nc = classes.diameter.size();
  frameSum.assign(nc, 0.0);
  frameSumSq.assign(nc, 0.0);
  frameCount.assign(nc, 0);
  particleCount.assign(nc, 0);
  classMass.assign(nc, 0.0);
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
    classMass[m.cls] += m.mass;
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
  double allMass = 0.0;
  for (double m : classMass) allMass += m;
  for (std::size_t c = 0; c < out.size(); ++c) {
    ClassDrift &r = out[c];
    if (allMass > 0.0) r.massShare = classMass[c] / allMass;
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

std::vector<double> measuredDriftTable(const std::vector<MeasuredDrift::ClassDrift> &drift) {
  std::vector<double> t;
  for (const auto &c : drift)
    t.insert(t.end(), {c.diameter, c.velocity, c.standardError, static_cast<double>(c.particles),
                       static_cast<double>(c.frames), c.massShare});
  return t;
}

std::vector<MeasuredDrift::ClassDrift> measuredDriftFromTable(const std::vector<double> &t, int cols) {
  if (cols != kMeasuredDriftColumns || t.size() % kMeasuredDriftColumns != 0)
    throw std::invalid_argument("a measured-drift table has " + std::to_string(kMeasuredDriftColumns) +
                                " columns (diameter, velocity, standard error, particles, frames, mass "
                                "share), this one " + std::to_string(cols));
  std::vector<MeasuredDrift::ClassDrift> out;
  for (std::size_t r = 0; r < t.size(); r += kMeasuredDriftColumns)
    out.push_back({t[r], t[r + 1], t[r + 2], static_cast<long>(t[r + 3]), static_cast<int>(t[r + 4]), t[r + 5]});
  return out;
}

DriftFit fitDriftCoefficient(const std::vector<MeasuredDrift::ClassDrift> &drift, double d32,
                             DriftLawShape shape, bool relativeToBulk) {
  auto lawOf = [&](double d) {
    const double dd = d - d32;
    return shape == DriftLawShape::A ? d * d - d32 * d32 : dd * std::fabs(dd);
  };
  double mean = 0.0; // sum_j s_j x_j over the classes with a mass share
  if (relativeToBulk)
    for (const auto &c : drift)
      if (std::isfinite(c.massShare)) mean += c.massShare * lawOf(c.diameter);
  double sxx = 0.0, sxu = 0.0;
  std::vector<std::pair<double, double>> used; // (x, u) with weight
  std::vector<double> weights;
  for (const auto &c : drift) {
    if (c.frames < 2 || !(c.standardError > 0.0) || !std::isfinite(c.velocity)) continue;
    const double x = lawOf(c.diameter) - mean;
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
