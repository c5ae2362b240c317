#include "rcfd/drift.hpp"
#include "base/checked_options.hpp"
#include "base/petsc_compat.hpp"
#include "database/fluidization_model.hpp"

#include "rcfd/agitation.hpp"
#include "rcfd/measured_drift_field.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace rcfd {

DriftOperator::DriftOperator() : DriftOperator(SizeLawRegistry::withBuiltins()) {}
DriftOperator::DriftOperator(SizeLawRegistry laws) : known(std::move(laws)) {
  // The default law when known (a registry without it: setFromOptions refuses).
  if (known.has(lawName) && known.create(lawName, &law) == PETSC_SUCCESS) law->setOptionsPrefix(prefix + "size_law_");
}
DriftOperator::~DriftOperator() = default;

PetscErrorCode DriftOperator::setSizeLaw(const std::string &name) {
  PetscFunctionBeginUser;
  PetscCall(known.create(name, &law));
  law->setOptionsPrefix(prefix + "size_law_");
  lawName = name;
  model = Model::SizeLaw;
  if (!kdGiven) kd = law->defaultK();
  PetscFunctionReturn(PETSC_SUCCESS);
}

// -drift_model A|B is the size law of that name; -drift_size_law chooses any
// registered law and overrides -drift_model A|B.
PetscErrorCode DriftOperator::setFromOptions(MPI_Comm comm) {
  const char *models[] = {"A", "B", "constant", "none", "measured"};
  const bool plain = model == Model::SizeLaw && (lawName == "A" || lawName == "B");
  PetscInt which = model == Model::Constant ? 2 : model == Model::None ? 3 : model == Model::Measured ? 4
                   : plain && lawName == "A" ? 0 : 1;
  PetscReal velocities[256] = {0.0}; // -help prints the first entry
  PetscInt nv = 256;
  PetscBool setV = PETSC_FALSE, setModel = PETSC_FALSE, setLaw = PETSC_FALSE, setKd = PETSC_FALSE;
  char agitationText[32], lawText[64];
  std::snprintf(agitationText, sizeof agitationText, "%s", agitationName.c_str());
  std::snprintf(lawText, sizeof lawText, "%s", lawName.c_str());
  const std::string lawHelp = "Size law of the drift velocity (docs/drift.md): " + known.listing();
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, prefix.c_str(), "Fractional drift (face swaps along gravity)", "rcfd");
  PetscCall(PetscOptionsEList("-model",
                              "Drift model: A (d^2), B (d|d|), constant, none or measured (the database's field; A, "
                              "B: size laws)",
                              "", models, 5, models[which], &which, &setModel));
  PetscCall(PetscOptionsString("-size_law", lawHelp.c_str(), "", lawText, lawText, sizeof lawText, &setLaw));
  PetscCall(checkedReal(PetscOptionsObject, "-kd",
                        "Drift constant k_d in the size law's unit: 1/(m s) for A and B (paper: 5e2 for A, 5e3 "
                        "for B), m/s for drag, log and power",
                        &kd, kNonNegative, &setKd));
  PetscCall(checkedRealArray(PetscOptionsObject, "-velocities",
                             "Drift velocity of each fraction, up positive [m/s] (model constant)", velocities,
                             &nv, &setV));
  PetscCall(checkedReal(PetscOptionsObject, "-d32",
                        "Sauter diameter in the model [m] (default: the inventory's)",
                        &d32Override, {0.0, 1.0, false, true, "a positive diameter in m"}));
  PetscCall(PetscOptionsBool("-local_d32", "Use each sending cell's Sauter diameter instead", "",
                             localD32, &localD32, nullptr));
  PetscCall(PetscOptionsBool("-hindered", "Hindered drift: times (1 - alpha_s / alpha_max)", "",
                             hindered, &hindered, nullptr));
  PetscCall(checkedReal(PetscOptionsObject, "-alpha_max",
                        "Packing limit of hindered drift", &alphaMax, kUnitInterval));
  PetscCall(checkedReal(PetscOptionsObject, "-alpha_min",
                        "Faces touching a cell below this alpha_s do not swap",
                        &alphaMin, {0.0, 1.0, true, false, "a solid fraction in [0, 1)"}));
  PetscCall(checkedReal(PetscOptionsObject, "-max_share",
                        "Largest share of a fraction one sub-step may drift out of a cell",
                        &maxShare, kUnitInterval));
  PetscCall(checkedInt(PetscOptionsObject, "-max_substeps",
                       "Refuse steps that would need more sub-steps", &substepLimit, 1, 100000000));
  PetscCall(checkedInt(PetscOptionsObject, "-every",
                       "Apply the drift of N steps at once, every N steps (speed against splitting error, see docs/drift.md)",
                       &every, 1, 1000000));
  PetscCall(PetscOptionsString("-agitation",
                               "Scale u_d in each sending cell by (a/a_bar)^n, a the frame's agitation: "
                               "none, leaving (1 - T[i,i]) or dispersion (sum_j T[j,i] |x_j - x_i|^2 / dt)",
                               "", agitationText, agitationText, sizeof agitationText, nullptr));
  PetscCall(checkedReal(PetscOptionsObject, "-agitation_exponent",
                        "Exponent n of the agitation scaling (a/a_bar)^n", &agitationExponent,
                        {0.0, 100.0, true, true, "an exponent in [0, 100]"}));
  PetscCall(checkedReal(PetscOptionsObject, "-agitation_reference",
                        "A fixed a_ref in place of the database's own a_bar: (a/a_ref)^n; for leaving a rate "
                        "in 1/s (compared with a/dt_rec), for dispersion in m^2/s",
                        &agitationReference, {0.0, PETSC_MAX_REAL, false, true, "a positive agitation"}));
  PetscCall(PetscOptionsBool("-excess_gas",
                             "Multiply u_d by the bed's excess gas velocity u_sup - u_mf [m/s] (u_mf of the "
                             "inventory's d32, -umf_correlation): k_d is then per m/s of excess gas",
                             "", excessGas, &excessGas, nullptr));
  PetscOptionsEnd();
  if (excessGas) {
    char correlation[64];
    std::snprintf(correlation, sizeof correlation, "%s", umfCorrelation.c_str());
    PetscCall(OperatingConditions::fromOptions(comm, &givenConditions));
    PetscCall(PetscOptionsGetString(nullptr, nullptr, "-umf_correlation", correlation, sizeof correlation, nullptr));
    umfCorrelation = correlation;
    PetscCallCXX(findUmfCorrelation(umfCorrelation)); // an unknown name is refused here, listing the known ones
  }
  const std::string chosen = models[which];
  if (setKd) kdGiven = true;
  // -drift_size_law wins over -drift_model A|B (case files name B), but a
  // law makes no sense with given velocities or no drift.
  PetscCheck(!setLaw || !setModel || chosen == "A" || chosen == "B", comm, PETSC_ERR_USER_INPUT,
             "-%ssize_law %s cannot be used with -%smodel %s; leave out one of them", prefix.c_str(), lawText,
             prefix.c_str(), chosen.c_str());
  if (setLaw || (setModel && (chosen == "A" || chosen == "B"))) {
    const std::string name = setLaw ? std::string(lawText) : chosen;
    PetscCheck(known.has(name), comm, PETSC_ERR_USER_INPUT, "-%ssize_law %s is not a known size law; known: %s",
               prefix.c_str(), name.c_str(), known.listing().c_str());
    PetscCall(setSizeLaw(name));
  } else if (setModel) {
    model = chosen == "constant" ? Model::Constant : chosen == "measured" ? Model::Measured : Model::None;
  }
  if (model == Model::SizeLaw) {
    PetscCheck(law, comm, PETSC_ERR_USER_INPUT, "-%ssize_law %s is not a known size law; known: %s",
               prefix.c_str(), lawName.c_str(), known.listing().c_str());
    law->setOptionsPrefix(prefix + "size_law_"); // a law's option -NAME is -drift_size_law_NAME
    PetscCall(law->setFromOptions(comm));
    if (!kdGiven) kd = law->defaultK();
    PetscCheck(std::isfinite(kd), comm, PETSC_ERR_USER_INPUT,
               "-%ssize_law %s has no default k_d: give -%skd (in %s)", prefix.c_str(), lawName.c_str(),
               prefix.c_str(), law->unitOfK());
  }
  agitationName = agitationText;
  PetscCheck(agitationName == "none" || agitationName == "leaving" || agitationName == "dispersion", comm,
             PETSC_ERR_USER_INPUT, "-%sagitation %s is not known; use none, leaving or dispersion",
             prefix.c_str(), agitationText);
  constantVelocity.assign(velocities, velocities + (setV ? nv : 0));
  PetscCheck(kd >= 0 && std::isfinite(kd), comm, PETSC_ERR_USER_INPUT,
             "-%skd must be a non-negative number, got %g", prefix.c_str(), kd);
  PetscCheck(maxShare > 0 && maxShare < 1, comm, PETSC_ERR_USER_INPUT,
             "-%smax_share must lie in (0, 1), got %g", prefix.c_str(), maxShare);
  PetscCheck(alphaMax > 0 && alphaMin >= 0, comm, PETSC_ERR_USER_INPUT,
             "-%salpha_max must be positive and -%salpha_min non-negative", prefix.c_str(),
             prefix.c_str());
  PetscCheck(every >= 1, comm, PETSC_ERR_USER_INPUT, "-%severy must be at least 1, got %d",
             prefix.c_str(), (int)every);
  PetscCheck(model != Model::Constant || setV, comm, PETSC_ERR_USER_INPUT,
             "-%smodel constant needs -%svelocities (one per fraction, m/s, up positive)",
             prefix.c_str(), prefix.c_str());
  PetscFunctionReturn(PETSC_SUCCESS);
}

