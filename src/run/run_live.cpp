// A live run (rcfd run -live FILE, docs/live.md): the measured conditions of
// src/run/live_input reach what a schedule drives -- the switching rule's u_sup
// (switching and blending), the conditions the monitors see (bottom-layer u_mf
// and the de-fluidization warning) -- and the granulator's rates.  A row
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
  const std::string pipeline = " (-pipeline " + pipelineSpec + " has none)";
  PetscCheck((!live.has(LiveInput::FeedRate) && !live.has(LiveInput::FeedShare)) ||
               findOperator<FeedOperator>(ops), comm, PETSC_ERR_USER_INPUT,
             "%sthe feed columns need the feed operator in -pipeline%s", file.c_str(), pipeline.c_str());
  PetscCheck(!live.has(LiveInput::DischargeRate) || findOperator<DischargeOperator>(ops), comm,
             PETSC_ERR_USER_INPUT, "%sthe column discharge_rate needs the discharge operator in -pipeline%s",
             file.c_str(), pipeline.c_str());
  PetscCheck(!live.has(LiveInput::GrowthRate) || findOperator<GrowthOperator>(ops), comm, PETSC_ERR_USER_INPUT,
             "%sthe column growth_rate needs the growth operator in -pipeline%s", file.c_str(), pipeline.c_str());
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
  if (auto *feed = findOperator<FeedOperator>(ops)) {
    const bool rate = live.has(LiveInput::FeedRate), shares = live.has(LiveInput::FeedShare);
    if (rate || shares) {
      std::vector<double> w = feed->feedShares();
      if (shares)
        for (std::size_t i = 0; i < w.size(); ++i) w[i] = live.at(LiveInput::FeedShare, time, static_cast<int>(i));
      feed->setFeed(rate ? live.at(LiveInput::FeedRate, time) : feed->feedRate(), w);
    }
  }
  if (auto *discharge = findOperator<DischargeOperator>(ops))
    if (live.has(LiveInput::DischargeRate)) discharge->setRate(live.at(LiveInput::DischargeRate, time));
  if (auto *growth = findOperator<GrowthOperator>(ops))
    if (live.has(LiveInput::GrowthRate))
      growth->setRate(live.at(LiveInput::GrowthRate, time), growth->transferFraction());
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
