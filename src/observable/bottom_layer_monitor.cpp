// The bottom cell layer's Sauter diameter over time, u_mf from it, and the
// de-fluidization warning (paper Sec. 3.2, Fig. 5).
#include "observable/answers.hpp"
#include "base/petsc_compat.hpp"

#include "base/collective.hpp"

#include <cmath>
#include <limits>

namespace rcfd {

PetscErrorCode BottomLayerMonitor::setUp(const RunContext &run, const FractionState &, const std::string &dir) {
  PetscFunctionBeginUser;
  comm = run.db.layout().comm();
  fractions = &run.fractions;
  rhoP = run.solidDensity;
  const Vec3 &g = run.db.metadata().gravity;
  gravity = std::hypot(g[0], g[1], g[2]);
  std::string header = "time_s,d32_bottom_m,umf_m_s,usup_m_s,defluidized";
  for (const Zone &z : zones->all()) header += ",d32_" + z.name() + "_m";
  // A scalar named moisture (docs/scalars.md): the bottom layer's, for the wet-bed warning.
  moisture = -1;
  ns = run.numScalars;
  for (int s = 0; run.scalarNames && s < ns; ++s)
    if ((*run.scalarNames)[s] == "moisture") moisture = s;
  if (moisture >= 0) header += ",moisture_bottom";
  PetscCheck(wetUmf == 0.0 || moisture >= 0, comm, PETSC_ERR_USER_INPUT,
             "-moisture_umf_coefficient needs a scalar named moisture in -scalars (the bottom layer's moisture "
             "raises its u_mf)");
  if (wetUmf > 0.0) header += ",umf_wet_m_s";
  csv = std::make_unique<CsvSeries>(comm, dir + "/bottom.csv", header);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BottomLayerMonitor::sample(const MonitorContext &ctx) {
  PetscFunctionBeginUser;
  const std::vector<double> *perLayer;
  PetscCall(sampler->masses(ctx, &perLayer));
  const int nf = fractions->size();
  const double d32 = layers::sauterDiameter(*perLayer, 0, *fractions);
  // The conditions of the database in use now: a run on several databases switches.
  const OperatingConditions now = model.resolve(ctx.run.operatingConditions());
  if (now.superficialVelocity != detector.superficialVelocity()) { // keeps whether and when it fired
    const std::vector<double> fired = detector.saveState();
    detector = DefluidizationDetector(now.superficialVelocity);
    detector.restoreState(fired);
  }
  // An empty bottom layer has no diameter and no u_mf (NaN): it cannot warn.
  double umf = std::numeric_limits<double>::quiet_NaN();
  if (std::isfinite(d32)) // d32 and the conditions are the same on every rank: no reduction
    PetscCall(collectively(
        PETSC_COMM_SELF, [&] { umf = model.minFluidizationVelocity(d32, rhoP, now, gravity); },
        PETSC_ERR_USER_INPUT));
  // The bottom layer's moisture amount over its solid (a scalar named moisture); with -moisture_umf_coefficient
  // it raises u_mf: the flag and the warning follow u_mf,wet = u_mf (1 + kappa X).
  double wet = std::numeric_limits<double>::quiet_NaN(), limit = umf;
  if (moisture >= 0) {
    std::vector<double> amounts;
    PetscCall(sampler->geometry().layerAmounts(ctx.state, 0, &amounts));
    double water = 0.0, solid = 0.0;
    for (int i = 0; i < nf; ++i) water += amounts[moisture * nf + i], solid += (*perLayer)[i];
    if (solid > 0.0) wet = water / solid;
    if (wetUmf > 0.0) limit = umf * (1.0 + wetUmf * wet);
  }
  if (detector.update(ctx.time, limit)) {
    if (wetUmf > 0.0)
      PetscCall(PetscPrintf(comm,
                            "WARNING: de-fluidization at t = %.6g s: u_mf of the bottom layer (d32 = %.4g mm, %s; "
                            "raised by its moisture %.4g kg/kg to %.4g m/s) reached the superficial velocity %.4g m/s\n",
                            ctx.time, 1e3 * d32, model.correlation.name.c_str(), wet, limit, detector.superficialVelocity()));
    else
      PetscCall(PetscPrintf(comm,
                            "WARNING: de-fluidization at t = %.6g s: u_mf of the bottom layer (d32 = %.4g mm, %s) "
                            "= %.4g m/s reached the superficial velocity %.4g m/s\n",
                            ctx.time, 1e3 * d32, model.correlation.name.c_str(), umf, detector.superficialVelocity()));
  }
  std::vector<double> row{ctx.time, d32, umf, detector.superficialVelocity(), limit >= detector.superficialVelocity() ? 1.0 : 0.0};
  latest = row;
  if (!zones->all().empty()) { // each zone's mass per fraction, one reduction for all zones
    std::vector<double> local(zones->all().size() * nf, 0.0), global(local.size());
    const PetscScalar *m;
    PetscCall(VecGetArrayRead(ctx.state.masses(), &m));
    for (std::size_t z = 0; z < zones->all().size(); ++z)
      for (PetscInt c : zones->all()[z].localCells())
        for (int i = 0; i < nf; ++i) local[z * nf + i] += m[c * nf + i];
    PetscCall(VecRestoreArrayRead(ctx.state.masses(), &m));
    PetscCallMPI(MPI_Allreduce(local.data(), global.data(), static_cast<int>(local.size()), MPI_DOUBLE, MPI_SUM, comm));
    for (std::size_t z = 0; z < zones->all().size(); ++z) // a zone is one "layer" of nf masses
      row.push_back(layers::sauterDiameter(global, static_cast<int>(z), *fractions));
  }
  if (moisture >= 0) {
    row.push_back(wet);
    if (wetUmf > 0.0) row.push_back(limit);
    if (wetThreshold > 0.0 && std::isnan(wetTime) && wet > wetThreshold &&
        umf >= nearShare * detector.superficialVelocity()) {
      wetTime = ctx.time;
      PetscCall(PetscPrintf(comm,
                            "WARNING: wet bottom layer at t = %.6g s: its moisture %.4g kg/kg passed -moisture_warning "
                            "%g while its u_mf = %.4g m/s is %.0f %% of u_sup (near de-fluidization by size)\n",
                            ctx.time, wet, wetThreshold, umf, 100.0 * umf / detector.superficialVelocity()));
    }
  }
  PetscCall(csv->add(formatNumberRow(row)));
  if (ctx.last && !quiet && std::isfinite(wetTime))
    PetscCall(PetscPrintf(comm, "  bottom layer: wet and near de-fluidization from t = %.6g s on (-moisture_warning "
                                "%g)\n", wetTime, wetThreshold));
  if (ctx.last && !quiet) {
    if (detector.fired())
      PetscCall(PetscPrintf(comm, "  bottom layer: de-fluidized from t = %.6g s on (%s)\n", detector.firstTime(),
                            model.correlation.name.c_str()));
    else
      PetscCall(PetscPrintf(comm, "  bottom layer: u_mf (%s) stayed below u_sup = %g m/s; last d32 %.4g mm, u_mf %.4g m/s\n",
                            model.correlation.name.c_str(), detector.superficialVelocity(), 1e3 * d32, umf));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BottomLayerMonitor::flush() { return csv->flush(); }

// State: {fired, first time, length of bottom.csv} and, with moisture, the wet warning's time.
std::vector<double> BottomLayerMonitor::saveState() const {
  std::vector<double> state = detector.saveState();
  state.push_back(csv->mark());
  if (moisture >= 0) state.push_back(wetTime);
  return state;
}

PetscErrorCode BottomLayerMonitor::restoreState(const std::vector<double> &state) {
  PetscFunctionBeginUser;
  const std::size_t expected = moisture >= 0 ? 4 : 3;
  PetscCheck(state.size() == expected, PETSC_COMM_SELF, PETSC_ERR_FILE_UNEXPECTED,
             "The checkpoint's bottom.csv state holds %zu numbers, expected %zu (the detector, the file's length and "
             "with moisture the wet warning)", state.size(), expected);
  if (moisture >= 0) wetTime = state[3];
  PetscCall(collectively(PETSC_COMM_SELF, [&] { detector.restoreState({state[0], state[1]}); },
                         PETSC_ERR_FILE_UNEXPECTED));
  PetscCall(csv->resume(state[2]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
