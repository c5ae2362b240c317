// rcfd calibrate: the drift coefficient k_d that best reproduces a
// reference's segregation curve.  For each drift model, replay runs on the
// database (in-process: one Run object per evaluation, -drift_kd set through
// the options database) are scored against the reference with
// scoreDeltaZ; a coarse scan of log10 k_d brackets the minimum and a
// golden-section search refines it.
#include "cli/commands.hpp"
#include "base/petsc_compat.hpp"

#include "analysis/segregation_score.hpp"
#include "rcfd/run.hpp"
#include "base/collective.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace rcfd::cli {
namespace {

struct CalibrateOptions {
  std::string reference;
  std::vector<std::string> models{"B"};
  std::string objective = "rms"; // rms: RMS/peak of the curve; seg: |Delta_seg|
  double offset = 0.0, windowBegin = 0.5, windowEnd = 1.5;
  double kdLo = 1e2, kdHi = 1e6, tolerance = 0.01; // tolerance in log10 k_d
  PetscInt scanPoints = 9;
};

PetscErrorCode readCalibrateOptions(MPI_Comm comm, CalibrateOptions *o) {
  char ref[PETSC_MAX_PATH_LEN] = "", objective[16] = "rms";
  char *models[4] = {};
  PetscInt nmodels = 4, nrange = 2, nwindow = 2;
  PetscReal range[2] = {o->kdLo, o->kdHi}, window[2] = {o->windowBegin, o->windowEnd};
  PetscBool setRef = PETSC_FALSE, setModels = PETSC_FALSE, setRange = PETSC_FALSE,
            setWindow = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, nullptr, "rcfd calibrate: fit the drift coefficient to a reference", "rcfd");
  PetscCall(PetscOptionsString("-reference", "Reference cog.csv (rcfd reference)", "", "", ref,
                               sizeof ref, &setRef));
  PetscCall(PetscOptionsStringArray("-calibrate_models", "Drift models to fit: A, B or A,B", "",
                                    models, &nmodels, &setModels));
  PetscCall(PetscOptionsString("-calibrate_objective",
                               "rms: RMS of Delta z(t) - reference / reference peak; seg: |Eq. 7 error| in the window",
                               "", objective, objective, sizeof objective, nullptr));
  PetscCall(PetscOptionsRealArray("-calibrate_kd_range", "Search interval of k_d [1/(m s)]", "",
                                  range, &nrange, &setRange));
  PetscCall(PetscOptionsReal("-calibrate_tolerance", "Width of the final interval in log10 k_d",
                             "", o->tolerance, &o->tolerance, nullptr));
  PetscCall(PetscOptionsInt("-calibrate_scan", "Points of the coarse scan that brackets the minimum",
                            "", o->scanPoints, &o->scanPoints, nullptr));
  PetscCall(PetscOptionsReal("-rcfd_time_offset",
                             "Physical time of the database's frame 0 [s], added to the runs' times",
                             "", o->offset, &o->offset, nullptr));
  PetscCall(PetscOptionsRealArray("-score_window", "Window t0,t1 [s] of the Eq. 7 means", "",
                                  window, &nwindow, &setWindow));
  PetscOptionsEnd();
  std::vector<std::string> given;
  for (PetscInt i = 0; i < (setModels ? nmodels : 0); ++i) {
    given.emplace_back(models[i]);
    PetscCall(PetscFree(models[i]));
  }
  if (helpRequested()) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCheck(setRef, comm, PETSC_ERR_USER_INPUT,
             "No reference given: pass -reference REF/cog.csv (made by rcfd reference)");
  for (const auto &m : given)
    PetscCheck(m == "A" || m == "B", comm, PETSC_ERR_USER_INPUT,
               "-calibrate_models: model '%s' is not known; use A, B or A,B", m.c_str());
  o->objective = objective;
  PetscCheck(o->objective == "rms" || o->objective == "seg", comm, PETSC_ERR_USER_INPUT,
             "-calibrate_objective %s is not known; use rms or seg", objective);
  PetscCheck((!setRange || nrange == 2) && range[0] > 0 && range[0] < range[1], comm, PETSC_ERR_USER_INPUT,
             "-calibrate_kd_range takes two values lo,hi with 0 < lo < hi");
  PetscCheck(o->tolerance > 0, comm, PETSC_ERR_USER_INPUT, "-calibrate_tolerance must be positive");
  PetscCheck(o->scanPoints >= 3, comm, PETSC_ERR_USER_INPUT, "-calibrate_scan must be at least 3");
  PetscCheck((!setWindow || nwindow == 2) && window[0] < window[1], comm, PETSC_ERR_USER_INPUT,
             "-score_window takes two times t0,t1 [s] with t0 < t1");
  o->reference = ref;
  if (!given.empty()) o->models = given;
  o->kdLo = range[0];
  o->kdHi = range[1];
  o->windowBegin = window[0];
  o->windowEnd = window[1];
  PetscFunctionReturn(PETSC_SUCCESS);
}

