// The Eulerian frame builder (eulerian_frames.hpp): options checked, frames
// fed in time order, one database frame emitted per pair, and the report.
#include "builders/eulerian/eulerian_frames.hpp"
#include "builders/eulerian/eulerian_cells.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace rcfd {
namespace {

double mean(const std::vector<EulerianFrameStats> &v, double EulerianFrameStats::*field) {
  if (v.empty()) return 0.0;
  double s = 0.0;
  for (const auto &f : v) s += f.*field;
  return s / static_cast<double>(v.size());
}

double largest(const std::vector<EulerianFrameStats> &v, double EulerianFrameStats::*field) {
  double s = 0.0;
  for (const auto &f : v) s = std::max(s, f.*field);
  return s;
}

} // namespace

void validateEulerianBuildOptions(const EulerianBuildOptions &o) {
  if (o.mesh.nx < 1 || o.mesh.ny < 1 || o.mesh.nz < 1)
    throw std::invalid_argument("the mesh needs at least one cell along each axis");
  if (!(o.dtRec > 0) || !std::isfinite(o.dtRec))
    throw std::invalid_argument("-dt_rec must be a positive time [s]");
  if (!o.cellVolume.empty() && o.cellVolume.size() != static_cast<std::size_t>(o.mesh.numCells()))
    throw std::invalid_argument("the Eulerian build's cell volumes do not match the mesh's cells");
  if (o.tracersPerCell < 1) throw std::invalid_argument("-tracers_per_cell must be at least 1");
  if (!(o.courant > 0) || o.courant > 1)
    throw std::invalid_argument("-tracer_courant must be in (0, 1]");
  if (!(o.slowCellFactor >= 0)) throw std::invalid_argument("-slow_cell_factor must be >= 0");
  if (!(o.emptyAlphaS >= 0 && o.emptyAlphaS < 1))
    throw std::invalid_argument("-empty_alpha_s must be in [0, 1)");
  if (!(o.supportSeed >= 0 && o.supportSeed < 1))
    throw std::invalid_argument("-scaling_support must be in [0, 1)");
  if (o.maxSupportRadius < 1) throw std::invalid_argument("-scaling_support_radius must be >= 1");
  if (o.scalingIterations < 0) throw std::invalid_argument("-scaling_iterations must be >= 0");
  if (!(o.scalingTolerance >= 0)) throw std::invalid_argument("-scaling_tolerance must be >= 0");
}

double EulerianBuildReport::maxResidualBefore() const {
  return largest(frame, &EulerianFrameStats::residualBefore);
}
double EulerianBuildReport::meanResidualBefore() const {
  return mean(frame, &EulerianFrameStats::residualBefore);
}
double EulerianBuildReport::maxResidualAfter() const {
  return largest(frame, &EulerianFrameStats::residualAfter);
}
double EulerianBuildReport::meanResidualAfter() const {
  return mean(frame, &EulerianFrameStats::residualAfter);
}
double EulerianBuildReport::maxMassChange() const {
  return largest(frame, &EulerianFrameStats::massChange);
}

std::string EulerianBuildReport::summary() const {
  std::ostringstream s;
  s.precision(3);
  s << "Eulerian frames: " << files << " files, " << frames << " database frames of " << cells
    << " cells\n"
    << "tracing: " << tracersPerCell << " tracers per occupied cell (" << tracers
    << " in all), velocity " << interpolation << ", at most " << maxSubsteps
    << " sub-steps; slow cells " << slowCells << ", tracers moved out of cells empty at t_k+1 "
    << redirected << ", cells reached by no tracer " << filledCells + unreachedCells
    << " (filled from neighbours " << filledCells << ")\n"
    << "shift nonzeros per column: mean " << meanNnzPerColumn << " (occupied cells "
    << meanNnzPerOccupiedColumn << "), max " << maxNnzPerColumn << "; largest alpha_s "
    << maxAlphaS << "\n"
    << "scaling support: seeds " << supportSeed << " of each occupied cell at home and at its face "
    << "neighbours; widened to 2 cells in " << framesWidened[0] << " frames, to 3 cells in "
    << framesWidened[1] << "\n"
    << "mass mismatch |T a_k - a_k+1|_1 / |a_k|_1 per frame: traced max " << maxResidualBefore()
    << ", mean " << meanResidualBefore() << "; after scaling max " << maxResidualAfter()
    << ", mean " << meanResidualAfter() << " (tolerance " << scalingTolerance << ", at most "
    << scalingIterations << " iterations, used up to " << maxIterations << "; "
    << framesAboveTolerance << " frames above the tolerance); largest change of the total "
    << "solid volume between frames " << maxMassChange();
  return s.str();
}

