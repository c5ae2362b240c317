#include "analysis/measured_drift.hpp"
#include "rcfd/size_law.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace rcfd {

namespace {

// One frame's mean of every entry seen (sum / count) added to the sums of per-frame means.
void addFrameMeans(const std::vector<double> &sum, const std::vector<long> &count, std::vector<double> &frameSum,
                   std::vector<double> &frameSumSq, std::vector<int> &frameCount, std::vector<long> &particles) {
  for (std::size_t k = 0; k < sum.size(); ++k) {
    if (count[k] == 0) continue;
    const double mean = sum[k] / static_cast<double>(count[k]);
    frameSum[k] += mean;
    frameSumSq[k] += mean * mean;
    ++frameCount[k];
    particles[k] += count[k];
  }
}

// Mean and standard error of per-frame means from their count, sum and sum of squares.
void frameStatistics(int count, double sum, double sumSq, MeasuredDrift::ClassDrift *r) {
  r->frames = count;
  if (count == 0) {
    r->velocity = r->standardError = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  const double n = count;
  r->velocity = sum / n;
  const double variance = n > 1 ? std::max(0.0, (sumSq - n * r->velocity * r->velocity) / (n - 1)) : 0.0;
  r->standardError = std::sqrt(variance / n);
}

} // namespace

MeasuredDrift::MeasuredDrift(SizeClasses c, AxisMap a, BoxSpec m)
    : classes(std::move(c)), axes(a), mesh(m) {
  const std::size_t nc = classes.diameter.size();
  frameSum.assign(nc, 0.0);
  frameSumSq.assign(nc, 0.0);
  frameCount.assign(nc, 0);
  particleCount.assign(nc, 0);
  classMass.assign(nc, 0.0);
  const std::size_t nb = kAgitationBins * nc;
  binFrameSum.assign(nb, 0.0);
  binFrameSumSq.assign(nb, 0.0);
  binClassMass.assign(nb, 0.0);
  binFrameCount.assign(nb, 0);
  binParticles.assign(nb, 0);
  binAgitationSum.assign(kAgitationBins, 0.0);
  binMass.assign(kAgitationBins, 0.0);
}

std::vector<MatchedParticle> matchParticles(const ParticleSnapshot &before, const ParticleSnapshot &after,
                                            const SizeClasses &classes, const AxisMap &axes, const BoxSpec &mesh) {
  std::unordered_map<int64_t, std::size_t> later;
  later.reserve(after.size());
  for (std::size_t q = 0; q < after.size(); ++q) later.emplace(after.id[q], q);
  std::vector<MatchedParticle> moved;
  moved.reserve(before.size());
  for (std::size_t p = 0; p < before.size(); ++p) {
    const auto it = later.find(before.id[p]);
    if (it == later.end()) continue;
    const int cls = classes.classOf(before.diameter[p]);
    const Vec3 x0 = axes.apply(before.position[p]), x1 = axes.apply(after.position[it->second]);
    const int cell = mesh.locate(x0);
    if (cls < 0 || cell < 0) continue;
    moved.push_back({cell, cls, before.mass[p], x1[2] - x0[2], mesh.locate(x1) != cell});
  }
  return moved;
}

void MeasuredDrift::add(const ParticleSnapshot &before, const ParticleSnapshot &after, double dt) {
  if (!(dt > 0.0)) throw std::invalid_argument("measured drift: the time between snapshots must be positive");
  const std::vector<MatchedParticle> moved = matchParticles(before, after, classes, axes, mesh);
  // The bulk's displacement per cell, mass-weighted.
  std::unordered_map<int, std::pair<double, double>> bulk; // cell -> (sum m dz, sum m)
  std::unordered_map<int, double> leftMass;                 // cell -> mass found elsewhere
  for (const auto &m : moved) {
    auto &b = bulk[m.cell];
    b.first += m.mass * m.dz;
    b.second += m.mass;
    if (m.left) leftMass[m.cell] += m.mass;
  }
  const std::size_t nc = classes.diameter.size();
  std::vector<double> sum(nc, 0.0);
  std::vector<long> count(nc, 0);
  const std::size_t nb = kAgitationBins * nc;
  std::vector<double> binSum(nb, 0.0);
  std::vector<long> binCount(nb, 0);
  for (const auto &m : moved) {
    const auto &b = bulk[m.cell];
    const double u = (m.dz - b.first / b.second) / dt;
    sum[m.cls] += u;
    ++count[m.cls];
    classMass[m.cls] += m.mass;
    const double a = leftMass[m.cell] / b.second;
    const int bin = std::min(kAgitationBins - 1, static_cast<int>(a * kAgitationBins));
    binSum[bin * nc + m.cls] += u;
    ++binCount[bin * nc + m.cls];
    binClassMass[bin * nc + m.cls] += m.mass;
    binAgitationSum[bin] += m.mass * a;
    binMass[bin] += m.mass;
    agitationSum += m.mass * a;
    agitationMass += m.mass;
  }
  addFrameMeans(binSum, binCount, binFrameSum, binFrameSumSq, binFrameCount, binParticles);
  addFrameMeans(sum, count, frameSum, frameSumSq, frameCount, particleCount);
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
    r.particles = particleCount[c];
    frameStatistics(frameCount[c], frameSum[c], frameSumSq[c], &r);
  }
  return out;
}


