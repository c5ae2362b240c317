#include "markov/markov_monitor.hpp"
#include "base/atomic_file.hpp"
#include "base/checked_options.hpp"
#include "base/collective.hpp"
#include "base/petsc_compat.hpp"

#include "markov/chain_files.hpp"
#include "markov/drift_matrices.hpp"
#include "markov/frame_chain.hpp"

#include <algorithm>
#include <sstream>

namespace rcfd {

PetscErrorCode MarkovMonitor::setFromOptions(MPI_Comm comm) {
  const char *backgrounds[] = {"mean", "stationary"};
  PetscInt background = stationaryBackground_ ? 1 : 0, iterations = background_.iterations;
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, prefix.c_str(), "The run's zones from its database as the solid's Markov chain", "rcfd");
  PetscCall(checkedInt(PetscOptionsObject, "-departures", "Frames whose zone crossings are followed (spread evenly)",
                       &departures_, 1, 1000000));
  PetscCall(checkedReal(PetscOptionsObject, "-passage_horizon", "Longest time a crossing is followed [s]",
                        &passages_.horizon, kChainTime));
  PetscCall(checkedReal(PetscOptionsObject, "-passage_tail", "Stop following a crossing when less than this is left",
                        &passages_.tail, kOpenUnit));
  PetscCall(PetscOptionsEList("-class_background",
                              "With several size classes: the bed each class's drift is linearised on: mean or "
                              "stationary (the composition the classes' own period chains give, iterated)",
                              "", backgrounds, 2, backgrounds[background], &background, nullptr));
  PetscCall(checkedInt(PetscOptionsObject, "-class_background_iterations",
                       "With the stationary background: at most this many iterations", &iterations, 1, 100));
  PetscCall(checkedReal(PetscOptionsObject, "-class_background_tolerance",
                        "With the stationary background: stop when no class's centre moves more than this [m]",
                        &background_.tolerance, kPositive));
  PetscOptionsEnd();
  stationaryBackground_ = background == 1;
  background_.iterations = static_cast<int>(iterations);
  if (stationaryBackground_) PetscCall(solver_.setFromOptions(comm, prefix.c_str()));
  // The run's own zones, drift and carry: the chain is the run's.
  PetscCall(zones_.setFromOptions(comm));
  PetscCall(drift_.setFromOptions(comm));
  PetscCall(carry_.setFromOptions(comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode MarkovMonitor::setUp(const RunContext &run, const FractionState &, const std::string &outputDirectory) {
  const Database &db = run.db;
  const MPI_Comm comm = db.layout().comm();
  PetscFunctionBeginUser;
  if (done_ == db.identity()) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCheck(!zones_.all().empty(), comm, PETSC_ERR_USER_INPUT,
             "-monitors markov needs zones: give -zones NAME,... and each zone's shape (docs/markov.md)");
  PetscCall(zones_.setUp(db.mesh(), db.layout(), db.metadata().gravity));
  FrameChain chain;
  PetscCall(chain.setUp(db));
  PetscCall(carry_.setUp(chain, run.solidDensity));
  const bool classes = run.fractions.size() > 1;
  if (classes) PetscCall(drift_.setUp(chain, run.fractions, run.solidDensity));
  passages_.departures = evenFrames(chain.numFrames(), static_cast<int>(departures_));
  std::vector<const Zone *> list;
  for (const Zone &z : zones_.all()) list.push_back(&z);
  // The bulk's chain, then each class's (its drift first, then the carry at the wrap).
  std::vector<std::pair<std::string, std::vector<ZonePassages>>> chains(1);
  chains[0].first = "bulk";
  PetscCall(zonePassages(chain, list, passages_, &chains[0].second, {&carry_}));
  if (classes && stationaryBackground_ && drift_.moves()) { // the bed as the classes' chains say, as rcfd markov finds it
    ChainSpectrum spectrum;
    PetscCall(solver_.solve(chain, FrameChain::Average::Mass, 1e-3, &spectrum));
    PeriodChain period;
    PetscCall(period.setUp(chain, spectrum.absorbingLocal));
    BackgroundIterations found;
    PetscCall(findBackground(chain, period, solver_, drift_, run.fractions, true, &carry_, background_, &found));
  }
  for (int i = 0; classes && i < run.fractions.size(); ++i) {
    chains.emplace_back(run.fractions.label(i), std::vector<ZonePassages>());
    DriftMatrices matrices;
    std::vector<ChainStep *> steps;
    // As rcfd markov takes them: the drift read off once per frame as
    // matrices (unless -drift_every), then the carry.
    PetscCall(classSteps(chain, drift_, i, true, &carry_, &matrices, &steps));
    PetscCall(zonePassages(chain, list, passages_, &chains.back().second, steps));
  }
  const std::string dir = outputDirectory + "/";
  const double dt = chain.dt();
  const size_t departures = passages_.departures.size();
  PetscMPIInt rank;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  written_.clear();
  PetscCall(collectively(comm, [&] {
    std::ostringstream table;
    table << "# the run's database " << db.path() << " as the solid's Markov chain (docs/markov.md): per chain (the "
          << "bulk, each size class with the drift linearised on the mean composition) and zone, from " << departures
          << " departure frames, the wrap carried; kac_share = E[visit] / (E[visit] + E[away])\n"
          << "chain,zone,database_share,mean_residence,mean_away,kac_share,residence_tail,away_tail,conservation\n";
    for (const auto &[name, zones] : chains)
      for (const ZonePassages &p : zones) {
        const std::string file = "markov_zone_" + p.zone + (name == "bulk" ? "" : "_" + name) + ".csv";
        written_.push_back(file);
        table << name << ',' << p.zone << ',' << chainNumber(p.databaseShare) << ',' << chainNumber(p.residence.mean)
              << ',' << chainNumber(p.away.mean) << ',' << chainNumber(kacShare(p)) << ','
              << chainNumber(p.residence.tail) << ',' << chainNumber(p.away.tail) << ','
              << chainNumber(std::max(p.residence.conservation, p.away.conservation)) << '\n';
        if (rank == 0)
          writeTextAtomically(dir + file, zoneFileText(p, name == "bulk" ? "" : ", size class " + name, departures, dt));
      }
    if (rank == 0) writeTextAtomically(dir + "markov.csv", table.str());
  }));
  done_ = db.identity();
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode MarkovMonitor::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer, "monitor markov: %zu zone(s), %d departure frames, horizon %g s; wrote markov.csv and %zu distribution(s)\n",
                                   zones_.all().size(), static_cast<int>(departures_), passages_.horizon, written_.size()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
