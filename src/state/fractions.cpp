#include "rcfd/fractions.hpp"
#include "base/petsc_compat.hpp"

#include "base/checked_options.hpp"
#include "base/collective.hpp"
#include "state/cell_passes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

namespace rcfd {

std::string FractionSet::problem(const std::vector<double> &d, const std::vector<double> &w) {
  if (d.empty()) return "-fractions_diameters: at least one diameter is needed";
  if (d.size() > static_cast<size_t>(kMaxFractions))
    return "-fractions_diameters has " + std::to_string(d.size()) + " diameters; rcfd handles at most " +
           std::to_string(kMaxFractions) + " fractions";
  if (d.size() != w.size())
    return "-fractions_mass_shares has " + std::to_string(w.size()) + " values but -fractions_diameters has " +
           std::to_string(d.size()) + "; give one mass share per diameter";
  for (size_t i = 0; i < d.size(); ++i)
    if (!(d[i] > 0.0) || !std::isfinite(d[i]))
      return "-fractions_diameters: diameter " + std::to_string(i + 1) + " is " + std::to_string(d[i]) +
             ", expected a positive length in m";
  for (size_t i = 0; i < w.size(); ++i)
    if (!(w[i] >= 0.0) || !std::isfinite(w[i]))
      return "-fractions_mass_shares: share " + std::to_string(i + 1) + " is " + std::to_string(w[i]) +
             ", expected a number in [0, 1]";
  const double sum = std::accumulate(w.begin(), w.end(), 0.0);
  if (std::fabs(sum - 1.0) > 1e-6)
    return "-fractions_mass_shares sum to " + std::to_string(sum) + ", expected 1 (within 1e-6)";
  for (size_t i = 0; i < d.size(); ++i)
    for (size_t j = i + 1; j < d.size(); ++j)
      if (d[i] == d[j])
        return "-fractions_diameters: diameters " + std::to_string(i + 1) + " and " + std::to_string(j + 1) +
               " are equal; give each size once";
  return {};
}

void FractionSet::assign(std::vector<double> diameters, std::vector<double> massShares) {
  d = std::move(diameters);
  w = std::move(massShares);
  const double sum = std::accumulate(w.begin(), w.end(), 0.0);
  for (double &x : w) x /= sum; // exact normalisation of what is within tolerance
  // Labels name CSV columns and datasets: three decimals of a millimetre unless
  // two diameters would print alike, then as many as tell them apart.
  for (labelDigits = 3; labelDigits < 17; ++labelDigits) {
    std::vector<std::string> names;
    for (int i = 0; i < size(); ++i) names.push_back(label(i));
    std::sort(names.begin(), names.end());
    if (std::adjacent_find(names.begin(), names.end()) == names.end()) break;
  }
}

PetscErrorCode FractionSet::create(std::vector<double> diameters, std::vector<double> massShares,
                                   FractionSet *set) {
  PetscFunctionBeginUser;
  const std::string why = problem(diameters, massShares);
  PetscCheck(why.empty(), PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "%s", why.c_str());
  set->assign(std::move(diameters), std::move(massShares));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FractionSet::fromOptions(MPI_Comm comm, FractionSet *set) {
  PetscReal dd[256] = {1.95e-3, 2.82e-3}, ww[256] = {0.473, 0.527};
  PetscInt nd = 256, nw = 256;
  PetscBool setD = PETSC_FALSE, setW = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, nullptr, "Particle-size fractions", "rcfd");
  PetscCall(checkedRealArray(PetscOptionsObject, "-fractions_diameters", "Diameter of each size fraction [m]",
                             dd, &nd, &setD));
  PetscCall(checkedRealArray(PetscOptionsObject, "-fractions_mass_shares",
                             "Share of the inventory's mass in each fraction (sums to 1)", ww, &nw, &setW));
  PetscOptionsEnd();
  PetscBool namedD = PETSC_FALSE, namedW = PETSC_FALSE;
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-fractions_diameters", &namedD));
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-fractions_mass_shares", &namedW));
  PetscCheck(setD == namedD && (nd > 0 || !setD), comm, PETSC_ERR_USER_INPUT,
             "-fractions_diameters is empty; give the diameters in m, e.g. 1.95e-3,2.82e-3");
  PetscCheck(setW == namedW && (nw > 0 || !setW), comm, PETSC_ERR_USER_INPUT,
             "-fractions_mass_shares is empty; give one mass share per diameter, summing to 1");
  PetscCheck(!setW || setD, comm, PETSC_ERR_USER_INPUT,
             "-fractions_mass_shares was given without -fractions_diameters; give the diameters they "
             "belong to");
  if (!setD) nd = 2;
  if (!setW) nw = setD ? 0 : 2;
  PetscCheck(setW || !setD || nd == 0, comm, PETSC_ERR_USER_INPUT,
             "-fractions_diameters was given without -fractions_mass_shares; give one mass share "
             "per diameter");
  // Every rank read the same options: each finds the same problem, and all
  // return it (the lowest failing rank's sentence, as for any input).
  const std::vector<double> diameters(dd, dd + nd), shares(ww, ww + nw);
  const std::string why = problem(diameters, shares);
  PetscCall(agreeOnFailure(comm, !why.empty(), why, PETSC_ERR_USER_INPUT));
  set->assign(diameters, shares);
  PetscFunctionReturn(PETSC_SUCCESS);
}

double FractionSet::inventorySauterDiameter() const {
  double s = 0.0;
  for (int i = 0; i < size(); ++i) s += w[i] / d[i];
  return 1.0 / s;
}

int FractionSet::smallest() const {
  return static_cast<int>(std::min_element(d.begin(), d.end()) - d.begin());
}
int FractionSet::largest() const {
  return static_cast<int>(std::max_element(d.begin(), d.end()) - d.begin());
}

std::string FractionSet::label(int i) const {
  char text[48];
  std::snprintf(text, sizeof text, "d%.*fmm", labelDigits, d[i] * 1e3);
  return text;
}

PetscErrorCode FractionSet::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer, "Fractions: %d, inventory Sauter diameter %.4g mm\n",
                                   size(), inventorySauterDiameter() * 1e3));
  for (int i = 0; i < size(); ++i)
    PetscCall(PetscViewerASCIIPrintf(viewer, "  %d: d = %.4g mm, mass share %.4g\n", i,
                                     d[i] * 1e3, w[i]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FractionState::create(const Layout &layout, int numFractions) {
  PetscFunctionBeginUser;
  nf = numFractions;
  ns = 0;
  names.clear();
  amountA.reset();
  amountB.reset();
  amountNow = amountSpare = nullptr;
  nlocal = layout.numLocal();
  occupied = Occupied{};
  known = KnownSums{};
  PetscCall(VecCreate(layout.comm(), a.put()));
  PetscCall(VecSetSizes(a, layout.numLocal() * nf, layout.numCells() * nf));
  PetscCall(VecSetBlockSize(a, nf));
  PetscCall(VecSetType(a, VECMPI));
  PetscCall(VecDuplicate(a, b.put()));
  PetscCall(VecZeroEntries(a));
  PetscCall(VecZeroEntries(b));
  current = a;
  spare = b;
  PetscFunctionReturn(PETSC_SUCCESS);
}

// In the order VecStrideSumAll adds (cell by cell, from the first), over the
// cells that may hold mass only: the empty ones add nothing.
PetscErrorCode FractionState::totals(std::vector<double> *perFraction) const {
  PetscFunctionBeginUser;
  PetscCall(localTotals(perFraction));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, perFraction->data(), nf, MPI_DOUBLE, MPI_SUM,
                             PetscObjectComm((PetscObject)current)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FractionState::localTotals(std::vector<double> *perFraction) const {
  PetscInt end;
  PetscObjectState now = 0;
  const PetscScalar *m;
  PetscFunctionBeginUser;
  if (known.of == current) {
    PetscCall(PetscObjectStateGet((PetscObject)current, &now));
    if (now == known.state) {
      *perFraction = known.sums;
      PetscFunctionReturn(PETSC_SUCCESS);
    }
  }
  PetscCall(occupiedEnd(&end));
  perFraction->assign(nf, 0.0);
  double *sum = perFraction->data();
  PetscCall(VecGetArrayRead(current, &m));
  byFractions(nf, [&](auto n) { sumCells<decltype(n)::value>(nf, m, 0, end, sum); });
  PetscCall(VecRestoreArrayRead(current, &m));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FractionState::setLocalTotals(const std::vector<double> &perFraction) {
  PetscFunctionBeginUser;
  PetscCheck(static_cast<int>(perFraction.size()) == nf, PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ,
             "setLocalTotals needs %d sums, got %zu", nf, perFraction.size());
  known.of = current;
  known.sums = perFraction;
  PetscCall(PetscObjectStateGet((PetscObject)current, &known.state));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FractionState::occupiedEnd(PetscInt *end) const {
  PetscObjectState now = 0;
  PetscFunctionBeginUser;
  *end = nlocal;
  if (occupied.of != current) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscObjectStateGet((PetscObject)current, &now));
  if (now == occupied.state) *end = occupied.end;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FractionState::setOccupiedEnd(PetscInt end) {
  PetscFunctionBeginUser;
  occupied.of = current;
  occupied.end = std::clamp<PetscInt>(end, 0, nlocal);
  PetscCall(PetscObjectStateGet((PetscObject)current, &occupied.state));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FractionState::createScalars(const std::vector<std::string> &scalarNames) {
  PetscFunctionBeginUser;
  PetscCheck(current, PETSC_COMM_SELF, PETSC_ERR_ORDER, "FractionState::createScalars() needs create() first");
  names = scalarNames;
  ns = static_cast<int>(names.size());
  amountA.reset();
  amountB.reset();
  amountNow = amountSpare = nullptr;
  if (ns == 0) PetscFunctionReturn(PETSC_SUCCESS);
  PetscInt global;
  PetscCall(VecGetSize(current, &global));
  PetscCall(VecCreate(PetscObjectComm((PetscObject)current), amountA.put()));
  PetscCall(VecSetSizes(amountA, nlocal * nf * ns, global * ns));
  PetscCall(VecSetBlockSize(amountA, nf * ns));
  PetscCall(VecSetType(amountA, VECMPI));
  PetscCall(VecDuplicate(amountA, amountB.put()));
  PetscCall(VecZeroEntries(amountA));
  PetscCall(VecZeroEntries(amountB));
  amountNow = amountA;
  amountSpare = amountB;
  PetscFunctionReturn(PETSC_SUCCESS);
}

// Cell by cell from the first, as localTotals() adds the masses, over the
// cells that may hold mass: a cell without mass holds no amount (every
// operator moves amounts with the masses, and a cell whose masses are all
// zero received none).
PetscErrorCode FractionState::localAmountTotals(std::vector<double> *perScalarFraction) const {
  const PetscScalar *x;
  PetscInt end;
  PetscFunctionBeginUser;
  const int w = nf * ns;
  perScalarFraction->assign(w, 0.0);
  if (ns == 0) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(occupiedEnd(&end));
  double *sum = perScalarFraction->data();
  PetscCall(VecGetArrayRead(amountNow, &x));
  for (PetscInt c = 0; c < end; ++c, x += w)
    for (int k = 0; k < w; ++k) sum[k] += x[k];
  PetscCall(VecRestoreArrayRead(amountNow, &x));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FractionState::scaleAmounts(const std::vector<double> &factor, PetscInt end) {
  PetscFunctionBeginUser;
  const int w = nf * ns;
  if (std::all_of(factor.begin(), factor.end(), [](double f) { return f == 1.0; })) PetscFunctionReturn(PETSC_SUCCESS);
  PetscInt n;
  PetscScalar *x;
  PetscCall(VecGetLocalSize(amountNow, &n));
  if (end >= 0) n = std::min(n, end * w);
  PetscCall(VecGetArray(amountNow, &x));
  for (PetscInt j = 0; j < n; j += w)
    for (int k = 0; k < w; ++k) x[j + k] *= factor[k];
  PetscCall(VecRestoreArray(amountNow, &x));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FractionState::amountTotals(std::vector<double> *perScalarFraction) const {
  PetscFunctionBeginUser;
  PetscCall(localAmountTotals(perScalarFraction));
  if (ns == 0) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, perScalarFraction->data(), nf * ns, MPI_DOUBLE, MPI_SUM,
                             PetscObjectComm((PetscObject)amountNow)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FractionState::minimum(double *value) const {
  PetscFunctionBeginUser;
  PetscCall(VecMin(current, nullptr, value));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
