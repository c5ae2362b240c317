// Kinematic stand-in for a bubbling fluidized bed (see docs/synthetic-bed.md):
// the bed's parcels and bubbles, shared by the files of its sub-steps.
//
// State: equal-volume parcels.  A parcel is either *dense* (part of the
// emulsion) or *airborne* (thrown up by an erupting bubble, or falling into a
// crater).  Dense parcels are stacked per column of cells on a lattice of
// "slots", ppc slots per cell height, one parcel per slot, so no cell ever
// holds more than ppc parcels (alpha_s <= packing) and the emulsion is exactly
// incompressible.  One kinematic substep:
//   1. bubbles nucleate at the distributor, rise at U = c sqrt(g D), wander,
//      grow with height (at a limited rate) and merge when they touch;
//   2. dense parcels move sideways with the potential flow around each bubble
//      sphere (a dipole with mirror images in the floor and walls), or with
//      the bubble when inside its sphere (the wake); their advected height,
//      plus a vertical random walk, is only a sort key;
//   3. airborne parcels fly ballistically;
//   4. the surface is levelled: parcels slide from higher to lower columns;
//   5. every column is restacked: dense parcels sorted by key are laid from
//      the floor, one per slot, jumping over the part of each bubble chord
//      above the bubble's wake (the void); airborne parcels that reach the
//      surface land on it;
//   6. horizontal dispersion swaps parcels between neighbouring columns;
//   7. gaps under voids are filled from neighbouring columns, balanced by
//      pushing as many parcels out from above the void (flow around bubbles);
//   8. bubbles with a thin roof erupt: the roof is thrown up and the void
//      closes gradually.
// Randomness comes from one xoshiro256** stream and only IEEE-exact operations
// (+ - * / sqrt floor ceil) shape the state, so a seed gives the same frames
// with any standard library (given IEEE doubles without FMA contraction).
//
// Where each sub-step lives (all in src/builders/synthetic/):
//   kinematic_bed.cpp      the settled bed, one substep (advance), cells of the parcels
//   bubbles.cpp            1. nucleation, rise, wander, growth and coalescence
//   bubble_flow.cpp        2. the dipole flow around the bubbles that moves dense parcels
//   airborne_parcels.cpp   3. ballistic flight, and landing on a column (5.)
//   surface_levelling.cpp  4. parcels sliding from higher to lower columns
//   column_stacking.cpp    5. void chords and the restacking of every column
//   column_dispersion.cpp  6. swaps between neighbouring columns
//   wake_filling.cpp       7. gaps under voids filled from neighbouring columns
//   eruption.cpp           8. eruption of bubbles with a thin roof
// synthetic_bed.cpp runs the substeps and turns the parcels into frames.
#pragma once

#include "builders/synthetic/synthetic_bed.hpp"

#include "base/random.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace rcfd::synthetic {

/// The project's xoshiro256** (src/base/random.hpp) with the draws the
/// kinematics use.
class Rng {
public:
  explicit Rng(std::uint64_t seed) : generator(seed) {}
  std::uint64_t next() { return generator.next(); }
  /// Uniform in [0, 1).
  double uniform() { return generator.uniform(); }
  /// Uniform in [-1, 1).
  double symmetric() { return 2.0 * uniform() - 1.0; }

private:
  Xoshiro256 generator;
};

struct Bubble {
  double x, y, z;    // centre, from the box origin
  double diameter;   // current diameter of the sphere
  double target;     // diameter it grows towards: growth law, merged volume
  double wanderX = 0.0, wanderY = 0.0; // lateral random-walk velocity
  double ux = 0.0, uy = 0.0, uz = 0.0; // current velocity
  bool newborn = true;
  bool absorbed = false; // merged or erupted: shrinks away at shrinkRate
  bool erupted = false;
  double shrinkRate = 0.0;
  int centreColumn = 0;
  int roof = 0;      // dense parcels above the void in the centre column
  double radius() const { return 0.5 * diameter; }
};

/// Potential flow around a sphere moving with velocity V, or one of its mirror
/// images: u = R^3 / (2 r^3) (3 (V.e_r) e_r - V) for r > R.
struct Dipole {
  double cx, cy, cz;
  double vx, vy, vz;
  double halfR3;
  double cut2;
  double r2;
  int bubble; // index of the real bubble, -1 for an image
};

/// The part of a bubble's chord through one column that is void: parcels
/// whose advected height is above zCentre are laid from topSlot up.
struct VoidChord {
  double zCentre;
  int topSlot;
  int wakeTopSlot; // the wake (solid) should reach this slot from below
  int bubble;
  int belowTop;    // slot where the solid below the void ended at the last restack, -1: no solid above
  int aboveStart;  // slot where the solid above the void starts
};

/// The kinematic bed: its parcels and bubbles, moved one substep at a time.
class SyntheticBed {
public:
  explicit SyntheticBed(const SyntheticBedOptions &options);

