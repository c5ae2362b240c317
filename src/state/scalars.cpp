#include "state/scalars.hpp"
#include "base/petsc_compat.hpp"

#include "base/checked_options.hpp"
#include "base/collective.hpp"
#include "base/h5.hpp"
#include "rcfd/zone.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rcfd {

namespace {
constexpr int kMaxScalars = 16;
} // namespace

PetscErrorCode ScalarSet::setFromOptions(MPI_Comm comm) {
  std::vector<std::string> names;
  PetscBool given = PETSC_FALSE;
  PetscFunctionBeginUser;
  scalars.clear();
  PetscReal span[2] = {0.0, 0.0};
  PetscInt two = 2;
  PetscBool spanGiven = PETSC_FALSE;
  PetscOptionsBegin(comm, nullptr, "Scalars carried with the fractions (docs/scalars.md)", "rcfd");
  PetscCall(checkedStringArray(PetscOptionsObject, "-scalars",
                               "Names of the scalars each fraction carries, e.g. temperature,moisture,tracer",
                               kMaxScalars, &names, &given));
  PetscCall(checkedReal(PetscOptionsObject, "-scalar_leak_tolerance",
                        "Relative change of a scalar's total amount treated as a leak, not round-off", &tolerance,
                        kPositive));
  PetscCall(PetscOptionsBool("-scalar_mixing", "Write scalar_mixing.csv: each scalar's spread over the bed and the time "
                             "it mixed", "", mixing, &mixing, nullptr));
  PetscCall(checkedReal(PetscOptionsObject, "-scalar_mixing_tolerance",
                        "Mixed: every cell within this share of the starting contrast of the bed's mean",
                        &mixingShare, kPositive));
  PetscCall(PetscOptionsBool("-scalar_profiles", "Write scalar_profiles.csv: each scalar per class and cell layer, "
                             "averaged over -scalar_profiles_window", "", profiles, &profiles, nullptr));
  PetscCall(checkedRealArray(PetscOptionsObject, "-scalar_profiles_window",
                             "Window t0,t1 [s] of scalar_profiles.csv (default: the last second)", span, &two,
                             &spanGiven));
  PetscOptionsEnd();
  PetscCheck(!spanGiven || (two == 2 && span[1] >= span[0] && span[0] >= 0.0), comm, PETSC_ERR_USER_INPUT,
             "-scalar_profiles_window needs two times t0,t1 [s] with 0 <= t0 <= t1");
  window.clear();
  if (spanGiven) window = {static_cast<double>(span[0]), static_cast<double>(span[1])};
  for (std::size_t s = 0; s < names.size(); ++s) {
    const std::string &n = names[s];
    PetscCheck(!n.empty() && std::isalpha(static_cast<unsigned char>(n[0])) &&
                   n.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_") ==
                       std::string::npos,
               comm, PETSC_ERR_USER_INPUT,
               "-scalars: '%s' is not a scalar name (a letter, then letters, digits or _)", n.c_str());
    PetscCheck(n != "d32" && n.rfind("alpha_", 0) != 0, comm, PETSC_ERR_USER_INPUT,
               "-scalars: '%s' is the name of a field the run writes (d32, alpha_...); name the scalar otherwise",
               n.c_str());
    for (std::size_t t = 0; t < s; ++t)
      PetscCheck(names[t] != n, comm, PETSC_ERR_USER_INPUT, "-scalars names '%s' twice", n.c_str());
    Scalar x;
    x.name = n;
    const std::string prefix = "scalar_" + n + "_";
    PetscReal values[64];
    PetscInt count = 64;
    PetscBool zonesGiven = PETSC_FALSE, valuesGiven = PETSC_FALSE, fileGiven = PETSC_FALSE;
    char file[PETSC_MAX_PATH_LEN] = "";
    PetscOptionsBegin(comm, prefix.c_str(), ("Scalar " + n).c_str(), "rcfd");
    PetscCall(checkedReal(PetscOptionsObject, "-initial", "Initial value in every cell and fraction", &x.initial,
                          {0.0, PETSC_MAX_REAL, true, true, "a value >= 0 (no negative or NaN values)"}));
    PetscCall(checkedReal(PetscOptionsObject, "-decay", "First-order decay rate k [1/s]: amounts times exp(-k dt) per step",
                          &x.decay, {0.0, PETSC_MAX_REAL, true, true, "a rate >= 0 in 1/s"}));
    PetscCall(checkedStringArray(PetscOptionsObject, "-zones", "Zones (of -zones) with their own initial value",
                                 64, &x.zones, &zonesGiven));
    PetscCall(checkedRealArray(PetscOptionsObject, "-zone_values", "Initial value in each zone of -scalar_NAME_zones",
                               values, &count, &valuesGiven));
    PetscCall(PetscOptionsString("-initial_file", "HDF5 file with /values [cells x fractions]: the initial value "
                                 "per cell and fraction", "", file, file, sizeof file, &fileGiven));
    PetscOptionsEnd();
    if (fileGiven) x.file = file;
    PetscCheck(!fileGiven || !x.file.empty(), comm, PETSC_ERR_USER_INPUT,
               "-%sinitial_file is empty; give the HDF5 file with /values [cells x fractions]", prefix.c_str());
    if (valuesGiven) x.zoneValues.assign(values, values + count);
    PetscCheck(x.zones.size() == x.zoneValues.size(), comm, PETSC_ERR_USER_INPUT,
               "-%szone_values has %zu values but -%szones names %zu zones; give one value per zone",
               prefix.c_str(), x.zoneValues.size(), prefix.c_str(), x.zones.size());
    for (std::size_t k = 0; k < x.zoneValues.size(); ++k)
      PetscCheck(x.zoneValues[k] >= 0.0 && std::isfinite(x.zoneValues[k]), comm, PETSC_ERR_USER_INPUT,
                 "-%szone_values: value %zu is %g; expected a value >= 0 (no negative or NaN values)",
                 prefix.c_str(), k + 1, x.zoneValues[k]);
    scalars.push_back(std::move(x));
  }
  PetscCall(sourceTerms.setFromOptions(comm, names));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ScalarSet::setUp(const Database &db, const FractionSet &fractions, double solidDensity) {
  PetscFunctionBeginUser;
  PetscCall(sourceTerms.setUp(db, fractions, solidDensity));
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::vector<std::string> ScalarSet::names() const {
  std::vector<std::string> all;
  for (const Scalar &x : scalars) all.push_back(x.name);
  return all;
}

PetscErrorCode ScalarSet::setInitial(const Database &db, FractionState &state) const {
  PetscFunctionBeginUser;
  const int ns = size(), nf = state.numFractions(), w = ns * nf;
  const PetscInt nlocal = db.layout().numLocal();
  const MPI_Comm comm = db.layout().comm();
  // The value of each scalar in each own cell and fraction: uniform, then the
  // zones in order, or the file's.
  std::vector<double> value(static_cast<std::size_t>(nlocal) * w);
  ZoneSet zones;
  bool anyZone = false;
  for (const Scalar &x : scalars) anyZone = anyZone || !x.zones.empty();
  if (anyZone) {
    PetscCall(zones.setFromOptions(db.layout().comm()));
    PetscCall(zones.setUp(db.mesh(), db.layout(), db.metadata().gravity));
  }
  for (int s = 0; s < ns; ++s) {
    const Scalar &x = scalars[s];
    auto set = [&](PetscInt c, double v) { std::fill_n(&value[c * w + s * nf], nf, v); };
    for (PetscInt c = 0; c < nlocal; ++c) set(c, x.initial);
    for (std::size_t k = 0; k < x.zones.size(); ++k) {
      const Zone *z = zones.find(x.zones[k]);
      PetscCheck(z, comm, PETSC_ERR_USER_INPUT,
                 "-scalar_%s_zones names '%s', which is no zone of -zones", x.name.c_str(), x.zones[k].c_str());
      for (PetscInt c : z->localCells()) set(c, x.zoneValues[k]);
    }
    if (x.file.empty()) continue;
    // Every rank reads the file's values (a number per cell and fraction) and keeps its own cells'.
    const std::string option = "-scalar_" + x.name + "_initial_file '" + x.file + "'";
    std::vector<double> all;
    PetscCall(collectively(comm, [&] {
      h5::File f = h5::File::openRead(x.file, MPI_COMM_NULL);
      const auto dims = f.extents("/values");
      if (dims.size() != 2 || dims[0] != (hsize_t)db.layout().numCells() || dims[1] != (hsize_t)nf)
        throw std::runtime_error(option + ": /values should be " + std::to_string(db.layout().numCells()) +
                                 " cells x " + std::to_string(nf) + " fractions, as -init_file's /masses");
      all = f.read<double>("/values");
      std::size_t bad = 0;
      for (double v : all) bad += !(v >= 0.0) || !std::isfinite(v);
      if (bad > 0)
        throw std::runtime_error(option + ": /values holds " + std::to_string(bad) +
                                 " negative or non-finite (NaN, inf) values; expected values >= 0");
    }, PETSC_ERR_USER_INPUT));
    const std::vector<PetscInt> &owned = db.layout().ownedNatural();
    for (PetscInt c = 0; c < nlocal; ++c)
      for (int i = 0; i < nf; ++i) value[c * w + s * nf + i] = all[owned[c] * nf + i];
  }
  const PetscScalar *m;
  PetscScalar *a;
  PetscCall(VecGetArrayRead(state.masses(), &m));
  PetscCall(VecGetArrayWrite(state.amounts(), &a));
  for (PetscInt c = 0; c < nlocal; ++c)
    for (int s = 0; s < ns; ++s)
      for (int i = 0; i < nf; ++i) a[c * w + s * nf + i] = m[c * nf + i] * value[c * w + s * nf + i];
  PetscCall(VecRestoreArrayWrite(state.amounts(), &a));
  PetscCall(VecRestoreArrayRead(state.masses(), &m));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ScalarSet::applySources(double dt, int frame, FractionState &state) {
  PetscFunctionBeginUser;
  const int ns = size(), nf = state.numFractions(), w = ns * nf;
  bool any = false;
  for (const Scalar &x : scalars) any = any || x.decay > 0.0;
  decayFactor.assign(ns, 1.0);
  stepSources.assign(w, 0.0);
  if (any) {
    for (int s = 0; s < ns; ++s) decayFactor[s] = std::exp(-scalars[s].decay * dt);
    PetscInt n;
    PetscScalar *a;
    PetscCall(VecGetLocalSize(state.amounts(), &n));
    PetscCall(VecGetArray(state.amounts(), &a));
    for (PetscInt c = 0; c < n / w; ++c)
      for (int s = 0; s < ns; ++s)
        if (decayFactor[s] != 1.0)
          for (int i = 0; i < nf; ++i) a[c * w + s * nf + i] *= decayFactor[s];
    PetscCall(VecRestoreArray(state.amounts(), &a));
  }
  if (sourceTerms.any()) PetscCall(sourceTerms.apply(dt, frame, state, &stepSources));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ScalarSet::startLedger(const FractionState &state) {
  PetscFunctionBeginUser;
  PetscCall(state.amountTotals(&expected));
  seen.assign(expected.size(), 0.0);
  passed.assign(size(), 0.0);
  const int nf = size() > 0 ? static_cast<int>(expected.size()) / size() : 0;
  for (std::size_t k = 0; k < expected.size(); ++k) passed[k / nf] += std::fabs(expected[k]);
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::vector<double> ScalarSet::ledgerState() const {
  std::vector<double> state = expected;
  state.insert(state.end(), passed.begin(), passed.end());
  return state;
}

void ScalarSet::restoreLedger(const std::vector<double> &r) {
  const std::size_t w = r.size() - scalars.size();
  expected.assign(r.begin(), r.begin() + w);
  passed.assign(r.begin() + w, r.end());
}

void ScalarSet::advanceLedger(const std::vector<double> &operatorsAdded) {
  const int w = static_cast<int>(expected.size()), nf = size() > 0 ? w / size() : 0;
  if (seen.size() != expected.size()) seen.assign(w, 0.0);
  for (int k = 0; k < w; ++k) {
    const double now = k < static_cast<int>(operatorsAdded.size()) ? operatorsAdded[k] : 0.0;
    const double f = k / nf < static_cast<int>(decayFactor.size()) ? decayFactor[k / nf] : 1.0;
    const double source = k < static_cast<int>(stepSources.size()) ? stepSources[k] : 0.0;
    expected[k] = (expected[k] + (now - seen[k])) * f + source;
    if (k / nf < static_cast<int>(passed.size())) passed[k / nf] += std::fabs(now - seen[k]) + std::fabs(source);
    seen[k] = now;
  }
}

PetscErrorCode ScalarSet::checkLedger(long step, PetscInt every, FractionState &state, bool endOfRun) {
  PetscFunctionBeginUser;
  const bool regular = every > 0 && step % every == 0;
  if (every == 0 || (!regular && !endOfRun) || size() == 0) PetscFunctionReturn(PETSC_SUCCESS);
  const int ns = size(), nf = state.numFractions(), w = ns * nf;
  const MPI_Comm comm = PetscObjectComm((PetscObject)state.amounts());
  std::vector<double> now;
  PetscCall(state.amountTotals(&now));
  std::vector<double> factor(w, 1.0);
  for (int s = 0; s < ns; ++s) {
    // A fraction whose total has nearly all gone (dried out, discharged) is judged against 1e-3 of what
    // passed through the scalar (its start and all that came and went): round-off of those sums.
    const double floor = 1e-3 * passed[s];
    for (int i = 0; i < nf; ++i) {
      const int k = s * nf + i;
      const double target = expected[k], scale = std::fmax(std::fabs(target), floor);
      const double change = scale > 0.0 ? (now[k] - target) / scale : now[k];
      PetscCheck(std::fabs(change) <= tolerance, comm, PETSC_ERR_PLIB,
                 "Scalar %s of fraction %d changed its total amount by %.3e (relative) by step %ld, more than its "
                 "sources and round-off (-scalar_leak_tolerance %g): an operator does not carry it conservatively",
                 scalars[s].name.c_str(), i, change, step, (double)tolerance);
      largest = std::fmax(largest, std::fabs(change));
      if (std::fabs(target) >= floor && now[k] != 0.0) factor[k] = target / now[k];
    }
  }
  if (!regular) PetscFunctionReturn(PETSC_SUCCESS); // verified only, as the mass ledger
  PetscCall(state.scaleAmounts(factor));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd

namespace rcfd {

PetscErrorCode ScalarSet::report(const FractionState &state, double time) const {
  PetscFunctionBeginUser;
  const MPI_Comm comm = PetscObjectComm((PetscObject)state.amounts());
  PetscCall(PetscPrintf(comm, "  scalars: largest round-off removed by their ledger %.2e (relative)\n", largest));
  if (!sourceTerms.any()) PetscFunctionReturn(PETSC_SUCCESS);
  std::vector<double> now;
  PetscCall(state.amountTotals(&now));
  const int nf = state.numFractions();
  double held = 0.0, carried = 0.0; // the liquid in the bed, and what operators brought (feed) or took (discharge)
  for (int s = 0; s < size(); ++s)
    if (scalars[s].name == "moisture")
      for (int i = 0; i < nf; ++i) {
        held += now[s * nf + i];
        if (!seen.empty()) carried += seen[s * nf + i];
      }
  const std::vector<double> &a = sourceTerms.account();
  PetscCall(PetscPrintf(comm, "  sources: %s\n  liquid sprayed %.6g kg (missed an empty zone %.3g kg), dried %.6g kg, "
                              "held %.6g kg, brought in (+) or taken out (-) by feed and discharge %.6g kg; heat from "
                              "the gas %.6g J, of evaporation %.6g J\n",
                        sourceTerms.describe().c_str(), a[0], a[1], a[2], held, carried, a[3], a[4]));
  if (sourceTerms.plugGas() && time > 0.0) {
    const double flow = sourceTerms.gasCapacityFlow();
    PetscCall(PetscPrintf(comm, "  gas (plug flow): %.4g W given to the solid on average by its own balance (%.4g W by the "
                                "particles'), capacity flow %.4g W/K; leaving at %.6g K and %.4g kg/kg (saturation at "
                                "that temperature %.4g kg/kg), water out %.6g kg (%.4g kg/s)\n",
                          a[5] / time, a[3] / time, flow, sourceTerms.gasOutletTemperature(),
                          sourceTerms.gasOutletHumidity(),
                          gas_layer::saturationHumidity(sourceTerms.gasOutletTemperature(), sourceTerms.gasPressure()),
                          a[6], a[6] / time));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  // The gas is taken well mixed at its inlet state: it gives heat as if it never cooled.  What it gave,
  // spread over its flow, is the mean drop of its temperature that heat needs; past the difference
  // between the gas and the bed, a real gas could not have given it (docs/scalars.md, "Sources").
  const int t = sourceTerms.temperatureColumn();
  if (sourceTerms.exchangesHeat() && sourceTerms.gasCapacityFlow() > 0.0 && time > 0.0) {
    std::vector<double> mass;
    PetscCall(state.totals(&mass));
    double amount = 0.0, solid = 0.0;
    for (int i = 0; i < nf; ++i) amount += now[t * nf + i], solid += mass[i];
    const double bed = solid > 0.0 ? amount / solid : 0.0, drop = a[3] / (sourceTerms.gasCapacityFlow() * time);
    const double room = std::fabs(sourceTerms.gasInletTemperature() - bed);
    if (std::fabs(drop) > room)
      PetscCall(PetscPrintf(comm, "  note: the gas gave the solid %.4g W on average, a mean drop of %.4g K of its %.4g W/K "
                                  "(rho_g u_sup A c_p,g), more than the %.4g K between the gas and the bed at the end: the "
                                  "gas, taken well mixed at its inlet state, overestimates the exchange (docs/scalars.md)\n",
                            a[3] / time, drop, sourceTerms.gasCapacityFlow(), room));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
