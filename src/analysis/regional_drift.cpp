#include "analysis/regional_drift.hpp"

#include <stdexcept>

namespace rcfd {

RegionalDrift::RegionalDrift(SizeClasses c, AxisMap a, BoxSpec m, DriftRegions r)
    : classes(std::move(c)), axes(a), mesh(m), regions(r) {
  if (regions.rx < 1 || regions.ry < 1 || regions.rz < 1)
    throw std::invalid_argument("measured drift regions need at least one cell along each axis");
}

void RegionalDrift::add(const ParticleSnapshot &before, const ParticleSnapshot &after, double dt) {
  if (!(dt > 0.0)) throw std::invalid_argument("measured drift: the time between snapshots must be positive");
  const std::vector<MatchedParticle> moved = matchParticles(before, after, classes, axes, mesh);
  std::vector<double> cellMoment(mesh.numCells(), 0.0), cellMass(mesh.numCells(), 0.0);
  for (const MatchedParticle &p : moved) {
    cellMoment[p.cell] += p.mass * p.dz;
    cellMass[p.cell] += p.mass;
  }
  const int cols = columns();
  const std::size_t first = rows.size();
  rows.resize(first + static_cast<std::size_t>(regions.count(mesh)) * cols, 0.0);
  double *frame = rows.data() + first;
  for (const MatchedParticle &p : moved) { // sum m u, particles, sum m per region and class
    double *v = frame + static_cast<std::size_t>(regions.regionOf(mesh, p.cell)) * cols +
                kMeasuredDriftValuesPerClass * p.cls;
    v[0] += p.mass * (p.dz - cellMoment[p.cell] / cellMass[p.cell]) / dt;
    v[1] += 1.0;
    v[2] += p.mass;
  }
  for (double *v = frame; v < rows.data() + rows.size(); v += kMeasuredDriftValuesPerClass)
    if (v[2] > 0.0) v[0] /= v[2];
  ++frames;
}

std::vector<double> RegionalDrift::layoutRow() const {
  std::vector<double> row{static_cast<double>(regions.rx), static_cast<double>(regions.ry),
                          static_cast<double>(regions.rz)};
  row.insert(row.end(), classes.diameter.begin(), classes.diameter.end());
  return row;
}

double RegionalDrift::shareBelow(long n) const {
  long occupied = 0, few = 0;
  for (std::size_t k = 1; k < rows.size(); k += kMeasuredDriftValuesPerClass)
    if (rows[k] > 0) {
      ++occupied;
      few += rows[k] < static_cast<double>(n);
    }
  return occupied ? static_cast<double>(few) / static_cast<double>(occupied) : 0.0;
}

} // namespace rcfd
