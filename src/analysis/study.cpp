// The public study API (include/rcfd/study.hpp): calibration and ensembles
// as objects with PETSc's life cycle, over the analysis room's
// DriftCalibration and writeEnsembleSummary (the comparison:
// study_comparison.cpp).
#include "rcfd/study.hpp"
#include "base/petsc_compat.hpp"

#include "analysis/calibration.hpp"
#include "analysis/study_agreement.hpp"
#include "analysis/ensemble.hpp"
#include "base/collective.hpp"
#include "rcfd/handle.hpp"
#include "rcfd/drift.hpp"
#include "rcfd/run.hpp"
#include "rcfd/size_law.hpp"

#include <cmath>
#include <cstdio>
#include <numeric>

namespace rcfd {

namespace {
// A viewer asked for with -<prefix>NAME (e.g. -calibrate_view ascii:FILE).
struct AskedViewer {
  OwnedViewer viewer;
  PetscViewerFormat format = PETSC_VIEWER_DEFAULT;
  PetscErrorCode read(MPI_Comm comm, const std::string &prefix, const char *name) {
    PetscFunctionBeginUser;
    PetscCall(PetscOptionsGetViewer(comm, nullptr, prefix.empty() ? nullptr : prefix.c_str(), name, viewer.put(),
                                    &format, nullptr));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  template <typename Object> PetscErrorCode show(const Object &object) const {
    PetscFunctionBeginUser;
    if (!viewer) PetscFunctionReturn(PETSC_SUCCESS);
    PetscCall(PetscViewerPushFormat(viewer, format));
    PetscCall(object.view(viewer));
    PetscCall(PetscViewerPopFormat(viewer));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
};

} // namespace

// ---------------------------------------------------------------------------
// Calibration

struct Calibration::Impl {
  Impl(MPI_Comm c, const Registries &registries) : comm(c), search(c, registries) {}
  MPI_Comm comm;
  std::string prefix;
  DriftCalibration search;
  AskedViewer asked; // -calibrate_view
};

Calibration::Calibration(MPI_Comm comm, const Registries &registries)
    : impl(std::make_unique<Impl>(comm, registries)) {}
Calibration::~Calibration() = default;

void Calibration::setOptionsPrefix(const std::string &prefix) {
  impl->prefix = prefix;
  impl->search.setOptionsPrefix(prefix);
}

PetscErrorCode Calibration::setFromOptions() {
  PetscFunctionBeginUser;
  PetscCall(impl->search.setFromOptions());
  PetscCall(impl->asked.read(impl->comm, impl->prefix, "-calibrate_view"));
  PetscFunctionReturn(PETSC_SUCCESS);
}
PetscErrorCode Calibration::setUp() { return impl->search.setUp(); }
int Calibration::evaluations() const { return impl->search.evaluations(); }

PetscErrorCode Calibration::solve() {
  PetscFunctionBeginUser;
  PetscCall(impl->search.solve());
  best.clear();
  for (const DriftCalibration::Result &r : impl->search.results()) {
    Result out;
    out.model = r.model;
    out.kd = r.kd;
    out.unit = r.unit;
    out.kdStandardError = r.kdStandardError;
    out.scored = r.scored;
    if (r.scored) out.agreement = agreementOf(r.score);
    best.push_back(out);
  }
  PetscCall(impl->asked.show(*this));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Calibration::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer, "Calibration: %d replays\n", evaluations()));
  for (const Result &r : best) {
    PetscCall(PetscViewerASCIIPrintf(viewer, "  %s: k_d = %.4g %s%s", r.model.c_str(), r.kd, r.unit.c_str(),
                                     r.scored ? ", " : "\n"));
    if (r.scored) {
      PetscCall(PetscViewerASCIIUseTabs(viewer, PETSC_FALSE));
      PetscCall(viewAgreement(viewer, r.agreement));
      PetscCall(PetscViewerASCIIUseTabs(viewer, PETSC_TRUE));
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

// ---------------------------------------------------------------------------
// Ensemble

struct Ensemble::Impl {
  Impl(MPI_Comm c, const Registries &r) : comm(c), registries(r) {}
  MPI_Comm comm;
  const Registries &registries;
  std::unique_ptr<Run> first; // read the options; the members read them again
  std::shared_ptr<Database> db;
  std::uint64_t seed = 0;
  AskedViewer asked; // -ensemble_view
  std::string driftLaw; // setDriftLaw(): its size law (empty: the options'), k_d and its unit
  double driftKd = 0.0;
  std::string driftUnit;
};

Ensemble::Ensemble(MPI_Comm comm, const Registries &registries) : impl(std::make_unique<Impl>(comm, registries)) {}
Ensemble::~Ensemble() = default;

PetscErrorCode Ensemble::setMembers(int members) {
  PetscFunctionBeginUser;
  PetscCheck(members >= 1, impl->comm, PETSC_ERR_ARG_OUTOFRANGE, "-ensemble must be at least 1");
  count = members;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Ensemble::setFromOptions() {
  PetscFunctionBeginUser;
  impl->first = std::make_unique<Run>(impl->comm, impl->registries);
  if (impl->db) impl->first->useDatabase(impl->db);
  PetscCall(impl->first->setFromOptions());
  PetscCall(impl->asked.read(impl->comm, "", "-ensemble_view"));
  directory = impl->first->outputDirectory();
  PetscFunctionReturn(PETSC_SUCCESS);
}

void Ensemble::useDatabase(std::shared_ptr<Database> database) { impl->db = std::move(database); }

namespace {
// %g as C prints it (PETSc's own %g writes 0 as "0.").
std::string shortNumber(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}

// The drift operator of a run's -pipeline, or null.
DriftOperator *driftOf(Run &run) {
  DriftOperator *drift = nullptr;
  for (const auto &op : run.pipeline().operators())
    if (auto *d = dynamic_cast<DriftOperator *>(op.get())) drift = d;
  return drift;
}
} // namespace

PetscErrorCode Ensemble::setDriftLaw(const std::string &sizeLaw, double kd) {
  std::unique_ptr<SizeLaw> law;
  PetscFunctionBeginUser;
  PetscCall(impl->registries.operators.sizeLaws().create(sizeLaw, &law));
  PetscCheck(std::isfinite(kd) && kd > 0.0, impl->comm, PETSC_ERR_ARG_OUTOFRANGE,
             "Ensemble::setDriftLaw: k_d of the size law %s must be positive and finite, not %s", sizeLaw.c_str(),
             shortNumber(kd).c_str());
  impl->driftLaw = sizeLaw;
  impl->driftKd = kd;
  impl->driftUnit = law->unitOfK();
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Ensemble::setDriftLaw(const Calibration::Result &fit) { return setDriftLaw(fit.model, fit.kd); }

PetscErrorCode Ensemble::setUp() {
  PetscFunctionBeginUser;
  PetscCheck(impl->first, impl->comm, PETSC_ERR_ORDER, "Ensemble: call setFromOptions() before setUp()");
  const Run &run = *impl->first;
  PetscCheck(!run.switchesDatabases(), impl->comm, PETSC_ERR_USER_INPUT,
             "-ensemble %d with several databases in -db: an ensemble's members share one loaded database, and "
             "a run on several reads and drops them as it switches; run each member as its own rcfd run on the "
             "set with -path_seed s, s+1, ... (or the ensemble on one database of the set)", count);
  PetscCheck(run.path().hasSeed(), impl->comm, PETSC_ERR_USER_INPUT,
             "-ensemble %d needs a stochastic -path_type (random, markov or quarter), not %s", count,
             run.path().type().c_str());
  PetscCheck(impl->driftLaw.empty() || driftOf(*impl->first), impl->comm, PETSC_ERR_USER_INPUT,
             "Ensemble::setDriftLaw(%s, %s): -pipeline has no drift operator to run it (add drift)",
             impl->driftLaw.c_str(), shortNumber(impl->driftKd).c_str());
  impl->seed = run.path().seed();
  PetscFunctionReturn(PETSC_SUCCESS);
}

namespace {
PetscErrorCode totalMass(const Run &run, double *total) {
  std::vector<double> perFraction;
  PetscFunctionBeginUser;
  PetscCall(run.state().totals(&perFraction));
  *total = std::accumulate(perFraction.begin(), perFraction.end(), 0.0);
  PetscFunctionReturn(PETSC_SUCCESS);
}
} // namespace

// Every member reads the options itself; the setters then give it its own
// seed and directory and turn fields off.
PetscErrorCode Ensemble::solve() {
  const MPI_Comm comm = impl->comm;
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  std::vector<std::string> csvs;
  std::shared_ptr<Database> db = impl->db;
  massBefore.assign(count, 0.0);
  massAfter.assign(count, 0.0);
  for (int k = 0; k < count; ++k) {
    const std::string dir = directory + "/member_" + std::to_string(k);
    const std::uint64_t seed = impl->seed + static_cast<std::uint64_t>(k);
    Run member(comm, impl->registries);
    if (db) member.useDatabase(db);
    PetscCall(member.setFromOptions());
    PetscCall(member.setPathSeed(seed));
    if (!impl->driftLaw.empty()) { // as the calibration's replays set it (DriftCalibration::configureDrift)
      DriftOperator *drift = driftOf(member);
      PetscCall(drift->setSizeLaw(impl->driftLaw));
      drift->setKd(impl->driftKd);
    }
    member.setOutputDirectory(dir);
    member.setWriteFields(false);
    PetscCall(member.setUp());
    db = member.sharedDatabase();
    PetscCall(totalMass(member, &massBefore[k]));
    if (!member.quiet())
      PetscCall(PetscPrintf(comm, "Ensemble member %d of %d (path seed %llu)\n", k + 1, count,
                            static_cast<unsigned long long>(seed)));
    PetscCall(member.solve());
    PetscCall(totalMass(member, &massAfter[k]));
    csvs.push_back(dir + "/cog.csv");
  }
  PetscCall(collectively(comm, [&] {
    if (rank == 0) writeEnsembleSummary(csvs, summaryFile());
  }));
  PetscCall(impl->asked.show(*this));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Ensemble::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer, "Ensemble: %d members, path seeds %llu to %llu, summary %s\n", count,
                                   static_cast<unsigned long long>(impl->seed),
                                   static_cast<unsigned long long>(impl->seed + count - 1), summaryFile().c_str()));
  if (!impl->driftLaw.empty())
    PetscCall(PetscViewerASCIIPrintf(viewer, "  drift: size law %s, k_d = %s %s\n", impl->driftLaw.c_str(),
                                     shortNumber(impl->driftKd).c_str(), impl->driftUnit.c_str()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