bool DriftOperator::needed(const RunContext &ctx) const {
  if (ctx.fractions.size() < 2 || model == Model::None) return false;
  if (model == Model::Measured) return true;
  if (model == Model::Constant)
    return std::any_of(constantVelocity.begin(), constantVelocity.end(),
                       [](double u) { return u != 0.0; });
  return kd != 0.0; // NaN (a law without a default k_d) is refused by setUp
}

double DriftOperator::velocity(int i, double sauter) const {
  double u = 0.0;
  if (model == Model::SizeLaw) law->velocities(kd * gasFactor, sauter, &diameter[i], 1, &u);
  else if (model == Model::Constant) u = constantVelocity[i] * gasFactor;
  return u;
}

void DriftOperator::velocitiesAt(double dRef, double *u) const {
  if (model == Model::SizeLaw) law->velocities(kd * gasFactor, dRef, diameter.data(), nf, u);
  else for (int i = 0; i < nf; ++i) u[i] = velocity(i, dRef);
}

// Faces whose normal is within 1e-9 of horizontal carry no drift.
SwapOperator::FaceChoice DriftOperator::swapFaces(const RunContext &ctx) const {
  const Vec3 g = ctx.db.metadata().gravity;
  return {{-g[0], -g[1], -g[2]}, 1e-9};
}

