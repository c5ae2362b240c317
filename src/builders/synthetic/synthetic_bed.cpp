// The synthetic bed's entry points: options checked, the kinematic bed
// (kinematic_bed.hpp, one file per sub-step) run through the warm-up and the
// recorded frames, and each frame's alpha_s and exact shift made from the
// parcels' cells.
#include "builders/synthetic/synthetic_bed.hpp"

#include "builders/synthetic/kinematic_bed.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace rcfd {
namespace {

/// Column-stochastic shift from parcel identities: each parcel is one
/// transfer (cell at t_k) -> (cell at t_k+1).  Equal transfers are summed here
/// and handed over already ordered by (destination, source), which keeps the
/// sort inside shiftFromTransfers cheap.
CsrMatrix shiftBetween(int numCells, const std::vector<int32_t> &from,
                       const std::vector<int32_t> &to) {
  std::vector<int32_t> start(numCells + 1, 0);
  for (int32_t c : to) ++start[c + 1];
  for (int c = 0; c < numCells; ++c) start[c + 1] += start[c];
  std::vector<int32_t> sources(from.size());
  std::vector<int32_t> fill(start.begin(), start.end() - 1);
  for (size_t p = 0; p < from.size(); ++p) sources[fill[to[p]]++] = from[p];
  std::vector<int32_t> dest, src;
  std::vector<double> weight;
  dest.reserve(from.size());
  src.reserve(from.size());
  weight.reserve(from.size());
  for (int c = 0; c < numCells; ++c) {
    auto first = sources.begin() + start[c], last = sources.begin() + start[c + 1];
    for (auto it = first; it != last; ++it) // insertion sort: a cell gets few parcels
      for (auto jt = it; jt != first && *(jt - 1) > *jt; --jt) std::iter_swap(jt - 1, jt);
    for (auto it = first; it != last;) {
      auto runEnd = std::upper_bound(it, last, *it);
      dest.push_back(c);
      src.push_back(*it);
      weight.push_back(static_cast<double>(runEnd - it));
      it = runEnd;
    }
  }
  return shiftFromTransfers(numCells, std::move(dest), std::move(src), std::move(weight));
}

std::vector<double> alphaOf(int numCells, const std::vector<int32_t> &cells, double perParcel) {
  std::vector<int> count(numCells, 0);
  for (int32_t c : cells) ++count[c];
  std::vector<double> alpha(numCells);
  for (int c = 0; c < numCells; ++c) alpha[c] = count[c] * perParcel;
  return alpha;
}

/// Largest per-axis cell distance travelled by a parcel between two states.
class JumpMeter {
public:
  explicit JumpMeter(const BoxSpec &box) : ijk_(box.numCells()) {
    for (int k = 0; k < box.nz; ++k)
      for (int j = 0; j < box.ny; ++j)
        for (int i = 0; i < box.nx; ++i) ijk_[box.cellIndex(i, j, k)] = {i, j, k};
  }
  int largest(const std::vector<int32_t> &from, const std::vector<int32_t> &to) const {
    int jump = 0;
    for (size_t p = 0; p < from.size(); ++p) {
      const auto &a = ijk_[from[p]], &b = ijk_[to[p]];
      for (int axis = 0; axis < 3; ++axis) jump = std::max(jump, std::abs(a[axis] - b[axis]));
    }
    return jump;
  }

private:
  std::vector<std::array<int, 3>> ijk_;
};

/// Height of the solid's centre of gravity [m] from the parcels' cells (all
/// parcels have the same volume; heights are cell centres, as for alpha_s).
double centreOfGravity(const BoxSpec &box, const std::vector<int32_t> &cells) {
  const int perLayer = box.nx * box.ny;
  double sum = 0.0;
  for (int32_t c : cells) sum += c / perLayer + 0.5;
  return sum / static_cast<double>(cells.size()) * box.spacing()[2];
}

void require(bool ok, const std::string &sentence) {
  if (!ok) throw std::invalid_argument("synthetic bed: " + sentence);
}

} // namespace

