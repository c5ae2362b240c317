// A live run (rcfd run -live FILE, docs/live.md): the measured conditions of
// src/run/live_input reach what a schedule drives -- the switching rule's u_sup
// (switching and blending), the conditions the monitors see (bottom-layer u_mf
// and the de-fluidization warning) -- the granulator's rates and the scalars'
// spray rate and gas temperature (their u_sup follows in the time loop, run.cpp).  A row
// holds from its time on, so a step starting at t uses the row at or before t,
// exactly as a -db_switch_schedule entry: a live run fed a schedule's
// conditions gives the schedule run's bits.
#include "run/run_impl.hpp"
#include "run/find_operator.hpp"
#include "rcfd/granulation.hpp"
#include "base/collective.hpp"
#include "base/petsc_compat.hpp"

#include <cmath>

namespace rcfd {
PetscErrorCode Run::Impl::liveStart() {
  PetscFunctionBeginUser;
  PetscCall(live.start(comm, set, quiet == PETSC_TRUE));
  const std::string file = "-live " + live.path() + ": ";
  const std::string missing = granulatorColumnWithoutOperator(live, ops);
  PetscCheck(missing.empty(), comm, PETSC_ERR_USER_INPUT, "%s%s (-pipeline %s has none)", file.c_str(), missing.c_str(),
             pipelineSpec.c_str());
  // The scalars' sources (docs/scalars.md): spray into moisture, the gas's inlet temperature.
  ScalarSources &sources = scalars.sources();
  PetscCheck(!live.has(LiveInput::SprayRate) || (scalars.size() > 0 && sources.canSpray()), comm, PETSC_ERR_USER_INPUT,
             "%sthe column spray_rate needs a scalar named moisture in -scalars (the liquid it adds, kg per kg "
             "solid)", file.c_str());
  PetscCheck(!live.has(LiveInput::GasTemperature) || (scalars.size() > 0 && sources.exchanges()), comm,
             PETSC_ERR_USER_INPUT, "%sthe column gas_temperature needs the scalars' exchange with the gas "
             "(-scalars temperature and -scalar_exchange_model gunn or constant)", file.c_str());
  if (live.has(LiveInput::SprayRate)) sources.followSpray(); // its zone is set up even at a rate of 0
  if (live.has(LiveInput::SuperficialVelocity) && !switching) {
    // Two answers to "what is u_sup" would give bottom.csv one and the case the other.
    PetscCheck(!std::isfinite(answers.fluidization().given.superficialVelocity), comm, PETSC_ERR_USER_INPUT,
               "-superficial_velocity %g and the live file's u_sup column both give u_sup; give it once (%s)",
               answers.fluidization().given.superficialVelocity, live.path().c_str());
    liveVelocity = true;
  }
  PetscCall(liveFollow(0.0)); // the switching rule's first u_sup, before it chooses the first database
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Run::Impl::liveFollow(double time) {
  PetscFunctionBeginUser;
  if (!live.enabled()) PetscFunctionReturn(PETSC_SUCCESS);
  if (live.has(LiveInput::SuperficialVelocity) && switching) {
    // The same rows on every rank: the rule refuses on all of them alike.
    PetscCall(collectively(comm, [&] {
      for (; liveRowsScheduled < live.numRows(); ++liveRowsScheduled) try {
          throwOnError([&] {
            return switching->appendSchedule(live.rowTime(liveRowsScheduled),
                                             live.rowValue(liveRowsScheduled, LiveInput::SuperficialVelocity));
          });
        } catch (const std::exception &e) {
          throw std::invalid_argument("-live " + live.path() + ": the column u_sup cannot drive the switching: " +
                                      e.what());
        }
    }, PETSC_ERR_USER_INPUT));
  }
  if (liveVelocity) {
    if (db) liveConditions = db->metadata().conditions;
    liveConditions.superficialVelocity = live.at(LiveInput::SuperficialVelocity, time);
  }
  if (scalars.size() > 0) { // the sources take the conditions of the steps from `time` on
    ScalarSources &sources = scalars.sources();
    if (live.has(LiveInput::SprayRate)) sources.setSprayRate(live.at(LiveInput::SprayRate, time));
    if (live.has(LiveInput::GasTemperature)) sources.setGasTemperature(live.at(LiveInput::GasTemperature, time));
  }
  setGranulatorRates(live, time, ops);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Run::Impl::liveAdvance(long k, bool *ended) {
  PetscFunctionBeginUser;
  *ended = false;
  if (!live.enabled() || k >= steps) PetscFunctionReturn(PETSC_SUCCESS);
  const double dt = dtRec;
  live.pace(k * dt);
  LiveInput::End end = LiveInput::End::None;
  const double need = (k + 1) * dt; // the next step's end: the rows that hold during it are in
  if (!live.covers(need)) {
    PetscCall(live.waitFor(need, &end, [&]() -> PetscErrorCode {
      PetscFunctionBeginUser;
      PetscCall(flushMonitors()); // what the run knows is on disk while it waits
      if (!quiet)
        PetscCall(PetscPrintf(comm, "  t = %8.3f s: waiting for the live file (it reaches %.6g s)\n", k * dt,
                              live.knownUntil()));
      PetscFunctionReturn(PETSC_SUCCESS);
    }));
  } else if (k % 16 == 0) // a signal is looked for every few steps while the run catches up
    PetscCall(live.interrupted(&end));
  if (end == LiveInput::End::None) PetscFunctionReturn(PETSC_SUCCESS);
  *ended = true;
  steps = k;
  if (!quiet)
    PetscCall(PetscPrintf(comm, "Live run stopped at t = %g s (step %ld): %s; continue it with -restart %s\n", k * dt, k,
                          end == LiveInput::End::Signal ? "a signal (SIGINT or SIGTERM)"
                                                        : "the stop file, once the rows before it were followed",
                          checkpointFile.c_str()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