PetscErrorCode DriftOperator::setUpSwap(const RunContext &ctx) {
  PetscFunctionBeginUser;
  PetscCheck(model != Model::Constant || (int)constantVelocity.size() == nf, comm,
             PETSC_ERR_USER_INPUT, "-%svelocities has %zu values but there are %d fractions",
             prefix.c_str(), constantVelocity.size(), nf);
  PetscCheck(model != Model::SizeLaw || std::isfinite(kd), comm, PETSC_ERR_USER_INPUT,
             "-%ssize_law %s has no default k_d: give -%skd (in %s)", prefix.c_str(), lawName.c_str(),
             prefix.c_str(), law->unitOfK());
  diameter.resize(nf);
  for (int i = 0; i < nf; ++i) diameter[i] = ctx.fractions.diameter(i);
  d32 = d32Override > 0 ? d32Override : ctx.fractions.inventorySauterDiameter();
  PetscCall(setUpExcessGas(ctx));
  setUpVelocities();
  setUpTables();
  measured.reset();
  if (model == Model::Measured) { // the sweep's per-cell speeds come from the database's field
    PetscCheck(!localD32 && !hindered && !agitation && agitationName == "none", comm, PETSC_ERR_USER_INPUT,
               "-%smodel measured drifts with the velocities the database measured; -%slocal_d32, -%shindered "
               "and -%sagitation do not apply to it",
               prefix.c_str(), prefix.c_str(), prefix.c_str(), prefix.c_str());
    measured = std::make_shared<MeasuredDriftField>();
    PetscCall(measured->setUp(ctx.db, diameter, exchange()));
  }
  PetscCall(setUpScaling(ctx));
  PetscFunctionReturn(PETSC_SUCCESS);
}

void DriftOperator::setUpVelocities() {
  velocityCache.resize(nf);
  fixedUp.resize(nf);
  fixedDown.resize(nf);
  velocitiesAt(d32, velocityCache.data());
  for (int i = 0; i < nf; ++i) {
    fixedUp[i] = std::max(velocityCache[i], 0.0);
    fixedDown[i] = std::max(-velocityCache[i], 0.0);
  }
}