EulerianFrameBuilder::EulerianFrameBuilder(const EulerianBuildOptions &options, FrameSink sink)
    : opt(options), sink(std::move(sink)) {
  validateEulerianBuildOptions(opt);
  rep.cells = opt.mesh.numCells();
  rep.tracersPerCell = opt.tracersPerCell;
  rep.interpolation = opt.interpolation == TracerInterpolation::cell ? "cell-constant" : "trilinear";
  rep.scalingTolerance = opt.scalingTolerance;
  rep.scalingIterations = opt.scalingIterations;
  rep.supportSeed = opt.supportSeed;
}

void EulerianFrameBuilder::add(EulerianFrame frame) {
  const int N = opt.mesh.numCells();
  if (static_cast<int>(frame.alphaS.size()) != N)
    throw std::invalid_argument("EulerianFrameBuilder: frame '" + frame.source +
                                "' does not match the mesh's cells");
  if (!opt.cellVolume.empty()) // in a vessel: no solid where there is no vessel
    for (int c = 0; c < N; ++c)
      if (!(opt.cellVolume[c] > 0) && frame.alphaS[c] > opt.emptyAlphaS)
        throw std::runtime_error("Eulerian frame '" + frame.source + "' has solid (alpha_s = " +
                                 eulerian::number(frame.alphaS[c]) + ") in " + eulerian::cellName(opt.mesh, c) +
                                 ", which lies outside the vessel; give frames of this vessel, or a vessel that "
                                 "holds every cell with solid.");
  ++rep.files;
  for (double a : frame.alphaS) rep.maxAlphaS = std::max(rep.maxAlphaS, a);
  if (prev) {
    EulerianFrameStats st;
    FrameRecord rec;
    rec.shift = traceShift(*prev, frame.alphaS, opt, rep.frames, &st);
    rec.alphaS = std::move(prev->alphaS);
    std::vector<int> perColumn(N, 0);
    for (int32_t c : rec.shift.col) ++perColumn[c];
    for (int c = 0; c < N; ++c) {
      nnzTotal += perColumn[c];
      rep.maxNnzPerColumn = std::max(rep.maxNnzPerColumn, perColumn[c]);
      if (rec.alphaS[c] > opt.emptyAlphaS) nnzOccupied += perColumn[c], ++occupiedColumns;
    }
    rep.tracers += st.tracers;
    rep.slowCells += st.slowCells;
    rep.redirected += st.redirected;
    rep.filledCells += st.filledCells;
    rep.unreachedCells += st.unreachedCells;
    rep.maxSubsteps = std::max(rep.maxSubsteps, st.maxSubsteps);
    rep.maxIterations = std::max(rep.maxIterations, st.iterations);
    for (int r = 2; r <= std::min(st.supportRadius, 3); ++r) ++rep.framesWidened[r - 2];
    if (st.residualAfter - st.massChange > opt.scalingTolerance) ++rep.framesAboveTolerance;
    rep.frame.push_back(st);
    ++rep.frames;
    rep.meanNnzPerColumn = static_cast<double>(nnzTotal) / (static_cast<double>(N) * rep.frames);
    rep.meanNnzPerOccupiedColumn =
        occupiedColumns ? static_cast<double>(nnzOccupied) / occupiedColumns : 0.0;
    sink(rec);
  }
  prev = std::move(frame);
}

} // namespace rcfd
