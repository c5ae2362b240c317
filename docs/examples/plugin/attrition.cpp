// An rcfd plugin: what a researcher adds to the rcfd program without
// rebuilding it (docs/extending.md).  It registers
//  - the operator "attrition": every step a share k dt of each fraction but
//    the finest is ground into the next finer one (-attrition_rate k [1/s]);
//    total mass is kept, each fraction's changes on purpose and is accounted
//    (addedMass, kept across a restart by saveState);
//  - the size law "linear": u = kd (d32 - d) / d32, kd in m/s
//    (-drift_size_law linear);
//  - the monitor "fines": fines.csv, the finest fraction's share of the bed
//    over time (-monitors fines, -fines_every N);
//  - the path rule "stride": frames 0, s, 2s, ... modulo the number of
//    frames (-path_type stride -path_stride s).
//
//   rcfd run -plugin ./librcfd_attrition.so -pipeline shift,drift,attrition,carry -attrition_rate 0.05
#include <rcfd/plugin.hpp>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

RCFD_PLUGIN_VERSION_SYMBOL

namespace {

class Attrition : public rcfd::Operator {
public:
  std::string type() const override { return "attrition"; }

  PetscErrorCode setFromOptions(MPI_Comm comm) override {
    PetscFunctionBeginUser;
    PetscOptionsBegin(comm, optionsPrefix().c_str(), "Attrition: fractions ground into the next finer one", "plugin");
    PetscCall(PetscOptionsReal("-rate", "Share of each fraction ground per second [1/s]", "", rate, &rate, nullptr));
    PetscOptionsEnd();
    PetscCheck(rate >= 0 && rate < 100, comm, PETSC_ERR_USER_INPUT,
               "-%srate must be a rate in [0, 100) 1/s, got %g", optionsPrefix().c_str(), (double)rate);
    PetscFunctionReturn(0);
  }

  bool needed(const rcfd::RunContext &ctx) const override { return rate > 0 && ctx.fractions.size() > 1; }

  // Re-entrant: a run on several databases calls it again on every switch;
  // what the run has ground so far (added) is kept.
  PetscErrorCode setUp(const rcfd::RunContext &ctx) override {
    PetscFunctionBeginUser;
    nf = ctx.fractions.size();
    if (added.size() != static_cast<std::size_t>(nf)) added.assign(nf, 0.0);
    // The fractions' order by diameter: finer[i] is the next finer than i (-1: none).
    finer.assign(nf, -1);
    for (int i = 0; i < nf; ++i)
      for (int j = 0; j < nf; ++j)
        if (ctx.fractions.diameter(j) < ctx.fractions.diameter(i) &&
            (finer[i] < 0 || ctx.fractions.diameter(j) > ctx.fractions.diameter(finer[i])))
          finer[i] = j;
    PetscFunctionReturn(0);
  }

  PetscErrorCode apply(const rcfd::StepInfo &step, rcfd::FractionState &state) override {
    PetscScalar *m;
    PetscInt n;
    PetscFunctionBeginUser;
    const double share = 1.0 - std::exp(-rate * step.dt);
    std::vector<double> moved(nf, 0.0);
    PetscCall(VecGetLocalSize(state.masses(), &n));
    PetscCall(VecGetArray(state.masses(), &m));
    for (PetscInt c = 0; c < n; c += nf)
      for (int i = 0; i < nf; ++i) {
        if (finer[i] < 0) continue;
        const double dm = share * m[c + i];
        m[c + i] -= dm;
        m[c + finer[i]] += dm;
        moved[i] += dm;
      }
    PetscCall(VecRestoreArray(state.masses(), &m));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, moved.data(), nf, MPI_DOUBLE, MPI_SUM,
                               PetscObjectComm((PetscObject)state.masses())));
    for (int i = 0; i < nf; ++i)
      if (finer[i] >= 0) added[i] -= moved[i], added[finer[i]] += moved[i];
    PetscFunctionReturn(0);
  }

  PetscErrorCode view(PetscViewer viewer) const override {
    PetscFunctionBeginUser;
    PetscCall(PetscViewerASCIIPrintf(viewer, "attrition: rate %g 1/s\n", (double)rate));
    PetscFunctionReturn(0);
  }

  bool conservesMass() const override { return false; } // per fraction; the total is kept
  const std::vector<double> *addedMass() const override { return &added; }
  std::vector<double> saveState() const override { return added; }
  PetscErrorCode restoreState(const std::vector<double> &state) override {
    PetscFunctionBeginUser;
    PetscCheck(state.size() == added.size(), PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG,
               "The checkpoint's attrition state holds %zu numbers for %zu fractions", state.size(), added.size());
    added = state;
    PetscFunctionReturn(0);
  }

private:
  PetscReal rate = 0.0;
  int nf = 0;
  std::vector<int> finer;
  std::vector<double> added; // [kg] per fraction since the start
};

