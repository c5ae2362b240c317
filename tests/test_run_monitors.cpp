// Monitors added with Run::addMonitor are called exactly at the initial
// state, at every multiple of their interval and after the last step, with
// the step's time, the frame the state should match (the frame of the next
// step) and the state itself; a Monitor object is set up once and flushed.
// The built-in centre-of-gravity monitor goes through the same list.
// Runs at 1 and 2 ranks.
// usage: test_run_monitors OUTPUT_DIR -db SMALL.h5 [run options]
#include "check.hpp"
#include "base/petsc_compat.hpp"
#include "rcfd/run.hpp"

#include <cmath>
#include <string>
#include <vector>

using namespace rcfd;

namespace {

struct Call {
  long step;
  double time;
  int frame;
  bool last;
  double mass; // total mass of all fractions [kg]
};

/// Counts its life-cycle calls.
class CountingMonitor : public Monitor {
public:
  int setUps = 0, samples = 0, flushes = 0;
  PetscErrorCode setUp(const RunContext &, const FractionState &, const std::string &) override {
    ++setUps;
    return PETSC_SUCCESS;
  }
  PetscErrorCode sample(const MonitorContext &) override {
    ++samples;
    return PETSC_SUCCESS;
  }
  PetscErrorCode flush() override {
    ++flushes;
    return PETSC_SUCCESS;
  }
};

} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  {
    PetscCheck(argc > 1, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT,
               "usage: test_run_monitors OUTPUT_DIR -db DATABASE");
    const OperatorRegistry registry = OperatorRegistry::withBuiltins();
    Run run(PETSC_COMM_WORLD, registry);
    PetscCall(run.setFromOptions());
    run.setQuiet(true);
    run.keepHistory(true); // history() and framesUsed() below
    run.setWriteFields(false);
    PetscMPIInt size;
    PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
    run.setOutputDirectory(std::string(argv[1]) + "-np" + std::to_string(size)); // np 1 and 2 may run at once

    const long every = 7;
    std::vector<Call> calls, ends;
    PetscCall(run.addMonitor(
        [&](const MonitorContext &m) -> PetscErrorCode {
          std::vector<double> totals;
          PetscFunctionBeginUser;
          PetscCall(m.state.totals(&totals)); // collective: every rank calls its monitors together
          double mass = 0.0;
          for (double t : totals) mass += t;
          calls.push_back({m.step, m.time, m.frame, m.last, mass});
          PetscFunctionReturn(PETSC_SUCCESS);
        },
        every, "probe"));
    PetscCall(run.addMonitor(
        [&](const MonitorContext &m) -> PetscErrorCode {
          ends.push_back({m.step, m.time, m.frame, m.last, 0.0});
          return PETSC_SUCCESS;
        },
        0, "first and last"));
    auto counting = std::make_unique<CountingMonitor>();
    CountingMonitor *counter = counting.get();
    PetscCall(run.addMonitor(std::move(counting), 1, "counter"));
    PetscCall(run.setUp());
    PetscCall(run.solve());

    const long steps = run.numSteps();
    const double dt = run.database().metadata().dtRec;
    RCFD_CHECK(steps == 60); // -t_end 0.3 at dt_rec 5 ms
    std::vector<long> expected;
    for (long s = 0; s < steps; s += every) expected.push_back(s);
    expected.push_back(steps); // 60 is no multiple of 7: the last step is added
    RCFD_CHECK(calls.size() == expected.size());
    const auto &frames = run.framesUsed();
    RCFD_CHECK(frames.size() == static_cast<size_t>(steps));
    const auto &history = run.history(); // the built-in monitor: every step
    RCFD_CHECK(history.size() == static_cast<size_t>(steps + 1));
    for (size_t k = 0; k < std::min(calls.size(), expected.size()); ++k) {
      const Call &c = calls[k];
      RCFD_CHECK(c.step == expected[k]);
      RCFD_CHECK_CLOSE(c.time, expected[k] * dt, 1e-14);
      RCFD_CHECK(c.last == (c.step == steps));
      // The state after step s matches the frame step s uses next.
      if (c.step < steps) RCFD_CHECK(c.frame == frames[c.step]);
      if (c.step < static_cast<long>(history.size())) {
        RCFD_CHECK_CLOSE(c.time, history[c.step].time, 1e-14);
        double mass = 0.0;
        for (double m : history[c.step].mass) mass += m;
        RCFD_CHECK_CLOSE(c.mass, mass, 1e-12);
      }
    }
    RCFD_CHECK(ends.size() == 2);
    if (ends.size() == 2) {
      RCFD_CHECK(ends[0].step == 0 && !ends[0].last);
      RCFD_CHECK(ends[1].step == steps && ends[1].last);
      RCFD_CHECK_CLOSE(ends[1].time, steps * dt, 1e-14);
    }
    RCFD_CHECK(counter->setUps == 1);
    RCFD_CHECK(counter->samples == steps + 1);
    RCFD_CHECK(counter->flushes >= 1);
  }
  const int result = RCFD_TEST_RESULT();
  PetscCall(PetscFinalize());
  return result;
}
