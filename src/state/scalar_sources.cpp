// The scalars' sources: spray, gas-solid exchange of heat and drying.
// docs/scalars.md, "Sources", has the model, the correlation and its range.
#include "state/scalar_sources.hpp"
#include "base/checked_options.hpp"
#include "base/petsc_compat.hpp"
#include "database/fluidization_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace rcfd {

PetscErrorCode ScalarSources::setFromOptions(MPI_Comm c, const std::vector<std::string> &names) {
  char zone[PETSC_MAX_PATH_LEN] = "spray", kind[32] = "none", gasKind[32] = "inlet";
  PetscBool set = PETSC_FALSE;
  PetscFunctionBeginUser;
  comm = c;
  ns = static_cast<int>(names.size());
  temperature = moisture = -1;
  for (int s = 0; s < ns; ++s) {
    if (names[s] == "temperature") temperature = s;
    if (names[s] == "moisture") moisture = s;
  }
  const ValueRange positive = kPositive, nonNegative = kNonNegative;
  PetscOptionsBegin(c, "scalar_", "Sources of the scalars (docs/scalars.md)", "rcfd");
  PetscCall(checkedReal(PetscOptionsObject, "-spray_rate", "Liquid sprayed into the spray zone [kg/s] (to moisture)",
                        &sprayRate, nonNegative));
  PetscCall(PetscOptionsString("-spray_zone", "Zone (of -zones) the liquid is sprayed into", "", zone, zone,
                               sizeof zone, &set));
  PetscCall(PetscOptionsString("-exchange_model", "Gas-solid exchange of heat and moisture: none, gunn (Gunn 1978) "
                               "or constant (-scalar_exchange_h, -scalar_exchange_beta)", "", kind, kind, sizeof kind,
                               &set));
  PetscCall(checkedReal(PetscOptionsObject, "-exchange_h", "Constant heat-transfer coefficient [W/m^2/K]", &h,
                        nonNegative));
  PetscCall(checkedReal(PetscOptionsObject, "-exchange_beta", "Constant mass-transfer coefficient [m/s]", &beta,
                        nonNegative));
  PetscCall(checkedReal(PetscOptionsObject, "-gas_temperature", "The gas's inlet temperature [K]", &gasTemperature,
                        nonNegative));
  PetscCall(checkedReal(PetscOptionsObject, "-gas_humidity_deficit",
                        "Saturation humidity at the particle surface minus the inlet gas's, Y_s - Y_g [kg/kg]",
                        &humidityDeficit, nonNegative));
  PetscCall(checkedReal(PetscOptionsObject, "-gas_conductivity", "The gas's thermal conductivity [W/m/K]",
                        &conductivity, positive));
  PetscCall(checkedReal(PetscOptionsObject, "-gas_prandtl", "The gas's Prandtl number", &prandtl, positive));
  PetscCall(checkedReal(PetscOptionsObject, "-gas_schmidt", "The vapour's Schmidt number in the gas", &schmidt,
                        positive));
  PetscCall(checkedReal(PetscOptionsObject, "-gas_heat_capacity", "The gas's heat capacity c_p,g [J/kg/K] (the check of "
                        "the well-mixed gas)", &gasHeatCapacity, positive));
  PetscCall(checkedReal(PetscOptionsObject, "-solid_heat_capacity", "The solid's heat capacity c_p [J/kg/K]",
                        &heatCapacity, positive));
  PetscCall(checkedReal(PetscOptionsObject, "-heat_of_evaporation",
                        "Heat of evaporation of the liquid [J/kg], taken from the temperature as it dries (0: none)",
                        &evaporation, nonNegative));
  PetscCall(checkedReal(PetscOptionsObject, "-critical_moisture", "Critical moisture X_c [kg/kg]: below it the drying "
                        "rate falls linearly to zero at zero moisture (0: the constant rate throughout)", &critical,
                        nonNegative));
  PetscCall(PetscOptionsString("-gas_model", "The gas: inlet (well mixed at its inlet state) or plug (rising layer by "
                               "layer with its own energy and vapour balance)", "", gasKind, gasKind, sizeof gasKind, &set));
  PetscCall(checkedReal(PetscOptionsObject, "-gas_humidity", "The plug-flow gas's inlet humidity Y_in [kg vapour/kg gas]",
                        &inletHumidity, nonNegative));
  PetscCall(checkedReal(PetscOptionsObject, "-gas_pressure", "The gas's pressure [Pa] (saturation humidity)", &pressure,
                        positive));
  PetscOptionsEnd();
  sprayZoneName = zone;
  const std::string g = gasKind;
  PetscCheck(g == "inlet" || g == "plug", c, PETSC_ERR_USER_INPUT,
             "-scalar_gas_model %s is not known; use inlet (well mixed at its inlet state) or plug (layer by layer)",
             gasKind);
  gasModel = g == "plug" ? Gas::Plug : Gas::Inlet;
  const std::string k = kind;
  PetscCheck(k == "none" || k == "gunn" || k == "constant", c, PETSC_ERR_USER_INPUT,
             "-scalar_exchange_model %s is not known; use none, gunn (Gunn 1978) or constant", kind);
  model = k == "gunn" ? Model::Gunn : k == "constant" ? Model::Constant : Model::None;
  PetscCheck(sprayRate == 0.0 || moisture >= 0, c, PETSC_ERR_USER_INPUT,
             "-scalar_spray_rate needs a scalar named moisture in -scalars (the liquid it adds, kg per kg solid)");
  PetscCheck(model == Model::None || temperature >= 0 || moisture >= 0, c, PETSC_ERR_USER_INPUT,
             "-scalar_exchange_model %s needs a scalar named temperature or moisture in -scalars", kind);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ScalarSources::setUp(const Database &database, const FractionSet &fractions, double density) {
  PetscFunctionBeginUser;
  db = &database;
  nf = fractions.size();
  solidDensity = density;
  diameter.resize(nf);
  for (int i = 0; i < nf; ++i) diameter[i] = fractions.diameter(i);
  if (model != Model::None) { // the case's gas, else the database's, else air (as the bottom layer's u_mf)
    FluidizationModel gas;
    PetscCall(OperatingConditions::fromOptions(comm, &gas.given));
    const OperatingConditions resolved = gas.resolve(database.metadata().conditions);
    gasDensity = resolved.gasDensity;
    viscosity = resolved.gasKinematicViscosity;
    velocity = resolved.superficialVelocity;
    if (gasModel == Gas::Plug) PetscCall(layers.setUp(database)); // the layers of the answers
  }
  gasFromVelocity();
  sprayZone.reset();
  if (sprayRate > 0.0 || sprayFollowed) {
    ZoneSet zones;
    PetscCall(zones.setFromOptions(comm));
    const Zone *found = zones.find(sprayZoneName);
    PetscCheck(found, comm, PETSC_ERR_USER_INPUT,
               "-scalar_spray_zone %s names no zone of -zones; define it with -zones ...,%s and -zone_%s_box (or "
               "_layers, _heights, _halfspace, _cylinder)", sprayZoneName.c_str(), sprayZoneName.c_str(),
               sprayZoneName.c_str());
    sprayZone = std::make_unique<Zone>(*found);
    PetscCall(sprayZone->setUp(database.mesh(), database.layout(), database.metadata().gravity));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

void ScalarSources::gasFromVelocity() {
  heatTerms.assign(nf, Terms{});
  massTerms.assign(nf, Terms{});
  if (model == Model::None) return;
  // The gas's heat capacity flow through the box's cross-section normal to gravity.
  capacityFlow = 0.0;
  if (db->mesh().isBox()) {
    const Vec3 &g = db->metadata().gravity, &length = db->mesh().boxSpec().length;
    int up = 0;
    for (int a = 1; a < 3; ++a)
      if (std::fabs(g[a]) > std::fabs(g[up])) up = a;
    capacityFlow = gasDensity * velocity * length[(up + 1) % 3] * length[(up + 2) % 3] * gasHeatCapacity;
  }
  if (gasModel == Gas::Plug) { // the gas's mass flow through the lowest layer's section
    gasFlow = gasDensity * velocity * layers.volume(0) / layers.thickness();
    capacityFlow = gasFlow * gasHeatCapacity;
  }
  for (int i = 0; i < nf && model == Model::Gunn; ++i) {
    const double re = velocity * diameter[i] / viscosity;
    heatTerms[i] = {1.0 + 0.7 * std::pow(re, 0.2) * std::cbrt(prandtl), std::pow(re, 0.7) * std::cbrt(prandtl)};
    massTerms[i] = {1.0 + 0.7 * std::pow(re, 0.2) * std::cbrt(schmidt), std::pow(re, 0.7) * std::cbrt(schmidt)};
  }
}

void ScalarSources::setSuperficialVelocity(double u) {
  if (!db || !(u > 0.0) || u == velocity) return; // an unknown u_sup (NaN) leaves the set-up's
  velocity = u;
  gasFromVelocity();
}

// Gunn, D. J. (1978), Int. J. Heat Mass Transfer 21, 467-476: for a particle in
// a fixed or fluidised bed of voidage 0.35 <= eps <= 1 up to Re = 1e5,
//   Nu = (7 - 10 eps + 5 eps^2)(1 + 0.7 Re^0.2 Pr^1/3) + (1.33 - 2.4 eps + 1.2 eps^2) Re^0.7 Pr^1/3,
// Re = u d / nu with the superficial velocity; Sh with Sc in place of Pr.
double ScalarSources::gunn(double reynolds, double pr, double eps) const {
  const double cube = std::cbrt(pr);
  return (7.0 - 10.0 * eps + 5.0 * eps * eps) * (1.0 + 0.7 * std::pow(reynolds, 0.2) * cube) +
         (1.33 - 2.4 * eps + 1.2 * eps * eps) * std::pow(reynolds, 0.7) * cube;
}

void ScalarSources::classCoefficients(int i, double eps, double *heat, double *mass) const {
  if (model != Model::Gunn) {
    *heat = heatCoefficient(diameter[i], eps);
    *mass = massCoefficient(diameter[i], eps);
    return;
  }
  const double first = 7.0 - 10.0 * eps + 5.0 * eps * eps, second = 1.33 - 2.4 * eps + 1.2 * eps * eps;
  *heat = (first * heatTerms[i].a + second * heatTerms[i].b) * conductivity / diameter[i];
  *mass = (first * massTerms[i].a + second * massTerms[i].b) * (viscosity / schmidt) / diameter[i];
}

double ScalarSources::heatCoefficient(double d, double eps) const {
  if (model == Model::Constant) return h;
  if (model == Model::None) return 0.0;
  return gunn(velocity * d / viscosity, prandtl, eps) * conductivity / d;
}

double ScalarSources::massCoefficient(double d, double eps) const {
  if (model == Model::Constant) return beta;
  if (model == Model::None) return 0.0;
  return gunn(velocity * d / viscosity, schmidt, eps) * (viscosity / schmidt) / d; // Sh D / d, D = nu / Sc
}

double ScalarSources::heatTimeConstant(double d, double eps) const {
  const double coefficient = heatCoefficient(d, eps);
  return coefficient > 0.0 ? solidDensity * heatCapacity * d / (6.0 * coefficient)
                           : std::numeric_limits<double>::infinity();
}

void ScalarSources::dry(double wanted, int i, PetscScalar *cell, double *change, double *dried,
                        double *evaporated) const {
  PetscScalar &X = cell[moisture * nf + i];
  const double removed = std::min(wanted, static_cast<double>(X)); // negative: condensed on a wet group
  X = removed == X ? 0.0 : X - removed;
  change[moisture * nf + i] -= removed;
  *dried += removed;
  if (temperature < 0 || evaporation == 0.0) return;
  PetscScalar &T = cell[temperature * nf + i];
  const double cooled = std::min(removed * evaporation / heatCapacity, static_cast<double>(T)); // K kg
  T = cooled == T ? 0.0 : T - cooled;
  change[temperature * nf + i] -= cooled;
  *evaporated += cooled * heatCapacity;
}

PetscErrorCode ScalarSources::apply(double dt, int frame, FractionState &state, std::vector<double> *change) {
  PetscFunctionBeginUser;
  const int w = ns * nf;
  change->assign(w, 0.0);
  if (!any()) PetscFunctionReturn(PETSC_SUCCESS);
  // Reduced together: the exchange's change [scalar][fraction], the spray zone's surface per
  // fraction (sum of m_i / d_i), liquid dried, heat in, heat of evaporation.
  std::vector<double> sums(w + nf + 3, 0.0);
  double *zoneSurface = sums.data() + w, *dried = zoneSurface + nf, *heatIn = dried + 1, *evaporated = heatIn + 1;
  PetscInt end;
  PetscCall(state.occupiedEnd(&end));
  const PetscScalar *m, *alpha;
  PetscScalar *a;
  PetscCall(VecGetArrayRead(state.masses(), &m));
  PetscCall(VecGetArray(state.amounts(), &a));
  if (model != Model::None && gasModel == Gas::Plug) PetscCall(applyPlug(dt, frame, end, m, a, sums));
  else if (model != Model::None) {
    PetscCall(VecGetArrayRead(db->alphaS(frame), &alpha));
    const bool heats = temperature >= 0, dries = moisture >= 0 && humidityDeficit > 0.0;
    for (PetscInt c = 0; c < end; ++c) {
      // Gunn's range: the voidage of a dense cell is at least 0.35, the freeboard's 1.
      const double eps = std::clamp(1.0 - static_cast<double>(alpha[c]), 0.35, 1.0);
      for (int i = 0; i < nf; ++i) {
        const double mass = m[c * nf + i];
        if (!(mass > 0.0)) continue;
        const double d = diameter[i];
        double h, beta;
        classCoefficients(i, eps, &h, &beta);
        PetscScalar *T = heats ? &a[c * w + temperature * nf + i] : nullptr;
        if (heats) { // exact for a gas at its inlet temperature: T - T_g falls as exp(-dt / tau)
          const double target = mass * gasTemperature, before = *T;
          // tau = rho_s c_p d / (6 h)
          *T = target + (before - target) * std::exp(-dt * 6.0 * h / (solidDensity * heatCapacity * d));
          sums[temperature * nf + i] += *T - before;
          *heatIn += (*T - before) * heatCapacity;
        }
        if (!dries) continue;
        // The first drying period: beta rho_g (Y_s - Y_g) per unit surface, 6 m / (rho_s d) of it;
        // it stops when the moisture is gone, never below zero.  With X_c, the falling rate below it.
        const double wanted =
            critical > 0.0
                ? mass * (a[c * w + moisture * nf + i] / mass -
                          dryingRemains(a[c * w + moisture * nf + i] / mass,
                                        beta * gasDensity * humidityDeficit * 6.0 / (solidDensity * d), dt, critical))
                : beta * gasDensity * humidityDeficit * 6.0 * mass / (solidDensity * d) * dt;
        dry(wanted, i, &a[c * w], sums.data(), dried, evaporated);
      }
    }
    PetscCall(VecRestoreArrayRead(db->alphaS(frame), &alpha));
  }
  if (sprayZone)
    for (PetscInt c : sprayZone->localCells())
      for (int i = 0; i < nf; ++i) zoneSurface[i] += m[c * nf + i] / diameter[i];
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums.data(), static_cast<int>(sums.size()), MPI_DOUBLE, MPI_SUM, comm));
  double surface = 0.0;
  for (int i = 0; i < nf; ++i) surface += zoneSurface[i];
  const double liquid = sprayRate * dt;
  if (sprayZone && surface > 0.0) { // by surface: m_i / d_i of each class in each cell
    for (PetscInt c : sprayZone->localCells())
      for (int i = 0; i < nf; ++i) a[c * w + moisture * nf + i] += liquid * (m[c * nf + i] / diameter[i]) / surface;
    for (int i = 0; i < nf; ++i) sums[moisture * nf + i] += liquid * zoneSurface[i] / surface;
    totals[0] += liquid;
  } else if (sprayZone) totals[1] += liquid; // nothing in the zone: the liquid misses the bed
  PetscCall(VecRestoreArray(state.amounts(), &a));
  PetscCall(VecRestoreArrayRead(state.masses(), &m));
  totals[2] += *dried;
  if (gasModel == Gas::Plug && model != Model::None) {
    outletHumidity = inletHumidity + *dried / (gasFlow * dt);
    totals[6] += inletHumidity * gasFlow * dt + *dried;
  }
  totals[3] += *heatIn;
  totals[4] += *evaporated;
  change->assign(sums.begin(), sums.begin() + w);
  PetscFunctionReturn(PETSC_SUCCESS);
}

double dryingRemains(double X, double rate, double dt, double critical) {
  if (!(X > 0.0) || !(rate > 0.0)) return X;
  const double above = X - critical; // kg/kg to dry at the constant rate
  if (above >= rate * dt) return X - rate * dt;
  const double rest = above > 0.0 ? dt - above / rate : dt; // the time below X_c
  return std::min(X, critical) * std::exp(-rate * rest / critical);
}

void gas_layer::sweep(double inletT, double inletY, double heatFlow, double vapourFlow, const std::vector<double> &sums,
                      std::vector<double> *T, std::vector<double> *Y) {
  const std::size_t nl = sums.size() / 4;
  T->resize(nl);
  Y->resize(nl);
  double t = inletT, y = inletY;
  for (std::size_t l = 0; l < nl; ++l) {
    const double *s = sums.data() + 4 * l;
    (*T)[l] = t = outlet(t, heatFlow, s[0], s[1]);
    (*Y)[l] = y = outlet(y, vapourFlow, s[2], s[3]);
  }
}

double gas_layer::saturationHumidity(double T, double p) {
  const double theta = std::clamp(T - 273.15, 1.0, 99.0);
  const double saturation = 133.322 * std::pow(10.0, 8.07131 - 1730.63 / (233.426 + theta)); // Pa
  return 0.622 * saturation / (p - saturation);
}

// The gas rises through the layers (the answers' horizontal layers, bottom first), each layer's gas
// mixed and exchanging with that layer's particles implicitly over the step (gas_layer): a first pass
// sums, per layer, each particle group's share g of the heat and its vapour conductance; one reduction;
// every rank then sweeps the layers upward (the same numbers everywhere); a second pass applies the
// layer's gas state to its particles.  The gas holds no storage: it crosses the bed in well under a
// second (0.3 m at 1.1 m/s), against the step's frames of 5 ms and a bed's heating over many seconds.
PetscErrorCode ScalarSources::applyPlug(double dt, int frame, PetscInt end, const PetscScalar *m, PetscScalar *a,
                                        std::vector<double> &sums) {
  PetscFunctionBeginUser;
  const int w = ns * nf, nl = layers.numLayers();
  const bool heats = temperature >= 0, dries = moisture >= 0;
  const PetscScalar *alpha;
  PetscCall(VecGetArrayRead(db->alphaS(frame), &alpha));
  // The particle group (c, i): its heat share g, its vapour conductance k = beta rho_g S dt [kg] when wet
  // (condensation on a wet particle colder than the gas's dew point is allowed), its temperature and
  // the saturation humidity at its surface.
  struct Group {
    double g, k, T, Ys;
  };
  const auto group = [&](PetscInt c, int i, double eps) {
    const double mass = m[c * nf + i], d = diameter[i], surface = 6.0 * mass / (solidDensity * d);
    double h, beta;
    classCoefficients(i, eps, &h, &beta);
    Group q{0.0, 0.0, gasTemperature, 0.0};
    if (heats) {
      q.T = a[c * w + temperature * nf + i] / mass;
      q.g = gas_layer::share(h * surface * dt, mass * heatCapacity);
    }
    if (dries && a[c * w + moisture * nf + i] > 0.0) {
      // Limited so that k Y_s <= X: the gas's humidity is never below 0, so the group never gives more
      // than it holds, and the layer's gas sees exactly what the particles give (no cap after the sweep).
      // Continuous in X: a trace of moisture has a trace of conductance, the same on any number of ranks.
      q.Ys = gas_layer::saturationHumidity(q.T, pressure);
      const double X = a[c * w + moisture * nf + i] / mass, falling = critical > X ? X / critical : 1.0;
      q.k = std::min(beta * gasDensity * surface * dt * falling, static_cast<double>(a[c * w + moisture * nf + i]) / q.Ys);
    }
    return q;
  };
  std::vector<double> layer(4 * nl, 0.0); // per layer: sum g, sum g T, sum k, sum k Y_s
  for (PetscInt c = 0; c < end; ++c) {
    const double eps = std::clamp(1.0 - static_cast<double>(alpha[c]), 0.35, 1.0);
    double *l = layer.data() + 4 * layers.localLayer(c);
    for (int i = 0; i < nf; ++i) {
      if (!(m[c * nf + i] > 0.0)) continue;
      const Group q = group(c, i, eps);
      l[0] += q.g, l[1] += q.g * q.T, l[2] += q.k, l[3] += q.k * q.Ys;
    }
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, layer.data(), 4 * nl, MPI_DOUBLE, MPI_SUM, comm));
  // Upward sweep: each layer's gas state, which is also what it hands to the next layer.
  std::vector<double> gasT, gasY;
  const double heatFlow = gasFlow * gasHeatCapacity * dt, vapourFlow = gasFlow * dt;
  gas_layer::sweep(gasTemperature, inletHumidity, heatFlow, vapourFlow, layer, &gasT, &gasY);
  double *dried = sums.data() + w + nf, *heatIn = dried + 1, *evaporated = heatIn + 1;
  for (PetscInt c = 0; c < end; ++c) {
    const double eps = std::clamp(1.0 - static_cast<double>(alpha[c]), 0.35, 1.0);
    const int l = layers.localLayer(c);
    for (int i = 0; i < nf; ++i) {
      const double mass = m[c * nf + i];
      if (!(mass > 0.0)) continue;
      const Group q = group(c, i, eps); // before this pass changes the group: the first pass's numbers
      PetscScalar *Ta = heats ? &a[c * w + temperature * nf + i] : nullptr;
      if (heats) {
        const double heat = q.g * (gasT[l] - q.T); // J
        *Ta += heat / heatCapacity;
        sums[temperature * nf + i] += heat / heatCapacity;
        *heatIn += heat;
      }
      if (q.k == 0.0) continue;
      // Drying toward the layer's gas, never below zero moisture (condensation on a wet group adds).
      dry(q.k * (q.Ys - gasY[l]), i, &a[c * w], sums.data(), dried, evaporated);
    }
  }
  PetscCall(VecRestoreArrayRead(db->alphaS(frame), &alpha));
  outletTemperature = nl > 0 ? gasT[nl - 1] : gasTemperature;
  // The humidity leaving is the inlet's plus what the particles gave (reduced with the step's sums, apply),
  // the sweep's top layer's to round-off.
  totals[5] += heatFlow * (gasTemperature - outletTemperature);
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::string ScalarSources::describe() const {
  char text[512];
  std::snprintf(text, sizeof text,
                "spray %g kg/s into zone %s; exchange %s (gas %g K, humidity deficit %g, c_p %g J/kg/K, heat of "
                "evaporation %g J/kg)",
                sprayRate, sprayZoneName.c_str(),
                model == Model::Gunn ? "Gunn 1978" : model == Model::Constant ? "constant" : "none", gasTemperature,
                humidityDeficit, heatCapacity, evaporation);
  return text;
}

} // namespace rcfd