// The bed's excess gas u_sup - u_mf, from the case's conditions over the
// database's (as the bottom layer resolves them), with u_mf of the
// inventory's d32: the bubble flux of two-phase theory, which sets how hard
// the whole bed is stirred (docs/drift.md, "One constant for every bed").
// A u_sup nobody gave is refused rather than taken as the default 1.1 m/s.
PetscErrorCode DriftOperator::setUpExcessGas(const RunContext &ctx) {
  PetscFunctionBeginUser;
  gasFactor = 1.0;
  if (!excessGas) PetscFunctionReturn(PETSC_SUCCESS);
  const Vec3 g = ctx.db.metadata().gravity;
  gasGravity = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  gasSauter = ctx.fractions.inventorySauterDiameter();
  gasSolidDensity = ctx.solidDensity;
  PetscCall(excessGasAt(ctx.operatingConditions()));
  PetscCheck(usupSource != "default", comm, PETSC_ERR_USER_INPUT,
             "-%sexcess_gas needs the superficial gas velocity: give -superficial_velocity, or record it in the "
             "database '%s' (rcfd build -superficial_velocity)",
             prefix.c_str(), ctx.db.path().c_str());
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode DriftOperator::excessGasAt(const OperatingConditions &run) {
  PetscFunctionBeginUser;
  FluidizationModel gas;
  gas.given = givenConditions;
  PetscCallCXX(gas.correlation = findUmfCorrelation(umfCorrelation));
  std::string sources[3];
  const OperatingConditions now = gas.resolve(run, sources);
  PetscCallCXX(gasUmf = gas.minFluidizationVelocity(gasSauter, gasSolidDensity, now, gasGravity));
  gasUsup = now.superficialVelocity;
  usupSource = sources[0];
  followedUsup = run.superficialVelocity;
  gasFactor = std::max(0.0, gasUsup - gasUmf); // a bed below u_mf does not bubble: no drift
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The faces as the sweep reads them, and the masses of each gathered cell at
// alpha_min and alpha_max, multiplied in the order (alpha_min rho) V and
// (rho V) alpha_max.  A cell on no face never swaps (an infinite floor).
void DriftOperator::setUpTables() {
  const FaceExchange &x = exchange();
  const size_t gathered = static_cast<size_t>(x.numGathered());
  driftFaces.clear();
  driftFaces.reserve(x.faces().size());
  dilute.assign(gathered, HUGE_VAL);
  packed.assign(gathered, 0.0);
  auto cell = [&](PetscInt c, double volume) {
    dilute[c] = alphaMin * rho * volume;
    packed[c] = rho * volume * alphaMax;
  };
  for (const SwapFace &f : x.faces()) {
    driftFaces.push_back({f.lower, f.upper, f.areaOverVolumeLower, f.areaOverVolumeUpper});
    cell(f.lower, f.volumeLower);
    cell(f.upper, f.volumeUpper);
  }
  // In the order of their last own cell, so that a sweep can leave out the
  // faces of the freeboard at the top of the own cells.
  const PetscInt own = x.numOwn();
  std::stable_sort(driftFaces.begin(), driftFaces.end(), [own](const DriftFace &a, const DriftFace &b) {
    return lastOwnCell(a, own) < lastOwnCell(b, own);
  });
  cellSums.assign(gathered, CellSums{});
  live.assign(gathered, 0);
  cellUp.assign(localD32 || model == Model::Measured ? gathered * nf : 0, 0.0);
  cellDown.assign(cellUp.size(), 0.0);
}

// The factor (a/a_bar)^n of every cell a face of this rank touches, per
// frame, computed once: a sweep then multiplies by a number it reads.
PetscErrorCode DriftOperator::setUpScaling(const RunContext &ctx) {
  PetscFunctionBeginUser;
  scaleByFrame.clear();
  largestScaleByFrame.clear();
  meanFactor = 1.0;
  if (!agitation && agitationName == "none") {
    PetscCheck(agitationReference == 0.0, comm, PETSC_ERR_USER_INPUT,
               "-%sagitation_reference needs -%sagitation leaving or dispersion", prefix.c_str(), prefix.c_str());
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  // A field made for another database (the run switched databases) is made
  // again, of the same measure, for this one.
  if (!agitation || agitation->databaseIdentity() != ctx.db.identity()) {
    AgitationMeasure measure = AgitationMeasure::LeavingShare;
    if (agitation) measure = agitation->measure();
    else PetscCall(parseAgitationMeasure(agitationName, &measure));
    auto field = std::make_shared<AgitationField>();
    PetscCall(field->setUp(ctx.db, measure));
    agitation = field;
  }
  // The factor's denominator: the database's own a_bar, or a fixed reference
  // (for the leaving share a rate in 1/s, so that databases recorded with
  // another dt_rec agree: the share leaving in dt_rec is about rate x dt_rec).
  const bool leavingShare = agitation->measure() == AgitationMeasure::LeavingShare;
  const double mean = agitationReference > 0.0
                          ? (leavingShare ? agitationReference * ctx.db.metadata().dtRec : agitationReference)
                          : agitation->solidWeightedMean();
  normaliser = mean;
  PetscCheck(mean > 0.0 || agitationExponent == 0.0, comm, PETSC_ERR_USER_INPUT,
             "-%sagitation %s: the database '%s' shows no agitation at all (a_bar = 0), so u_d "
             "cannot be scaled by a/a_bar",
             prefix.c_str(), agitationMeasureName(agitation->measure()), ctx.db.path().c_str());
  const int K = ctx.db.numFrames();
  OwnedVec cells;
  PetscCall(VecDuplicate(ctx.db.alphaS(0), cells.put()));
  scaleByFrame.resize(K);
  largestScaleByFrame.assign(K, 0.0);
  double sums[2] = {0.0, 0.0}; // sum alpha V factor, sum alpha V
  for (int k = 0; k < K; ++k) {
    PetscScalar *v;
    const PetscScalar *alpha;
    PetscCall(VecGetArray(cells, &v));
    PetscCall(VecGetArrayRead(ctx.db.alphaS(k), &alpha));
    const std::vector<double> &a = agitation->frame(k);
    for (std::size_t i = 0; i < a.size(); ++i) {
      v[i] = std::pow(a[i] / mean, agitationExponent);
      sums[0] += alpha[i] * ctx.db.localVolumes()[i] * v[i];
      sums[1] += alpha[i] * ctx.db.localVolumes()[i];
    }
    PetscCall(VecRestoreArrayRead(ctx.db.alphaS(k), &alpha));
    PetscCall(VecRestoreArray(cells, &v));
    PetscCall(exchange().gatherScalar(cells, &scaleByFrame[k]));
    for (double f : scaleByFrame[k]) largestScaleByFrame[k] = std::max(largestScaleByFrame[k], f);
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, largestScaleByFrame.data(), K, MPI_DOUBLE, MPI_MAX, comm));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_DOUBLE, MPI_SUM, comm));
  meanFactor = sums[1] > 0.0 ? sums[0] / sums[1] : 1.0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The largest drift Courant number any cell can reach in a step of dt sets
// the number of sub-steps: with the inventory's d32 the velocities are
// fixed, with local d32 each cell's d32 lies between the smallest and the
// largest diameter, which bounds |u_i|.  The hindrance factor is <= 1; the
// agitation factor is at most the frame's largest (1 when unscaled).
PetscErrorCode DriftOperator::substepsFor(double dt, double largestScale, int *n) const {
  PetscFunctionBeginUser;
  double umax = 0.0;
  if (!localD32 || model != Model::SizeLaw) {
    for (double u : velocityCache) umax = std::max(umax, std::fabs(u));
    if (measured) umax = measuredSpeed;
  } else {
    const double dmin = *std::min_element(diameter.begin(), diameter.end());
    const double dmax = *std::max_element(diameter.begin(), diameter.end());
    umax = law->largestSpeed(kd * gasFactor, dmin, dmax, diameter.data(), nf);
  }
  const double courant = umax * largestScale * exchange().maxAreaOverVolume() * dt;
  const double needed = std::ceil(courant / maxShare);
  PetscCheck(needed <= substepLimit, comm, PETSC_ERR_NOT_CONVERGED,
             "Drift needs %.0f sub-steps per step (Courant number %.3g), more than -%smax_substeps %d",
             needed, courant, prefix.c_str(), (int)substepLimit);
  *n = std::max(1, static_cast<int>(needed));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode DriftOperator::apply(const StepInfo &step, FractionState &state) {
  int n;
  PetscFunctionBeginUser;
  // With -drift_every N the drift of N steps is applied at the end of every
  // N-th step (counted from the run's start, so a restart keeps the rhythm).
  if ((step.step + 1) % every != 0) PetscFunctionReturn(PETSC_SUCCESS);
  const double dt = step.dt * static_cast<double>(every);
  // The excess gas follows the run's u_sup where a schedule or a live file changes it between
  // set-ups (a database switch sets the drift up again); unchanged, nothing is worked out again.
  if (excessGas && step.conditions && step.conditions->superficialVelocity != followedUsup) {
    PetscCall(excessGasAt(*step.conditions));
    setUpVelocities();
  }
  const bool scaled = !scaleByFrame.empty();
  PetscCheck(!scaled || (step.frame >= 0 && step.frame < (int)scaleByFrame.size()), comm,
             PETSC_ERR_ARG_OUTOFRANGE, "Drift scaled by agitation was given frame %d of %zu",
             step.frame, scaleByFrame.size());
  const double *scale = scaled ? scaleByFrame[step.frame].data() : nullptr;
  if (measured) {
    PetscCheck(step.frame >= 0 && step.frame < measured->numFrames(), comm, PETSC_ERR_ARG_OUTOFRANGE,
               "Measured drift was given frame %d of %d", step.frame, measured->numFrames());
    measured->speeds(step.frame, cellUp.data(), cellDown.data());
    measuredSpeed = measured->largestSpeed(step.frame);
  }
  PetscCall(substepsFor(dt, scaled ? largestScaleByFrame[step.frame] : 1.0, &n));
  for (int s = 0; s < n; ++s) PetscCall(substep(dt / n, scale, state));
  countStep(n);
  PetscFunctionReturn(PETSC_SUCCESS);
}

// One explicit swap sweep over this rank's faces, all evaluated from the
// state at the start of the sub-step.  On each face the lower cell sends the
// upward-drifting fractions and the upper cell the downward-drifting ones;
// whichever side sent less bulk mass adds its own mixture until both sent
// the same mass X, so the bulk of both cells is unchanged.  The face limiter
// caps X at faceShare times either cell's bulk mass ("what the receiver can
// take"), so that with the sub-step rule no fraction can leave a cell
// entirely: per cell the drift part is at most maxShare and the faces'
// top-ups at most (1 - maxShare) together.
PetscErrorCode DriftOperator::substep(double dt, const double *scale, FractionState &state) {
  FaceExchange &x = exchange();
  PetscFunctionBeginUser;
  PetscCall(state.occupiedEnd(&occupiedEnd));
  FaceExchange *ax = state.numScalars() > 0 ? amountExchange() : nullptr; // the scalars' amounts
  PetscCheck(!ax == !(state.numScalars() > 0) && (!ax || state.numScalars() == ns), comm, PETSC_ERR_ARG_WRONGSTATE,
             "The drift was set up for %d scalars and given a state with %d", ns, state.numScalars());
  if (ax) {
    PetscCall(ax->gatherBegin(state.amounts()));
    PetscCall(ax->gatherEnd());
  }
  PetscCall(x.gatherBegin(state.masses()));
  switch (nf) { // the common inventories get loops the compiler unrolls
  case 2: PetscCall(sweep<2>(dt, scale)); break;
  case 3: PetscCall(sweep<3>(dt, scale)); break;
  case 4: PetscCall(sweep<4>(dt, scale)); break;
  case 5: PetscCall(sweep<5>(dt, scale)); break;
  default: PetscCall(sweep<0>(dt, scale)); break;
  }
  PetscCall(x.endKernel());
  PetscCall(x.addChanges(state.masses()));
  PetscCall(state.setOccupiedEnd(occupiedEnd));
  if (ax) {
    PetscCall(ax->endKernel());
    PetscCall(ax->addChanges(state.amounts()));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

// What depends on one cell alone (its bulk mass and inverse, whether it
// swaps, its agitation and hindrance factors, its speeds with the local d32,
// and the sums of its masses times the upward and downward speeds) is found
// first, once per cell; a cell is the lower side of one face and the upper
// side of another, so this halves that work, and a face is then a few
// products of its cells' numbers, without a division unless its limiter
// acts.  The own cells above the last one holding any mass (the freeboard,
// most of the cells of an upper rank) are found first, from the state's
// bound down in blocks, by the bits of their masses (a zero mass is all zero
// bits; a -0.0 only makes its block go through the cell loop), and skipped
// with their faces.
template <int NF> PetscErrorCode DriftOperator::sweep(double dt, const double *scale) {
  PetscFunctionBeginUser;
  const int n = NF > 0 ? NF : nf;
  constexpr int cap = NF > 0 ? NF : kMaxFractions;
  FaceExchange &x = exchange();
  const PetscInt own = x.numOwn(), gathered = x.numGathered();
  const double faceShare = 0.999 * (1.0 - maxShare) / std::max(1, x.maxFacesPerCell());
  // Locals: the stores of the flags (bytes) would otherwise make the
  // compiler reload every table's address after each of them.
  unsigned char *swaps = live.data();
  CellSums *sums = cellSums.data();
  const double *floor = dilute.data(), *full = packed.data();
  const double *upFixed = fixedUp.data(), *downFixed = fixedDown.data();
  double *upLocal = cellUp.data(), *downLocal = cellDown.data();
  const bool hinder = hindered, local = localD32, measuredSpeeds = measured != nullptr;
  const PetscScalar *ownMasses = x.massAt(0), *ghostMasses = nullptr; // the ghosts' after gatherEnd()
  PetscScalar *ownChanges = x.changeInMarked(0), *ghostChanges = x.changeInMarked(own);

  PetscInt top = std::min(own, occupiedEnd);
  for (constexpr PetscInt block = 64; top > 0;) {
    const PetscInt from = std::max<PetscInt>(0, top - block);
    std::uint64_t bits = 0;
    for (PetscInt k = from * n; k < top * n; ++k) {
      std::uint64_t b;
      std::memcpy(&b, ownMasses + k, sizeof b);
      bits |= b;
    }
    if (bits != 0) break;
    top = from;
  }
  occupiedEnd = top; // the flags of cells at or above it are never read: no face below it touches them

  PetscInt first = own, last = -1; // the own cells that swap
  auto sumCells = [&](const PetscScalar *m, PetscInt from, PetscInt to) { // m: the masses of cell `from`
    for (PetscInt c = from; c < to; ++c, m += n) {
      double M = 0.0;
      for (int i = 0; i < n; ++i) M += m[i];
      // Solid at or above alpha_min (an empty cell has nothing to swap with).
      const bool swapping = M > 0.0 && M >= floor[c];
      swaps[c] = swapping;
      if (!swapping) continue;
      if (c < own) first = std::min(first, c), last = c;
      double rate = dt;
      if (scale) rate *= scale[c]; // u_d of each sending cell times its agitation factor
      if (hinder) rate *= std::max(0.0, 1.0 - M / full[c]);
      const double *up = upFixed, *down = downFixed;
      if (local) {
        double s = 0.0;
        for (int i = 0; i < n; ++i) s += m[i] / diameter[i];
        const double sauter = s > 0 ? M / s : d32;
        up = upLocal + c * n, down = downLocal + c * n;
        double u[cap];
        velocitiesAt(sauter, u);
        for (int i = 0; i < n; ++i) {
          upLocal[c * n + i] = std::max(u[i], 0.0);
          downLocal[c * n + i] = std::max(-u[i], 0.0);
        }
      } else if (measuredSpeeds) up = upLocal + c * n, down = downLocal + c * n; // filled by apply()
      double U = 0.0, D = 0.0;
      for (int i = 0; i < n; ++i) U += m[i] * up[i], D += m[i] * down[i];
      sums[c] = {M, 1.0 / M, rate, U, D};
    }
  };
  // The scalars' amounts (docs/scalars.md): each side sends amount x its
  // coefficient, so a swapped mass carries its sending cell's value.
  FaceExchange *ax = amountExchange();
  const bool withAmounts = ax && ax->numGathered() > 0 && ns > 0;
  const int w = ns * n; // amounts per cell
  const PetscScalar *ownAmounts = withAmounts ? ax->massAt(0) : nullptr;
  const PetscScalar *ghostAmounts = withAmounts && gathered > own ? ax->massAt(own) : nullptr;
  PetscScalar *ownAmountChanges = withAmounts ? ax->changeInMarked(0) : nullptr;
  PetscScalar *ghostAmountChanges = withAmounts ? ax->changeInMarked(own) : nullptr;
  auto swapFaces = [&](auto localSpeeds, auto amounts, const DriftFace *f, const DriftFace *end) {
    constexpr bool perCell = decltype(localSpeeds)::value; // else the fixed speeds, read once
    constexpr bool carry = decltype(amounts)::value;      // the scalars' amounts too
    for (; f != end; ++f) {
      const PetscInt L = f->lower, U = f->upper;
      if (!(swaps[L] & swaps[U])) continue;
      const CellSums &a = sums[L], &b = sums[U];
      const double cL = f->areaOverVolumeLower * a.rate, cU = f->areaOverVolumeUpper * b.rate;
      const double up = cL * a.up, down = cU * b.down;
      const double X = std::max(up, down);
      if (!(X > 0.0)) continue;
      // lambda = min(1, faceShare min(ML, MU) / X), dividing only when the
      // limiter acts (rarely: a division's latency is most of a face's).
      const double limit = faceShare * std::min(a.mass, b.mass);
      const double lambda = X <= limit ? 1.0 : limit / X;
      // The side that sent less tops up with its own mixture: X - sent over
      // its bulk mass (on the other side X - sent is 0, so no branch is needed).
      const double topLower = lambda * ((X - up) * a.inverseMass), topUpper = lambda * ((X - down) * b.inverseMass);
      const double kL = lambda * cL, kU = lambda * cU;
      const double *uL = perCell ? upLocal + L * n : upFixed;
      const double *uU = perCell ? downLocal + U * n : downFixed;
      const PetscScalar *mL = L < own ? ownMasses + L * n : ghostMasses + (L - own) * n;
      const PetscScalar *mU = U < own ? ownMasses + U * n : ghostMasses + (U - own) * n;
      double net[cap];
      for (int i = 0; i < n; ++i) net[i] = mL[i] * (kL * uL[i] + topLower) - mU[i] * (kU * uU[i] + topUpper);
      PetscScalar *dL = L < own ? ownChanges + L * n : ghostChanges + (L - own) * n;
      for (int i = 0; i < n; ++i) dL[i] -= net[i];
      PetscScalar *dU = U < own ? ownChanges + U * n : ghostChanges + (U - own) * n;
      for (int i = 0; i < n; ++i) dU[i] += net[i];
      if constexpr (carry) {
        const PetscScalar *aL = L < own ? ownAmounts + L * w : ghostAmounts + (L - own) * w;
        const PetscScalar *aU = U < own ? ownAmounts + U * w : ghostAmounts + (U - own) * w;
        PetscScalar *eL = L < own ? ownAmountChanges + L * w : ghostAmountChanges + (L - own) * w;
        PetscScalar *eU = U < own ? ownAmountChanges + U * w : ghostAmountChanges + (U - own) * w;
        double sendL[cap], sendU[cap]; // each side's share sent, per fraction
        for (int i = 0; i < n; ++i) sendL[i] = kL * uL[i] + topLower, sendU[i] = kU * uU[i] + topUpper;
        for (int k = 0; k < w; k += n)
          for (int i = 0; i < n; ++i) {
            const double moved = aL[k + i] * sendL[i] - aU[k + i] * sendU[i];
            eL[k + i] -= moved;
            eU[k + i] += moved;
          }
      }
    }
  };
  sumCells(ownMasses, 0, top); // while the ghosts' masses travel
  PetscCall(x.gatherEnd());
  ghostMasses = x.massAt(own);
  if (gathered > own) sumCells(ghostMasses, own, gathered);
  // The faces whose last own cell lies below the freeboard (the others do not swap).
  const auto end = std::partition_point(driftFaces.begin(), driftFaces.end(),
                                        [&](const DriftFace &f) { return lastOwnCell(f, own) < top; });
  const DriftFace *faces = driftFaces.data(), *below = faces + (end - driftFaces.begin());
  if (withAmounts) {
    if (local || measuredSpeeds) swapFaces(std::true_type{}, std::true_type{}, faces, below);
    else swapFaces(std::false_type{}, std::true_type{}, faces, below);
  } else if (local || measuredSpeeds) swapFaces(std::true_type{}, std::false_type{}, faces, below);
  else swapFaces(std::false_type{}, std::false_type{}, faces, below);
  // Both cells of a face that swaps are cells that swap.
  if (first <= last) x.markChanged(first, last + 1);
  if (withAmounts && first <= last) ax->markChanged(first, last + 1);
  PetscFunctionReturn(PETSC_SUCCESS);
}

// k_d's unit: the law's (unused by the constant model), per m/s
// of excess gas when scaled by it.
std::string DriftOperator::kdUnit() const {
  const std::string unit = model == Model::SizeLaw ? law->unitOfK() : "1/(m s)";
  return excessGas ? unit + " per m/s of excess gas" : unit;
}

PetscErrorCode DriftOperator::view(PetscViewer viewer) const {
  const std::string name = model == Model::SizeLaw ? lawName + ": " + law->formula()
                           : model == Model::Constant ? "constant velocities"
                           : model == Model::Measured ? "measured velocities (the database's field)" : "none";
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer, "drift: model %s, kd = %g %s, d32 = %.4g mm (%s)%s; applied every %d step(s)\n",
                                   name.c_str(), kd, kdUnit().c_str(), d32 * 1e3,
                                   localD32 ? "local per sending cell" : (d32Override > 0 ? "given" : "inventory"),
                                   hindered ? ", hindered" : "", (int)every));
  if (excessGas && isSetUp())
    PetscCall(PetscViewerASCIIPrintf(viewer, "  times the excess gas u_sup - u_mf = %.4g - %.4g = %.4g m/s (u_sup from the %s, u_mf by %s at the inventory's d32 %.4g mm)\n",
                                     gasUsup, gasUmf, gasFactor, usupSource.c_str(), umfCorrelation.c_str(),
                                     gasSauter * 1e3));
  if (agitation && agitationReference == 0.0)
    PetscCall(PetscViewerASCIIPrintf(viewer, "  scaled by (a/a_bar)^%g, a = %s agitation of the frame, a_bar = %.4g, a_max = %.4g, solid-weighted mean factor %.4g\n",
                                     agitationExponent, agitationMeasureName(agitation->measure()),
                                     agitation->solidWeightedMean(), agitation->maximum(), meanFactor));
  else if (agitation)
    PetscCall(PetscViewerASCIIPrintf(viewer, "  scaled by (a/a_ref)^%g, a = %s agitation of the frame, a_ref = %.4g (%s), a_bar = %.4g, a_max = %.4g, solid-weighted mean factor %.4g\n",
                                     agitationExponent, agitationMeasureName(agitation->measure()), normaliser,
                                     agitation->measure() == AgitationMeasure::LeavingShare ? "-drift_agitation_reference x dt_rec" : "-drift_agitation_reference",
                                     agitation->solidWeightedMean(), agitation->maximum(), meanFactor));
  if (agitation && agitation->measure() == AgitationMeasure::LeavingShare && isSetUp())
    PetscCall(PetscViewerASCIIPrintf(viewer, "  a_bar as a rate: %.4g 1/s (a_bar / dt_rec, dt_rec = %g s; the unit of -drift_agitation_reference)\n",
                                     agitation->solidWeightedMean() / database().metadata().dtRec, database().metadata().dtRec));
  PetscCall(PetscViewerASCIIPushTab(viewer));
  if (measured)
    PetscCall(PetscViewerASCIIPrintf(viewer, "measured drift field: regions of %d x %d x %d cells, %zu classes, %d frames\n",
                                     measured->regions().rx, measured->regions().ry, measured->regions().rz,
                                     measured->classDiameters().size(), measured->numFrames()));
  for (int i = 0; i < nf && !measured; ++i)
    PetscCall(PetscViewerASCIIPrintf(viewer, "fraction %d (d = %.4g mm): u_d = %+.4g m/s\n", i,
                                     diameter[i] * 1e3, velocityCache[i]));
  if (isSetUp())
    PetscCall(PetscViewerASCIIPrintf(viewer, "swap faces on this rank: %zu; sub-steps: %ld over %ld steps (at most %d)\n",
                                     exchange().faces().size(), substepsTaken(), stepsTaken(), maxSubsteps()));
  PetscCall(PetscViewerASCIIPopTab(viewer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