  void advance(double dt);
  /// Natural cell index of every parcel.
  void cellsOf(std::vector<int32_t> &cells) const;
  /// The cell cellOf(x, y, layer) of every parcel (x, y from the box origin, layer
  /// its cell layer), by parcel identity: for a vessel the bed's square is mapped into.
  template <typename CellOf> void cellsOf(std::vector<int32_t> &cells, CellOf &&cellOf) const {
    const size_t n = x_.size();
    cells.resize(n);
    for (size_t p = 0; p < n; ++p)
      cells[id_[p]] = cellOf(x_[p], y_[p], airborne_[p] ? layerOf(z_[p]) : slot_[p] / ppc_);
  }
  /// The cell cellAt(x, y, z) of every parcel (its position from the box origin),
  /// by parcel identity: for a vessel of any shape the bed's box is mapped into
  /// (vessel_map.hpp).  A dense parcel's height is its slot's, spread over the
  /// slot by a fixed share of its own (the golden-ratio sequence of its identity):
  /// a layer of the vessel thinner than a slot (a cone's tip, squeezed upwards)
  /// then gets its share of each slot's parcels, not all of them or none.
  template <typename CellAt> void cellsAt(std::vector<int32_t> &cells, CellAt &&cellAt) const {
    constexpr double golden = 0.61803398874989484820;
    const size_t n = x_.size();
    cells.resize(n);
    for (size_t p = 0; p < n; ++p) {
      const double spread = id_[p] * golden - std::floor(id_[p] * golden);
      cells[id_[p]] = cellAt(x_[p], y_[p], airborne_[p] ? z_[p] : (slot_[p] + spread) * slotHeight_);
    }
  }
  double meanSurfaceHeight() const;
  long numParcels() const { return static_cast<long>(x_.size()); }
  double alphaPerParcel() const { return opt_.packing / opt_.parcelsPerCell; }
  long nucleated = 0, erupted = 0;

private:
  void nucleate(double dt);
  void openBubble(double u, double v);
  void moveBubbles(double dt);
  void mergeBubbles();
  void buildDipoles();
  void buildVoids();
  void advectDense(double dt);
  void advectAirborne(double dt);
  void levelSurface(double dt);
  void slideParcels(int from, int to, int count);
  void restack();
  void stackColumn(int c);
  int layColumn(int c);
  void disperse(double dt);
  int32_t parcelAtSlot(int c, int slot) const;
  void fillWakeGaps(double dt);
  int neighboursByAxisDistance(int c, const Bubble &b, bool backward,
                               std::pair<double, int> *out) const;
  void queuePushes(int c, int fromSlot, int target, int count);
  void applyPushes();
  int pullFrom(int donor, int receiver, int fromSlot, int toSlot, int most);
  void renumber();
  void settleAirborne(std::vector<int32_t> &dense, int &cursor);
  void eruptBubbles();
  void eject(int k);
  void compactColumn(int c);

  int columnOf(double x, double y) const {
    const int i = std::min(nx_ - 1, static_cast<int>(x * invHx_));
    const int j = std::min(ny_ - 1, static_cast<int>(y * invHy_));
    return i + nx_ * j;
  }
  int binOf(int i, int j, int k) const { return i / 2 + bx_ * (j / 2 + by_ * k); }
  int layerOf(double z) const {
    return std::min(nz_ - 1, std::max(0, static_cast<int>(std::floor(z / hz_))));
  }
  double riseVelocity(double d) const {
    return opt_.riseCoefficient * std::sqrt(opt_.gravity * d);
  }
  /// Lowest allowed centre coordinate of a sphere of radius r between walls
  /// `length` apart: one cell clear of the walls (a sphere touching a wall
  /// spoils the flow there), and held in the middle when it cannot be.
  double centreMargin(double r, double length, double h) const {
    return std::min(r + h, 0.5 * length);
  }
  void keepCentreInside(Bubble &b) const {
    const double mx = centreMargin(b.radius(), lx_, hx_), my = centreMargin(b.radius(), ly_, hy_);
    b.x = std::min(std::max(b.x, mx), lx_ - mx);
    b.y = std::min(std::max(b.y, my), ly_ - my);
  }

  SyntheticBedOptions opt_;
  Rng rng_;
  int nx_, ny_, nz_, ncol_, ppc_, maxSlots_;
  double lx_, ly_, lz_, hx_, hy_, hz_, invHx_, invHy_;
  double slotHeight_;   // height of one parcel in a dense stack
  double wakeLevel_;    // new bubbles keep parcels below centre + wakeLevel * R as wake
  double diameterCap_;  // merged bubbles stay narrower than the bed

  // Parcels.
  std::vector<double> x_, y_, z_, zKey_, vx_, vy_, vz_;
  std::vector<int32_t> slot_, id_;
  std::vector<uint8_t> airborne_, pulled_;
  long substeps_ = 0;
  // Steady nucleation: bubbles still due (a bubble when it drops to 0), and
  // the strips of the distributor in this round's order.
  double nucleationDue_ = 0.0;
  bool nucleationStarted_ = false;
  std::vector<int> stripOrder_;
  int stripCursor_ = 0;
  // Parcels grouped by column: dense in slot order, then airborne.
  std::vector<int32_t> order_, colStart_, denseEnd_, top_;
  std::vector<Bubble> bubbles_;
  std::vector<Dipole> dipoles_;
  int bx_, by_;                              // dipole bins: 2 x 2 columns x 1 layer
  std::vector<int32_t> binStart_, binDipoles_;
  std::vector<VoidChord> voids_;
  std::vector<int32_t> voidStart_;
  // Scratch.
  std::vector<int32_t> column_, previousColumn_, voidColumn_, fill_, scratch_, dense_, air_, keys_, keyCount_, cellCount_;
  std::vector<int32_t> received_, given_, largestDrop_;
  struct Transfer {
    int from, to;
    double amount;
  };
  std::vector<Transfer> transfers_;
  std::vector<std::pair<int32_t, int32_t>> pushes_; // (parcel, target column), see fillWakeGaps
  std::vector<double> wantedBy_;
};

} // namespace rcfd::synthetic
