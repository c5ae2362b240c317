// The synthetic bed's entry points: options checked, the kinematic bed
// (kinematic_bed.hpp, one file per sub-step) run through the warm-up and the
// recorded frames, and each frame's alpha_s and exact shift made from the
// parcels' cells.
#include "builders/synthetic/synthetic_bed.hpp"

#include "builders/synthetic/kinematic_bed.hpp"
#include "builders/synthetic/vessel_map.hpp"
#include "mesh/vessel_mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace rcfd {
namespace {

constexpr double kMaxBubbleFlux = 10.0; // [m/s] gas through the distributor in new bubbles, at most

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

/// alpha_s of each cell of a vessel's mesh: its parcels' volume over its inside volume.
std::vector<double> alphaIn(const Mesh &mesh, const std::vector<int32_t> &cells, double parcelVolume) {
  std::vector<int> count(mesh.numCells(), 0);
  for (int32_t c : cells) ++count[c];
  std::vector<double> alpha(mesh.numCells());
  for (int c = 0; c < mesh.numCells(); ++c) alpha[c] = count[c] * parcelVolume / mesh.cellVolume[c];
  return alpha;
}

/// Where a parcel of the bed's square lands in a vertical cylinder: Shirley and
/// Chiu's concentric map takes the square onto the disk with a constant
/// Jacobian, so a square of the disk's area keeps the bed's density (its
/// alpha_s) on average, and neighbours stay neighbours.  A cell takes at most
/// the parcels that fill its inside volume (alpha_s <= 1): a cell the wall
/// leaves small would otherwise show alpha_s > 1 for one parcel; the parcels it
/// cannot take go to the next cell towards the axis.  Call start() before the
/// parcels of each state.
class CylinderMap {
public:
  CylinderMap(const BoxSpec &box, const Mesh &mesh, const Vessel::Shape &cylinder, double side, double parcelVolume)
      : box_(box), mesh_(mesh), cx_(cylinder.p[0]), cy_(cylinder.p[1]), radius_(cylinder.p[2]), side_(side),
        capacity_(mesh.numCells()) {
    for (int c = 0; c < mesh.numCells(); ++c)
      capacity_[c] = static_cast<int>(std::floor(mesh.cellVolume[c] / parcelVolume * (1.0 + 1e-12)));
  }
  CylinderMap &start() {
    held_.assign(capacity_.size(), 0);
    return *this;
  }
  int32_t operator()(double x, double y, int layer) {
    const double a = std::min(1.0, std::max(-1.0, 2.0 * x / side_ - 1.0));
    const double b = std::min(1.0, std::max(-1.0, 2.0 * y / side_ - 1.0));
    constexpr double quarterPi = 0.78539816339744830962;
    double r = 0.0, phi = 0.0;
    if (std::fabs(a) > std::fabs(b)) r = a, phi = quarterPi * (b / a);
    else if (b != 0.0) r = b, phi = 2.0 * quarterPi - quarterPi * (a / b);
    const Vec3 h = box_.spacing();
    int i = static_cast<int>(std::floor((cx_ + radius_ * r * std::cos(phi) - box_.origin[0]) / h[0]));
    int j = static_cast<int>(std::floor((cy_ + radius_ * r * std::sin(phi) - box_.origin[1]) / h[1]));
    i = std::min(box_.nx - 1, std::max(0, i));
    j = std::min(box_.ny - 1, std::max(0, j));
    // A point inside the disk in a cell whose samples all fell outside: the
    // next cell towards the axis (the mask is the same in every layer).
    const int ic = static_cast<int>(std::floor((cx_ - box_.origin[0]) / h[0]));
    const int jc = static_cast<int>(std::floor((cy_ - box_.origin[1]) / h[1]));
    int cell = mesh_.cellOfBoxCell(box_.cellIndex(i, j, layer));
    while ((cell < 0 || held_[cell] >= capacity_[cell]) && (i != ic || j != jc)) {
      if (std::abs(i - ic) >= std::abs(j - jc)) i += i < ic ? 1 : -1;
      else j += j < jc ? 1 : -1;
      cell = mesh_.cellOfBoxCell(box_.cellIndex(i, j, layer));
    }
    if (cell < 0) throw std::logic_error("synthetic bed: a parcel found no cell of the cylinder");
    ++held_[cell]; // the axis cell takes what is left (alpha_s > 1 there is refused by the loader)
    return cell;
  }

private:
  const BoxSpec &box_;
  const Mesh &mesh_;
  double cx_, cy_, radius_, side_;
  std::vector<int> capacity_, held_;
};

/// Largest per-axis cell distance travelled by a parcel between two states.
class JumpMeter {
public:
  explicit JumpMeter(const BoxSpec &box) : ijk_(box.numCells()) {
    for (int k = 0; k < box.nz; ++k)
      for (int j = 0; j < box.ny; ++j)
        for (int i = 0; i < box.nx; ++i) ijk_[box.cellIndex(i, j, k)] = {i, j, k};
  }
  /// The same for the cells of a vessel's mesh (their box cells' indices).
  JumpMeter(const BoxSpec &box, const Mesh &mesh) : ijk_(mesh.numCells()) {
    for (int c = 0; c < mesh.numCells(); ++c) {
      const int b = mesh.boxCell(c);
      ijk_[c] = {b % box.nx, (b / box.nx) % box.ny, b / (box.nx * box.ny)};
    }
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
double centreOfGravity(const BoxSpec &box, const std::vector<int32_t> &cells, const Mesh *vessel = nullptr) {
  const int perLayer = box.nx * box.ny;
  double sum = 0.0;
  if (vessel)
    for (int32_t c : cells) sum += vessel->boxCell(c) / perLayer + 0.5;
  else
    for (int32_t c : cells) sum += c / perLayer + 0.5;
  return sum / static_cast<double>(cells.size()) * box.spacing()[2];
}

void require(bool ok, const std::string &sentence) {
  if (!ok) throw std::invalid_argument("synthetic bed: " + sentence);
}

/// One vertical cylinder through the box's height, inside its cross-section:
/// the bed runs in a square of its area and CylinderMap takes it into the disk
/// (its bits since the cylinder came).  Every other vessel: a host box and
/// VesselMap (vessel_map.hpp).
bool cylinderThroughBox(const SyntheticBedOptions &o) {
  const BoxSpec &box = o.box;
  const auto &shapes = o.vessel.shapes();
  if (shapes.size() != 1 || shapes[0].kind != Vessel::Kind::Cylinder) return false;
  const auto &p = shapes[0].p;
  const double slack = 1e-12 * std::max(box.length[0], box.length[1]);
  return (p.size() == 3 || (p[3] <= box.origin[2] && p[4] >= box.origin[2] + box.length[2])) &&
         p[0] - p[2] >= box.origin[0] - slack && p[0] + p[2] <= box.origin[0] + box.length[0] + slack &&
         p[1] - p[2] >= box.origin[1] - slack && p[1] + p[2] <= box.origin[1] + box.length[1] + slack;
}

} // namespace

void validateSyntheticBedOptions(const SyntheticBedOptions &o, const Mesh *vesselMesh) {
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
  // The gas the new bubbles carry through the distributor, R pi/6 D0^3, is the
  // visible bubble flow of two-phase theory, below u_sup - u_mf: a few m/s in
  // any bubbling bed.  Far beyond it the bed is all bubbles (each substep
  // would open thousands per square decimetre) and the build never ends.
  require(o.nucleationRate * std::acos(-1.0) / 6.0 * std::pow(o.initialDiameter, 3) <= kMaxBubbleFlux,
          "nucleationRate times the new bubble's volume (pi/6 initialDiameter^3) must not exceed " +
              std::to_string(static_cast<int>(kMaxBubbleFlux)) + " m/s of gas in bubbles.");
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
  if (o.vessel.isWholeBox()) return;
  if (!cylinderThroughBox(o)) { // the host box must hold a bed (it checks itself)
    synthetic::hostBedOptions(o, vesselMesh ? *vesselMesh : cutVesselMesh(o.vessel, box));
    return;
  }
  const auto &p = o.vessel.shapes()[0].p;
  SyntheticBedOptions square = o; // the square the bed runs in must hold a bed too
  square.vessel = Vessel();
  square.box.length[0] = square.box.length[1] = p[2] * std::sqrt(kPi);
  validateSyntheticBedOptions(square);
}

namespace {

/// The kinematic run behind both entry points: frames go to `sink` when it is
/// given; without it only the report (the per-frame series) is made, and the
/// shifts, the costly part, are not built.  The bed's motion is the same.
SyntheticBedReport runSyntheticBed(const SyntheticBedOptions &options, const FrameSink *sink,
                                   const Mesh *vesselMesh) {
  const BoxSpec &box = options.box;
  // In a cylinder the bed runs in a square of the same area (CylinderMap), in
  // any other vessel in a host box of the vessel's volume (VesselMap), and its
  // frames are on the vessel's cells; in the box, as it always did.
  const bool inVessel = !options.vessel.isWholeBox();
  const bool shaped = inVessel && !cylinderThroughBox(options);
  const Mesh mesh = !inVessel ? Mesh() : vesselMesh ? *vesselMesh : cutVesselMesh(options.vessel, box);
  SyntheticBedOptions square = shaped ? synthetic::hostBedOptions(options, mesh) : options;
  if (inVessel && !shaped)
    square.box.length[0] = square.box.length[1] = options.vessel.shapes()[0].p[2] * std::sqrt(kPi);
  const int numCells = inVessel ? mesh.numCells() : box.numCells();
  const Vec3 h = square.box.spacing();
  const double cellVolume = h[0] * h[1] * h[2]; // of the bed's own cells

  synthetic::SyntheticBed bed(square);
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

  const JumpMeter jumps = inVessel ? JumpMeter(box, mesh) : JumpMeter(box);
  std::unique_ptr<CylinderMap> map;
  std::unique_ptr<synthetic::VesselMap> shapedMap;
  if (shaped) shapedMap = std::make_unique<synthetic::VesselMap>(box, square.box, mesh, report.parcelVolume);
  else if (inVessel)
    map = std::make_unique<CylinderMap>(box, mesh, options.vessel.shapes()[0], square.box.length[0],
                                        report.parcelVolume);
  auto cellsOf = [&](std::vector<int32_t> &out) {
    if (shapedMap) bed.cellsAt(out, shapedMap->start());
    else if (map) bed.cellsOf(out, map->start());
    else bed.cellsOf(out);
  };
  // The surface height in the vessel: the host's mapped (the same height elsewhere).
  auto surfaceHeight = [&] {
    return shapedMap ? shapedMap->height(bed.meanSurfaceHeight()) : bed.meanSurfaceHeight();
  };
  auto alphaOfCells = [&](const std::vector<int32_t> &of) {
    return inVessel ? alphaIn(mesh, of, report.parcelVolume) : alphaOf(numCells, of, bed.alphaPerParcel());
  };
  std::vector<int32_t> cells, next;
  cellsOf(cells);
  const std::vector<double> alpha0 = alphaOfCells(cells);
  FrameRecord frame;
  frame.alphaS = alpha0;
  double heightSum = 0.0;
  report.surfaceHeight.reserve(options.numFrames);
  report.centreOfGravity.reserve(options.numFrames);
  for (int k = 0; k < options.numFrames; ++k) {
    heightSum += surfaceHeight();
    report.surfaceHeight.push_back(surfaceHeight());
    report.centreOfGravity.push_back(centreOfGravity(box, cells, inVessel ? &mesh : nullptr));
    for (int s = 0; s < substeps; ++s) bed.advance(dt);
    cellsOf(next);
    report.maxAlpha = std::max(report.maxAlpha,
                               *std::max_element(frame.alphaS.begin(), frame.alphaS.end()));
    report.maxCellJump = std::max(report.maxCellJump, jumps.largest(cells, next));
    if (sink) {
      frame.shift = shiftBetween(numCells, cells, next);
      (*sink)(frame);
    }
    cells.swap(next);
    frame.alphaS = alphaOfCells(cells);
  }
  // frame.alphaS now holds alpha at t_K, where replay wraps to frame 0.
  report.maxAlpha =
      std::max(report.maxAlpha, *std::max_element(frame.alphaS.begin(), frame.alphaS.end()));
  for (int c = 0; c < numCells; ++c)
    report.wrapMismatchL1 += std::fabs(frame.alphaS[c] - alpha0[c]) * (inVessel ? mesh.cellVolume[c] : cellVolume);
  report.wrapMismatchRelative = report.wrapMismatchL1 / report.solidVolume;
  report.meanBedHeight = heightSum / options.numFrames;
  report.bubblesNucleated = bed.nucleated;
  report.bubblesErupted = bed.erupted;
  return report;
}

} // namespace

SyntheticBedReport generateSyntheticBed(const SyntheticBedOptions &options, const FrameSink &sink,
                                        const Mesh *vesselMesh) {
  validateSyntheticBedOptions(options, vesselMesh);
  if (!sink) throw std::invalid_argument("synthetic bed: the frame sink is empty.");
  return runSyntheticBed(options, &sink, vesselMesh);
}

SyntheticBedReport generateSyntheticBedSeries(const SyntheticBedOptions &options, const Mesh *vesselMesh) {
  validateSyntheticBedOptions(options, vesselMesh);
  return runSyntheticBed(options, nullptr, vesselMesh);
}

} // namespace rcfd
