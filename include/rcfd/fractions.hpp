// Particle-size fractions and the distributed state that carries their masses.
#pragma once

#include "rcfd/handle.hpp"
#include "rcfd/layout.hpp"

#include <string>
#include <utility>
#include <vector>

namespace rcfd {

/// Most size fractions a case may have (the kernels keep per-fraction sums
/// on the stack).
inline constexpr int kMaxFractions = 64;

/// The inventory's size classes: diameter [m] and share of the total mass.
class FractionSet {
public:
  FractionSet() = default;
  /// Not collective.  Validates and builds `*set`; refuses
  /// (PETSC_ERR_ARG_OUTOFRANGE, one sentence naming the option) diameters that
  /// are not positive, shares that are negative or do not sum to 1 within
  /// 1e-6, lists of different lengths, a repeated diameter, or more than
  /// kMaxFractions fractions.  The shares are normalised to sum to 1.
  static PetscErrorCode create(std::vector<double> diameters, std::vector<double> massShares,
                               FractionSet *set);

  /// Reads -fractions_diameters d1,d2,... [m] and -fractions_mass_shares w1,w2,...
  /// (default: the paper's bi-narrow inventory).
  static PetscErrorCode fromOptions(MPI_Comm comm, FractionSet *set);

  int size() const { return static_cast<int>(d.size()); }
  double diameter(int i) const { return d[i]; }
  double massShare(int i) const { return w[i]; }
  /// Sauter mean diameter of the inventory, 1 / sum(w_i / d_i).
  double inventorySauterDiameter() const;
  /// Indices of the smallest and largest diameters.
  int smallest() const;
  int largest() const;
  /// Column label of fraction i, e.g. "d1.950mm": millimetres with three decimals,
  /// or more when two diameters would print alike (labels never collide).
  std::string label(int i) const;
  PetscErrorCode view(PetscViewer viewer) const;

private:
  /// What is wrong with the lists, in one sentence; empty when nothing is.
  static std::string problem(const std::vector<double> &diameters, const std::vector<double> &massShares);
  /// Builds from lists problem() found nothing wrong with.
  void assign(std::vector<double> diameters, std::vector<double> massShares);

  std::vector<double> d, w;
  int labelDigits = 3;
};

/// Masses [kg] of every fraction in every cell: one PETSc Vec with block size
/// nf, interleaved (cell-major), in the layout's PETSc ordering, plus a second
/// Vec of the same shape so that operators can work out of place and swap.
class FractionState {
public:
  PetscErrorCode create(const Layout &layout, int numFractions);
  int numFractions() const { return nf; }
  Vec masses() const { return current; }
  Vec scratch() const { return spare; }
  /// Make the scratch vector the current state (pointer swap, no copy).
  void swap() { std::swap(current, spare); }
  /// Total mass of each fraction (collective).
  PetscErrorCode totals(std::vector<double> *perFraction) const;
  /// Not collective.  This rank's part of totals(), summed cell by cell from
  /// the first (the order totals() adds in): the sums said with
  /// setLocalTotals() while they hold, else a pass over the occupied cells.
  PetscErrorCode localTotals(std::vector<double> *perFraction) const;
  /// Not collective.  Says, right after writing masses(), what this rank's
  /// cells hold per fraction, summed as localTotals() sums (an operator that
  /// read every occupied cell while it wrote them); trusted, like the bound
  /// below, only until the next write.
  PetscErrorCode setLocalTotals(const std::vector<double> &perFraction);
  /// Smallest mass in any cell and fraction (collective).
  PetscErrorCode minimum(double *value) const;

  /// Scalars carried with the fractions (docs/scalars.md): per cell, ns x nf
  /// extensive amounts (mass x value), scalar-major within the cell
  /// ([cell][scalar][fraction]), in a Vec of their own with the cells of
  /// masses() (and a scratch Vec for out-of-place operators).  None unless
  /// createScalars() was called: a run without scalars allocates nothing.
  PetscErrorCode createScalars(const std::vector<std::string> &names);
  int numScalars() const { return ns; }
  /// The scalars' names (-scalars), in the order of their columns.
  const std::vector<std::string> &scalarNames() const { return names; }
  Vec amounts() const { return amountNow; }
  Vec amountsScratch() const { return amountSpare; }
  void swapAmounts() { std::swap(amountNow, amountSpare); }
  /// Total amount of each scalar and fraction, [scalar][fraction] (collective).
  PetscErrorCode amountTotals(std::vector<double> *perScalarFraction) const;
  /// Not collective.  Multiplies every own cell's amount of scalar s and
  /// fraction i by factor[s * nf + i] (nothing when all are 1), the cells
  /// below `end` only when given (the others hold no mass, so no amount).
  PetscErrorCode scaleAmounts(const std::vector<double> &factor, PetscInt end = -1);
  /// Not collective.  This rank's part of amountTotals().
  PetscErrorCode localAmountTotals(std::vector<double> *perScalarFraction) const;

  /// Not collective.  One past the last own cell (local index) that may hold
  /// mass: every cell at or above it is empty.  The number of own cells when
  /// nobody said, or when the masses were written since (any write raises the
  /// Vec's PETSc state, so a bound is never trusted after a write that did
  /// not renew it).  Lets a pass over the cells leave out a bed's freeboard.
  PetscErrorCode occupiedEnd(PetscInt *end) const;
  /// Not collective.  Says, right after writing masses(), that every own cell
  /// at or above `end` is empty (an operator that knows where it put mass).
  PetscErrorCode setOccupiedEnd(PetscInt end);

private:
  int nf = 0, ns = 0;
  std::vector<std::string> names; // of the scalars
  PetscInt nlocal = 0;
  OwnedVec a, b, amountA, amountB;
  Vec current = nullptr, spare = nullptr, amountNow = nullptr, amountSpare = nullptr;
  struct Occupied { // the bound, valid for one Vec in one state
    Vec of = nullptr;
    PetscObjectState state = 0;
    PetscInt end = 0;
  } occupied;
  struct KnownSums { // localTotals() said by a writer, valid for one Vec in one state
    Vec of = nullptr;
    PetscObjectState state = 0;
    std::vector<double> sums;
  } known;
};

} // namespace rcfd