class LinearLaw : public rcfd::SizeLaw {
public:
  std::string type() const override { return "linear"; }
  void velocities(double k, double dRef, const double *d, int n, double *u) const override {
    for (int i = 0; i < n; ++i) u[i] = k * (dRef - d[i]) / dRef;
  }
  const char *unitOfK() const override { return "m/s"; }
  std::string formula() const override { return "u = kd (d32 - d)/d32"; }
};

// fines.csv: time_s,fines_share -- the finest fraction's share of the bed's mass.
class FinesMonitor : public rcfd::Monitor {
public:
  std::string type() const override { return "fines"; }
  PetscErrorCode setUp(const rcfd::RunContext &run, const rcfd::FractionState &, const std::string &dir) override {
    PetscFunctionBeginUser;
    nf = run.fractions.size();
    finest = 0;
    for (int i = 1; i < nf; ++i)
      if (run.fractions.diameter(i) < run.fractions.diameter(finest)) finest = i;
    csv = std::make_unique<rcfd::CsvSeries>(run.db.layout().comm(), dir + "/fines.csv", "time_s,fines_share");
    PetscFunctionReturn(0);
  }
  PetscErrorCode sample(const rcfd::MonitorContext &ctx) override {
    const PetscScalar *m;
    PetscInt n;
    double sums[2] = {0.0, 0.0}; // finest, all
    PetscFunctionBeginUser;
    PetscCall(VecGetLocalSize(ctx.state.masses(), &n));
    PetscCall(VecGetArrayRead(ctx.state.masses(), &m));
    for (PetscInt c = 0; c < n; c += nf)
      for (int i = 0; i < nf; ++i) sums[1] += m[c + i], sums[0] += i == finest ? m[c + i] : 0.0;
    PetscCall(VecRestoreArrayRead(ctx.state.masses(), &m));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_DOUBLE, MPI_SUM, PetscObjectComm((PetscObject)ctx.state.masses())));
    PetscCall(csv->add(rcfd::formatNumberRow({ctx.time, sums[0] / sums[1]})));
    PetscFunctionReturn(0);
  }
  PetscErrorCode flush() override { return csv->flush(); }
  std::vector<double> saveState() const override { return csv->state(); }
  PetscErrorCode restoreState(const std::vector<double> &state) override {
    PetscFunctionBeginUser;
    if (!state.empty()) PetscCall(csv->resume(state[0]));
    PetscFunctionReturn(0);
  }

private:
  int nf = 0, finest = 0;
  std::unique_ptr<rcfd::CsvSeries> csv;
};

// Frames 0, s, 2s, ... modulo the number of frames; every step but the first
// is a jump when s != 1.  Deterministic from its option and the database.
class StridePath : public rcfd::FramePath {
public:
  std::string type() const override { return "stride"; }
  std::string describe() const override { return "stride: every " + std::to_string(stride) + " frames"; }
  PetscErrorCode setFromOptions(MPI_Comm comm) override {
    PetscFunctionBeginUser;
    PetscOptionsBegin(comm, optionsPrefix().c_str(), "Stride path (plugin)", "plugin");
    PetscCall(PetscOptionsInt("-stride", "Frames between steps", "", stride, &stride, nullptr));
    PetscOptionsEnd();
    PetscCheck(stride >= 1, comm, PETSC_ERR_USER_INPUT, "-%sstride must be at least 1, got %d", optionsPrefix().c_str(),
               (int)stride);
    PetscFunctionReturn(0);
  }

protected:
  int advance(bool &jump) override {
    jump = frame() >= 0 && stride != 1;
    return frame() < 0 ? 0 : static_cast<int>((frame() + stride) % numFrames());
  }
  std::uint64_t fingerprint() const override { return 0x5717de00u + static_cast<std::uint64_t>(stride); }
  void saveExtra(std::vector<std::uint64_t> &) const override {}
  PetscErrorCode restoreExtra(const std::uint64_t *, std::size_t) override { return 0; }

private:
  PetscInt stride = 1;
};

} // namespace

extern "C" __attribute__((visibility("default"))) PetscErrorCode rcfd_plugin_register(rcfd::Registries *r) {
  PetscFunctionBeginUser;
  PetscCall(r->operators.add("attrition", [] { return std::make_unique<Attrition>(); },
                             "plugin: each fraction ground into the next finer one (-attrition_rate k [1/s])"));
  PetscCall(r->operators.sizeLaws().add("linear", [] { return std::make_unique<LinearLaw>(); },
                                        "plugin: u = kd (d32 - d)/d32, kd in m/s"));
  PetscCall(r->paths.add("stride", [] { return std::make_unique<StridePath>(); },
                         "plugin: frames 0, s, 2s, ... (-path_stride s)"));
  PetscCall(r->monitors.add("fines", [] { return std::make_unique<FinesMonitor>(); },
                            "plugin: fines.csv, the finest fraction's share of the bed"));
  PetscFunctionReturn(0);
}