/// Runs the case with the given model and k_d and scores it.
class Evaluator {
public:
  Evaluator(MPI_Comm comm, const OperatorRegistry &registry, const CalibrateOptions &opt,
            const DeltaZSeries &reference)
      : comm(comm), registry(registry), opt(opt), reference(reference) {}

  PetscErrorCode operator()(const std::string &model, double log10kd, DeltaZScore *score) {
    char kd[32];
    PetscFunctionBeginUser;
    std::snprintf(kd, sizeof kd, "%.17g", std::pow(10.0, log10kd));
    PetscCall(PetscOptionsSetValue(nullptr, "-drift_model", model.c_str()));
    PetscCall(PetscOptionsSetValue(nullptr, "-drift_kd", kd));
    Run run(comm, registry);
    PetscCall(run.setFromOptions());
    if (!checked) { // every option must have been read by now
      PetscCall(rejectUnusedOptions(comm, "calibrate"));
      checked = true;
    }
    PetscCall(run.setUp());
    PetscCall(run.solve());
    DeltaZSeries s;
    for (const BedSample &b : run.history()) {
      s.time.push_back(b.time + opt.offset);
      s.deltaZ.push_back(b.deltaZ);
    }
    PetscCall(collectively(
        comm, [&] { *score = scoreDeltaZ(reference, s, opt.windowBegin, opt.windowEnd); },
        PETSC_ERR_USER_INPUT));
    ++evaluations;
    PetscFunctionReturn(PETSC_SUCCESS);
  }

  double objective(const DeltaZScore &s) const {
    return opt.objective == "rms" ? s.rmsRelative : std::fabs(s.segregationError);
  }
  int count() const { return evaluations; }

private:
  MPI_Comm comm;
  const OperatorRegistry &registry;
  const CalibrateOptions &opt;
  const DeltaZSeries &reference;
  bool checked = false;
  int evaluations = 0;
};

} // namespace