std::vector<MeasuredDrift::BinDrift> MeasuredDrift::byAgitation() const {
  const std::size_t nc = classes.diameter.size();
  std::vector<BinDrift> out(kAgitationBins * nc);
  for (int b = 0; b < kAgitationBins; ++b)
    for (std::size_t c = 0; c < nc; ++c) {
      const std::size_t k = b * nc + c;
      BinDrift &r = out[k];
      r.agitation = binMass[b] > 0.0 ? binAgitationSum[b] / binMass[b] : (b + 0.5) / kAgitationBins;
      r.drift.diameter = classes.diameter[c];
      r.drift.particles = binParticles[k];
      if (binMass[b] > 0.0) r.drift.massShare = binClassMass[k] / binMass[b];
      frameStatistics(binFrameCount[k], binFrameSum[k], binFrameSumSq[k], &r.drift);
    }
  return out;
}

std::vector<double> driftByAgitationTable(const std::vector<MeasuredDrift::BinDrift> &bins) {
  std::vector<double> t;
  for (const auto &b : bins) {
    t.push_back(b.agitation);
    const auto row = measuredDriftTable({b.drift});
    t.insert(t.end(), row.begin(), row.end());
  }
  return t;
}

std::vector<MeasuredDrift::BinDrift> driftByAgitationFromTable(const std::vector<double> &t, int cols) {
  if (cols != kDriftByAgitationColumns || t.size() % kDriftByAgitationColumns != 0)
    throw std::invalid_argument("a drift-by-agitation table has " + std::to_string(kDriftByAgitationColumns) +
                                " columns, this one " + std::to_string(cols));
  std::vector<MeasuredDrift::BinDrift> out;
  for (std::size_t r = 0; r < t.size(); r += kDriftByAgitationColumns) {
    const std::vector<double> row(t.begin() + r + 1, t.begin() + r + kDriftByAgitationColumns);
    out.push_back({t[r], measuredDriftFromTable(row, kMeasuredDriftColumns)[0]});
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

namespace {

// The law's shape g_i = u_i at k = 1 for each class, less sum_j s_j g_j when
// relative to the bulk.
std::vector<double> lawShape(const std::vector<MeasuredDrift::ClassDrift> &drift, double d32, const SizeLaw &law,
                             bool relativeToBulk) {
  std::vector<double> d, g(drift.size());
  for (const auto &c : drift) d.push_back(c.diameter);
  law.velocities(1.0, d32, d.data(), static_cast<int>(d.size()), g.data());
  double mean = 0.0; // sum_j s_j g_j over the classes with a mass share
  if (relativeToBulk)
    for (std::size_t c = 0; c < drift.size(); ++c)
      if (std::isfinite(drift[c].massShare)) mean += drift[c].massShare * g[c];
  for (double &x : g) x -= mean;
  return g;
}

} // namespace

DriftFit fitDriftCoefficient(const std::vector<MeasuredDrift::ClassDrift> &drift, double d32, const SizeLaw &law,
                             bool relativeToBulk) {
  const std::vector<double> g = lawShape(drift, d32, law, relativeToBulk);
  double sgg = 0.0, sgu = 0.0;
  int used = 0;
  auto usable = [](const MeasuredDrift::ClassDrift &c) {
    return c.frames >= 2 && c.standardError > 0.0 && std::isfinite(c.velocity);
  };
  for (std::size_t c = 0; c < drift.size(); ++c) {
    if (!usable(drift[c])) continue;
    const double w = 1.0 / (drift[c].standardError * drift[c].standardError);
    sgg += w * g[c] * g[c];
    sgu += w * g[c] * drift[c].velocity;
    ++used;
  }
  if (used == 0 || !(sgg > 0.0))
    throw std::invalid_argument("the measured drift has no size class with a spread over at least two "
                                "frames and a diameter other than d32: no k_d can be fitted");
  DriftFit fit;
  fit.kd = sgu / sgg;
  fit.standardError = std::sqrt(1.0 / sgg);
  for (std::size_t c = 0; c < drift.size(); ++c) {
    fit.predicted.push_back(fit.kd * g[c]);
    fit.residual.push_back(drift[c].velocity - fit.predicted.back());
    if (usable(drift[c])) fit.chiSquare += fit.residual.back() * fit.residual.back() / (drift[c].standardError * drift[c].standardError);
  }
  fit.chiSquarePerDof = used > 1 ? fit.chiSquare / static_cast<double>(used - 1) : 0.0;
  return fit;
}

DriftFit fitDriftLaw(const std::vector<MeasuredDrift::ClassDrift> &drift, double d32, SizeLaw &law) {
  SizeLaw::ShapeParameter p;
  int used = 0;
  for (const auto &c : drift) used += c.frames >= 2 && c.standardError > 0.0 && std::isfinite(c.velocity);
  // Two classes fit any one-parameter law exactly: a shape needs three.
  if (!law.shapeParameter(&p) || used < 3) return fitDriftCoefficient(drift, d32, law, true);
  DriftFit best;
  double bestValue = p.value;
  bool found = false;
  for (int step = 0; p.low + step * 0.01 <= p.high + 1e-12; ++step) {
    const double value = p.low + step * 0.01;
    law.setShapeParameter(value);
    const DriftFit fit = fitDriftCoefficient(drift, d32, law, true);
    if (!found || fit.chiSquare < best.chiSquare) best = fit, bestValue = value, found = true;
  }
  law.setShapeParameter(bestValue);
  best.shape = bestValue;
  best.chiSquarePerDof = used > 2 ? best.chiSquare / static_cast<double>(used - 2) : 0.0;
  return best;
}

} // namespace rcfd

namespace rcfd {

AgitationDriftFit fitAgitationExponent(const std::vector<MeasuredDrift::BinDrift> &bins,
                                       const std::vector<MeasuredDrift::ClassDrift> &bed, double aBar,
                                       double d32, const SizeLaw &law, double nMax) {
  // g_i - sum_j s_j g_j of the whole bed, by diameter.
  const std::vector<double> g = lawShape(bed, d32, law, true);
  auto shapeOf = [&](double d) {
    for (std::size_t c = 0; c < bed.size(); ++c)
      if (bed[c].diameter == d) return g[c];
    throw std::invalid_argument("the drift by agitation has a class the bed does not have");
  };
  struct Point {
    double x, r, u, w; // size term, a / a_bar, velocity, weight
  };
  std::vector<Point> points;
  for (const auto &b : bins)
    if (b.drift.frames >= 2 && b.drift.standardError > 0.0 && std::isfinite(b.drift.velocity) && b.agitation > 0.0)
      points.push_back({shapeOf(b.drift.diameter), b.agitation / aBar, b.drift.velocity,
                        1.0 / (b.drift.standardError * b.drift.standardError)});
  if (points.size() < 2 || !(aBar > 0.0))
    throw std::invalid_argument("the drift by agitation has fewer than two bins with a spread over two frames: "
                                "no exponent can be fitted");
  AgitationDriftFit best;
  double bestChi2 = std::numeric_limits<double>::infinity();
  for (int step = 0; step <= static_cast<int>(std::lround(nMax * 100)); ++step) {
    const double n = step / 100.0;
    double sxx = 0.0, sxu = 0.0;
    for (const Point &p : points) {
      const double x = p.x * std::pow(p.r, n);
      sxx += p.w * x * x;
      sxu += p.w * x * p.u;
    }
    if (!(sxx > 0.0)) continue;
    const double kd = sxu / sxx;
    double chi2 = 0.0;
    for (const Point &p : points) {
      const double res = p.u - kd * p.x * std::pow(p.r, n);
      chi2 += p.w * res * res;
    }
    if (chi2 < bestChi2) bestChi2 = chi2, best = {kd, n, chi2 / static_cast<double>(points.size() - 2)};
  }
  return best;
}

} // namespace rcfd