void validateSyntheticBedOptions(const SyntheticBedOptions &o) {
  const BoxSpec &box = o.box;
  require(box.nx >= 1 && box.ny >= 1 && box.nz >= 2, "the box needs at least 1 x 1 x 2 cells.");
  require(box.length[0] > 0.0 && box.length[1] > 0.0 && box.length[2] > 0.0,
          "the box lengths must be positive.");
  require(static_cast<double>(box.nx) * box.ny * box.nz < 2.0e9,
          "the box has too many cells for 32-bit cell indices.");
  require(o.numFrames >= 1, "numFrames must be at least 1.");
  require(o.dtRec > 0.0 && std::isfinite(o.dtRec), "dtRec must be positive.");
  require(o.maxSubstep > 0.0 && std::isfinite(o.maxSubstep), "maxSubstep must be positive.");
  require(o.dtRec / o.maxSubstep <= 1e4, "dtRec / maxSubstep must not exceed 10000 substeps.");
  require(o.warmUpTime >= 0.0 && std::isfinite(o.warmUpTime), "warmUpTime must not be negative.");
  require(o.bedHeight > 0.0, "bedHeight must be positive.");
  require(o.bedHeight < box.length[2], "bedHeight must be below the top of the box.");
  require(o.bedHeight <= 0.7 * box.length[2],
          "bedHeight must leave at least 30 % of the box height as freeboard for voids and splashes.");
  require(o.packing > 0.0 && o.packing < 0.65, "packing must be in (0, 0.65).");
  require(o.parcelsPerCell >= 1 && o.parcelsPerCell <= 1000,
          "parcelsPerCell must be between 1 and 1000.");
  const double parcels = o.bedHeight / box.length[2] * box.nz * o.parcelsPerCell *
                         static_cast<double>(box.nx) * box.ny;
  require(parcels >= 1.0, "the bed holds no parcel: raise bedHeight or parcelsPerCell.");
  require(parcels < 2.0e9, "the bed holds too many parcels: lower parcelsPerCell.");
  require(o.dispersion >= 0.0, "dispersion must not be negative.");
  require(o.surfaceDiffusivity >= 0.0, "surfaceDiffusivity must not be negative.");
  require(o.nucleationRate >= 0.0 && std::isfinite(o.nucleationRate),
          "nucleationRate must not be negative.");
  require(o.nucleationStrips >= 1 && o.nucleationStrips <= 1000,
          "nucleationStrips must be between 1 and 1000.");
  require(o.initialDiameter > 0.0, "initialDiameter must be positive.");
  require(o.maxDiameter >= o.initialDiameter, "maxDiameter must not be below initialDiameter.");
  require(o.initialDiameter < std::min(box.length[0], box.length[2]),
          "initialDiameter must be smaller than the box width and height.");
  require(o.growthLength > 0.0, "growthLength must be positive.");
  require(o.riseCoefficient > 0.0, "riseCoefficient must be positive.");
  require(o.wakeFraction >= 0.0 && o.wakeFraction <= 0.5, "wakeFraction must be in [0, 0.5].");
  require(o.bubbleWander >= 0.0, "bubbleWander must not be negative.");
  require(o.centreDrift >= 0.0 && o.centreDrift <= 1.0, "centreDrift must be in [0, 1].");
  require(o.dipoleCutoff >= 1.0, "dipoleCutoff must be at least 1 (radius).");
  require(o.eruptionRoof >= 0.0, "eruptionRoof must not be negative.");
  require(o.ejectionSpeed >= 0.0, "ejectionSpeed must not be negative.");
  require(o.gravity > 0.0, "gravity must be positive.");
}

namespace {

/// The kinematic run behind both entry points: frames go to `sink` when it is
/// given; without it only the report (the per-frame series) is made, and the
/// shifts, the costly part, are not built.  The bed's motion is the same.
SyntheticBedReport runSyntheticBed(const SyntheticBedOptions &options, const FrameSink *sink) {
  const BoxSpec &box = options.box;
  const int numCells = box.numCells();
  const Vec3 h = box.spacing();
  const double cellVolume = h[0] * h[1] * h[2];

  synthetic::SyntheticBed bed(options);
  const int substeps =
      std::max(1, static_cast<int>(std::ceil(options.dtRec / options.maxSubstep - 1e-9)));
  const double dt = options.dtRec / substeps;
  const long warmUp = static_cast<long>(std::ceil(options.warmUpTime / dt - 1e-9));
  for (long s = 0; s < warmUp; ++s) bed.advance(dt);
  bed.nucleated = bed.erupted = 0;

  SyntheticBedReport report;
  report.parcels = bed.numParcels();
  report.parcelVolume = bed.alphaPerParcel() * cellVolume;
  report.solidVolume = static_cast<double>(report.parcels) * report.parcelVolume;
  report.substepsPerFrame = substeps;

  const JumpMeter jumps(box);
  std::vector<int32_t> cells, next;
  bed.cellsOf(cells);
  const std::vector<double> alpha0 = alphaOf(numCells, cells, bed.alphaPerParcel());
  FrameRecord frame;
  frame.alphaS = alpha0;
  double heightSum = 0.0;
  report.surfaceHeight.reserve(options.numFrames);
  report.centreOfGravity.reserve(options.numFrames);
  for (int k = 0; k < options.numFrames; ++k) {
    heightSum += bed.meanSurfaceHeight();
    report.surfaceHeight.push_back(bed.meanSurfaceHeight());
    report.centreOfGravity.push_back(centreOfGravity(box, cells));
    for (int s = 0; s < substeps; ++s) bed.advance(dt);
    bed.cellsOf(next);
    report.maxAlpha = std::max(report.maxAlpha,
                               *std::max_element(frame.alphaS.begin(), frame.alphaS.end()));
    report.maxCellJump = std::max(report.maxCellJump, jumps.largest(cells, next));
    if (sink) {
      frame.shift = shiftBetween(numCells, cells, next);
      (*sink)(frame);
    }
    cells.swap(next);
    frame.alphaS = alphaOf(numCells, cells, bed.alphaPerParcel());
  }
  // frame.alphaS now holds alpha at t_K, where replay wraps to frame 0.
  report.maxAlpha =
      std::max(report.maxAlpha, *std::max_element(frame.alphaS.begin(), frame.alphaS.end()));
  for (int c = 0; c < numCells; ++c)
    report.wrapMismatchL1 += std::fabs(frame.alphaS[c] - alpha0[c]) * cellVolume;
  report.wrapMismatchRelative = report.wrapMismatchL1 / report.solidVolume;
  report.meanBedHeight = heightSum / options.numFrames;
  report.bubblesNucleated = bed.nucleated;
  report.bubblesErupted = bed.erupted;
  return report;
}

} // namespace

SyntheticBedReport generateSyntheticBed(const SyntheticBedOptions &options, const FrameSink &sink) {
  validateSyntheticBedOptions(options);
  if (!sink) throw std::invalid_argument("synthetic bed: the frame sink is empty.");
  return runSyntheticBed(options, &sink);
}

SyntheticBedReport generateSyntheticBedSeries(const SyntheticBedOptions &options) {
  validateSyntheticBedOptions(options);
  return runSyntheticBed(options, nullptr);
}

} // namespace rcfd