PetscErrorCode calibrateCommand(MPI_Comm comm) {
  CalibrateOptions opt;
  PetscFunctionBeginUser;
  PetscCall(readCalibrateOptions(comm, &opt));
  if (helpRequested()) { // list the run's options too; without -db the run stops early, never mind
    const OperatorRegistry registry = OperatorRegistry::withBuiltins();
    Run run(comm, registry);
    (void)run.setFromOptions();
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  // The runs are silent and write no fields or plots; their cog.csv goes to
  // -output_dir (default rcfd-calibrate), overwritten by each evaluation.
  PetscCall(PetscOptionsSetValue(nullptr, "-quiet", "true"));
  PetscCall(PetscOptionsSetValue(nullptr, "-fields", "false"));
  PetscCall(PetscOptionsSetValue(nullptr, "-plot", "false"));
  PetscBool hasDir = PETSC_FALSE;
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-output_dir", &hasDir));
  if (!hasDir) PetscCall(PetscOptionsSetValue(nullptr, "-output_dir", "rcfd-calibrate"));

  DeltaZSeries reference;
  PetscCall(collectively(comm, [&] { reference = readDeltaZCsv(opt.reference); }, PETSC_ERR_USER_INPUT));
  const OperatorRegistry registry = OperatorRegistry::withBuiltins();
  Evaluator evaluate(comm, registry, opt, reference);
  const double lo = std::log10(opt.kdLo), hi = std::log10(opt.kdHi);
  PetscCall(PetscPrintf(comm,
                        "Calibrating k_d in [%g, %g] 1/(m s) against %s, objective %s (%s), "
                        "Eq. 7 window [%g, %g] s\n",
                        opt.kdLo, opt.kdHi, opt.reference.c_str(), opt.objective.c_str(),
                        opt.objective == "rms" ? "RMS of the Delta z(t) difference / reference peak"
                                               : "|Delta_seg|",
                        opt.windowBegin, opt.windowEnd));

  for (const std::string &model : opt.models) {
    PetscCall(PetscPrintf(comm, "model %s:\n  %12s %14s %12s %10s\n", model.c_str(), "k_d",
                          "mean dz [mm]", "Delta_seg [%]", "RMS/peak"));
    auto report = [&](double x, const DeltaZScore &s) -> PetscErrorCode {
      return PetscPrintf(comm, "  %12.5g %14.4f %12.1f %10.4f\n", std::pow(10.0, x),
                         1e3 * s.meanModel, s.segregationError, s.rmsRelative);
    };
    // Coarse scan, then golden section in the bracket around the best point.
    const int n = static_cast<int>(opt.scanPoints);
    std::vector<double> xs(n), fs(n);
    DeltaZScore s;
    for (int i = 0; i < n; ++i) {
      xs[i] = lo + (hi - lo) * i / (n - 1);
      PetscCall(evaluate(model, xs[i], &s));
      fs[i] = evaluate.objective(s);
      PetscCall(report(xs[i], s));
    }
    const int best = static_cast<int>(std::min_element(fs.begin(), fs.end()) - fs.begin());
    double a = xs[std::max(0, best - 1)], b = xs[std::min(n - 1, best + 1)];
    const double g = (std::sqrt(5.0) - 1.0) / 2.0;
    double c = b - g * (b - a), d = a + g * (b - a), fc, fd;
    PetscCall(evaluate(model, c, &s));
    fc = evaluate.objective(s);
    PetscCall(report(c, s));
    PetscCall(evaluate(model, d, &s));
    fd = evaluate.objective(s);
    PetscCall(report(d, s));
    while (b - a > opt.tolerance) {
      if (fc < fd) {
        b = d, d = c, fd = fc;
        c = b - g * (b - a);
        PetscCall(evaluate(model, c, &s));
        fc = evaluate.objective(s);
        PetscCall(report(c, s));
      } else {
        a = c, c = d, fc = fd;
        d = a + g * (b - a);
        PetscCall(evaluate(model, d, &s));
        fd = evaluate.objective(s);
        PetscCall(report(d, s));
      }
    }
    double xBest = fc < fd ? c : d;
    if (fs[best] < std::min(fc, fd)) xBest = xs[best];
    DeltaZScore sb;
    PetscCall(evaluate(model, xBest, &sb));
    PetscCall(PetscPrintf(comm,
                          "model %s: best k_d = %.4g 1/(m s): Delta_seg %.1f %%, RMS/peak %.3f, "
                          "mean dz %.4g mm (reference %.4g mm)\n",
                          model.c_str(), std::pow(10.0, xBest), sb.segregationError,
                          sb.rmsRelative, 1e3 * sb.meanModel, 1e3 * sb.meanRef));
  }
  PetscCall(PetscPrintf(comm, "%d replay runs\n", evaluate.count()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
