// rcfd markov DB.h5: what the frames say as the solid's Markov chain, without
// a run (docs/markov.md): the averaged chain's stationary distribution against
// the database's mean mass share, its second eigenvalue and relaxation time
// (with -markov_spectrum period also the chain over one period of the frames,
// its stationary distribution at frame 0 against frame 0's, per size class too),
// the tracer mixing time from the frames, and for named zones the time per
// visit and the time away between visits; with size classes and a drift law,
// the mixing and the zones of each class's chain.
#include "cli/commands.hpp"
#include "base/petsc_compat.hpp"

#include "cli/figures.hpp"
#include "markov/chain_files.hpp"
#include "markov/class_background.hpp"
#include "markov/class_drift.hpp"
#include "markov/drift_matrices.hpp"
#include "markov/frame_chain.hpp"
#include "markov/pass_counts.hpp"
#include "markov/period_chain.hpp"
#include "markov/spectrum.hpp"
#include "markov/tracer_mixing.hpp"
#include "markov/wrap_carry.hpp"
#include "markov/zone_passages.hpp"
#include "rcfd/zone.hpp"
#include "base/atomic_file.hpp"
#include "base/checked_options.hpp"
#include "base/collective.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sstream>

namespace rcfd::cli {
namespace {

struct MarkovOptions {
  std::string file, directory;
  FrameChain::Average average = FrameChain::Average::Mass;
  double alphaMeanMin = 1e-3;
  MixingSettings mixing;
  bool allStarts = false, mix = true;
  PetscInt stride = 4;
  PassageSettings passages;
  PetscInt departures = 16;
  PassCountSettings passCounts; // time 0: not computed
  bool quiet = false, plot = true;
  bool classes = false; // -fractions_diameters given: every class's chain too
  bool carryWrap = false; // -markov_wrap carry
  bool period = false;    // -markov_spectrum period: the period chain too
  bool driftMatrices = true; // -markov_class_drift matrix: each class's drift as a matrix per frame
  bool segregatedBackground = false; // -markov_class_background stationary: the bed as the classes' chains say
  BackgroundSettings background;
  std::string mixZone;    // -markov_mix_zone: a tracer started in that zone too
  double solidDensity = 0.0; // 0: the database's
};

PetscErrorCode readOptions(MPI_Comm comm, const char *positional, MarkovOptions *o) {
  char text[PETSC_MAX_PATH_LEN] = "", dir[PETSC_MAX_PATH_LEN] = "";
  const char *averages[] = {"mass", "plain"};
  const char *startKinds[] = {"layers", "all"};
  const char *wraps[] = {"periodic", "carry"};
  const char *spectra[] = {"average", "period"};
  const char *classDrifts[] = {"matrix", "operator"};
  const char *backgrounds[] = {"mean", "stationary"};
  PetscInt average = 0, starts = 0, wrap = 0, spectrum = 0, classDrift = 0, background = 0;
  PetscBool mix = PETSC_TRUE, quiet = PETSC_FALSE, plot = figuresByDefault() ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, nullptr, "rcfd markov: the database's frames as the solid's Markov chain", "rcfd");
  PetscCall(PetscOptionsString("-db", "Database file (or give it as the first argument)", "", "", text, sizeof text,
                               nullptr));
  PetscCall(PetscOptionsString("-o", "Output folder (default: the database's name with -markov)", "", "", dir,
                               sizeof dir, nullptr));
  PetscCall(PetscOptionsEList("-markov_average",
                              "Average chain: mass (mean mass flux over mean mass) or plain (mean of the matrices)",
                              "", averages, 2, averages[average], &average, nullptr));
  PetscCall(PetscOptionsEList("-markov_spectrum",
                              "Spectrum: average (the time-averaged chain) or period (also the product of the frames "
                              "over one period, and with size classes each class's)",
                              "", spectra, 2, spectra[spectrum], &spectrum, nullptr));
  PetscCall(checkedReal(PetscOptionsObject, "-markov_alpha_mean_min",
                        "States of the averaged chain: cells whose mean alpha_s is at least this", &o->alphaMeanMin,
                        kNonNegative));
  PetscCall(PetscOptionsBool("-markov_mix", "Compute the tracer mixing time", "", mix, &mix, nullptr));
  PetscCall(checkedReal(PetscOptionsObject, "-markov_mix_tolerance",
                        "Mixed: every counted cell's tracer concentration within this of the mean", &o->mixing.tolerance,
                        kOpenUnit));
  PetscCall(checkedReal(PetscOptionsObject, "-markov_mix_alpha_min",
                        "Cells counted for mixing (and tracer starts): alpha_s at least this", &o->mixing.alphaMin,
                        kOpenUnit));
  PetscCall(checkedReal(PetscOptionsObject, "-markov_mix_horizon", "Longest tracer propagation [s]",
                        &o->mixing.horizon, kChainTime));
  PetscCall(PetscOptionsEList("-markov_mix_starts",
                              "Tracer start cells: layers (the centre of every -markov_mix_stride-th layer holding solid) or all", "",
                              startKinds, 2, startKinds[starts], &starts, nullptr));
  PetscCall(checkedInt(PetscOptionsObject, "-markov_mix_stride",
                       "With -markov_mix_starts layers: every this many layers from the bottom", &o->stride, 1, 1000000));
  char mixZone[256] = "";
  PetscCall(PetscOptionsString("-markov_mix_zone",
                               "Also a tracer started as the solid in this zone of -zones at frame 0 (as a run's "
                               "-scalar_NAME_zones)", "", mixZone, mixZone, sizeof mixZone, nullptr));
  o->mixZone = mixZone;
  PetscCall(checkedInt(PetscOptionsObject, "-markov_departures",
                       "Frames whose zone crossings are followed (spread evenly)", &o->departures, 1, 1000000));
  PetscCall(checkedReal(PetscOptionsObject, "-markov_passage_horizon", "Longest time a crossing is followed [s]",
                        &o->passages.horizon, kChainTime));
  PetscCall(checkedReal(PetscOptionsObject, "-markov_passage_tail",
                        "Stop following a crossing when less than this is left", &o->passages.tail, kOpenUnit));
  PetscReal passTime = 0.0;
  PetscInt maxPasses = 20;
  PetscCall(checkedReal(PetscOptionsObject, "-markov_passes_time",
                        "Distribution of the number of entries into each zone within this time [s] (0: not computed)",
                        &passTime, ValueRange{0.0, kChainTime.high, true, true, "a time from 0 to 3600 s"}));
  PetscCall(checkedInt(PetscOptionsObject, "-markov_passes_max",
                       "With -markov_passes_time: the last count holds this many entries or more", &maxPasses, 1, 1000));
  o->passCounts.time = passTime;
  o->passCounts.maxPasses = static_cast<int>(maxPasses);
  PetscCall(PetscOptionsEList("-markov_wrap",
                              "The step from the last frame to the first: periodic (as if the bed at the end were the "
                              "bed at the start) or carry (onto frame 0's bed as a run carries its state, -carry_type)",
                              "", wraps, 2, wraps[wrap], &wrap, nullptr));
  PetscCall(PetscOptionsEList("-markov_class_drift",
                              "With -fractions_diameters: each class's drift step as a matrix per frame, read off the "
                              "drift once (matrix), or the drift operator at every step (operator; the same numbers, slower)",
                              "", classDrifts, 2, classDrifts[classDrift], &classDrift, nullptr));
  PetscCall(PetscOptionsEList("-markov_class_background",
                              "With -fractions_diameters: the bed each class's drift is linearised on: mean (the "
                              "inventory's composition in every cell) or stationary (the composition the classes' own "
                              "period chains give, iterated to a fixed point)",
                              "", backgrounds, 2, backgrounds[background], &background, nullptr));
  PetscInt iterations = o->background.iterations;
  PetscCall(checkedInt(PetscOptionsObject, "-markov_class_background_iterations",
                       "With -markov_class_background stationary: at most this many iterations", &iterations, 1, 100));
  o->background.iterations = static_cast<int>(iterations);
  PetscCall(checkedReal(PetscOptionsObject, "-markov_class_background_tolerance",
                        "With -markov_class_background stationary: stop when no class's centre moves more than this [m]",
                        &o->background.tolerance, kPositive));
  PetscCall(checkedReal(PetscOptionsObject, "-solid_density",
                        "With -fractions_diameters: particle density for the drift [kg/m^3] (default: the database's)",
                        &o->solidDensity, {0.0, 1e6, false, true, "a positive density in kg/m^3"}));
  PetscCall(PetscOptionsBool("-quiet", "No report", "", quiet, &quiet, nullptr));
  PetscCall(PetscOptionsBool("-plot", "Draw the figures (default: $RCFD_PLOT, else true)", "", plot, &plot, nullptr));
  PetscOptionsEnd();
  o->file = positional ? positional : text;
  o->average = static_cast<FrameChain::Average>(average);
  o->allStarts = starts == 1;
  o->mix = mix;
  o->quiet = quiet;
  o->plot = plot;
  o->directory = *dir ? dir : o->file.substr(0, o->file.rfind('.')) + "-markov";
  PetscBool classes = PETSC_FALSE;
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-fractions_diameters", &classes));
  o->classes = classes;
  o->carryWrap = wrap == 1;
  o->period = spectrum == 1;
  o->driftMatrices = classDrift == 0;
  o->segregatedBackground = background == 1;
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::string number(double v) { return chainNumber(v); }

// A zone's distributions as zone_NAME[SUFFIX].csv (rank 0).
void writeZone(const std::string &dir, const ZonePassages &p, const std::string &suffix, const std::string &what,
               size_t departures, double dt) {
  writeTextAtomically(dir + "zone_" + p.zone + suffix + ".csv", zoneFileText(p, what, departures, dt));
}

// passes_ZONE[SUFFIX].csv: the distribution of the number of entries.
void writePasses(const std::string &dir, const PassCounts &c, const std::string &suffix, const std::string &what,
                 size_t departures, double dt) {
  std::ostringstream z;
  z << "# zone " << c.zone << what << ": probability of j entries into the zone within " << c.steps * dt
    << " s (the last row: that many or more), from the pass-counter chain, " << departures
    << " departure frames\npasses,probability\n";
  for (size_t j = 0; j < c.probability.size(); ++j) z << j << ',' << number(c.probability[j]) << '\n';
  writeTextAtomically(dir + "passes_" + c.zone + suffix + ".csv", z.str());
}

// One size class's answers (its chain: the shift and its linearised drift).
struct ClassAnswers {
  MixingResult mixing;
  double zoneMixTime = std::nan(""); // of the tracer started in -markov_mix_zone
  std::vector<ZonePassages> zones;
  std::vector<PassCounts> counts; // with -markov_passes_time
  int reach = 0;                  // the drift as matrices: the most faces a step crosses (0: the operator steps)
  double matrixSeconds = 0.0;     // and the time they took to read off
  PeriodNumbers period;                 // with -markov_spectrum period
  std::vector<double> periodStationary; // its distribution at frame 0, all cells (rank 0)
};

} // namespace

PetscErrorCode markovCommand(MPI_Comm comm, const char *positional) {
  MarkovOptions o;
  DatabaseLoadOptions loadOptions;
  ZoneSet zones;
  ChainEigensolver solver;
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(readOptions(comm, positional, &o));
  PetscCall(Database::optionsFromCommandLine(&loadOptions));
  PetscCall(zones.setFromOptions(comm));
  PetscCall(solver.setFromOptions(comm, "markov_"));
  FractionSet fractions;
  ClassDrift classDrift;
  WrapCarry wrapCarry;
  if (o.carryWrap) PetscCall(wrapCarry.setFromOptions(comm));
  if (o.classes) {
    PetscCall(FractionSet::fromOptions(comm, &fractions));
    PetscCall(classDrift.setFromOptions(comm));
  }
  if (helpRequested()) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(rejectUnusedOptions(comm, "markov"));
  PetscCheck(!o.file.empty(), comm, PETSC_ERR_USER_INPUT, "No database given: rcfd markov FILE");

  const double t0 = MPI_Wtime();
  std::unique_ptr<Database> db;
  PetscCall(Database::load(comm, o.file, loadOptions, &db));
  PetscCall(zones.setUp(db->mesh(), db->layout(), db->metadata().gravity));
  PetscCheck(o.mixZone.empty() || zones.find(o.mixZone), comm, PETSC_ERR_USER_INPUT,
             "-markov_mix_zone %s is none of -zones", o.mixZone.c_str());
  const double tLoad = MPI_Wtime();
  FrameChain chain;
  PetscCall(chain.setUp(*db)); // refuses frames that do not conserve mass, before anything is computed
  const double rho = o.solidDensity > 0 ? o.solidDensity : db->metadata().solidDensity;
  if (o.classes) // the drift refuses what it lacks (e.g. u_sup for -drift_excess_gas) before anything is computed
    PetscCall(classDrift.setUp(chain, fractions, rho));
  // What follows each frame's shift for the bulk: the carry at the wrap (with
  // -markov_wrap carry); a class's drift comes before it (below).
  std::vector<ChainStep *> bulkSteps;
  if (o.carryWrap) {
    PetscCall(wrapCarry.setUp(chain, rho));
    bulkSteps.push_back(&wrapCarry);
  }
  const double tChain = MPI_Wtime();
  ChainSpectrum spectrum;
  PetscCall(solver.solve(chain, o.average, o.alphaMeanMin, &spectrum));
  // The chain over one period (the frames' product with the steps after
  // them, the carry at the wrap included): its stationary distribution at
  // frame 0 against frame 0's share, the exact check of the database.
  const Layout &layout = db->layout();
  PeriodChain periodChain;
  PeriodSpectrum period;
  std::vector<double> periodStationary, share0;
  if (o.period || (o.classes && o.segregatedBackground)) PetscCall(periodChain.setUp(chain, spectrum.absorbingLocal));
  if (o.period) {
    PetscCall(periodChain.solve(solver, bulkSteps, "the period chain", &period));
    PetscCall(layout.gatherToAll(1, period.stationary, &periodStationary));
    PetscCall(layout.gatherToAll(1, chain.massShare(0), &share0));
  }
  const double tSpectrum = MPI_Wtime();

  std::vector<double> stationary, mean, alpha0;
  PetscCall(layout.gatherToAll(1, spectrum.stationary, &stationary));
  PetscCall(layout.gatherToAll(1, chain.meanShare(), &mean));
  PetscCall(layout.gatherToAll(1, db->alphaS(0), &alpha0));

  MixingResult mixing;
  double zoneMixTime = std::nan("");
  if (o.mix) {
    o.mixing.starts = mixingStarts(db->mesh(), db->metadata().gravity, alpha0, o.mixing.alphaMin, o.allStarts,
                                   static_cast<int>(o.stride));
    o.mixing.excluded = spectrum.absorbingLocal;
    if (!o.mixZone.empty()) {
      o.mixing.startZone = zones.find(o.mixZone)->localCells(); // found: checked after the load
      o.mixing.zoneStart = true;
    }
    PetscCall(tracerMixing(chain, o.mixing, &mixing, bulkSteps));
    if (o.mixing.zoneStart) { // the zone's tracer, apart from the cells'
      zoneMixTime = mixing.time.back();
      mixing.time.pop_back();
    }
  }
  const double tMixing = MPI_Wtime();

  std::vector<const Zone *> zoneList;
  for (const Zone &z : zones.all()) zoneList.push_back(&z);
  o.passages.departures = evenFrames(chain.numFrames(), static_cast<int>(o.departures));
  std::vector<ZonePassages> passages;
  PetscCall(zonePassages(chain, zoneList, o.passages, &passages, bulkSteps));
  for (size_t z = 0; z < passages.size(); ++z)
    for (PetscInt i : zoneList[z]->localCells()) passages[z].stationaryShare += stationary[layout.naturalCell(layout.rowStart() + i)];
  for (ZonePassages &p : passages)
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &p.stationaryShare, 1, MPI_DOUBLE, MPI_SUM, comm));
  std::vector<PassCounts> counts;
  if (o.passCounts.time > 0) {
    o.passCounts.departures = o.passages.departures;
    PetscCall(passCounts(chain, zoneList, o.passCounts, &counts, bulkSteps));
  }
  const double tZones = MPI_Wtime();

  // A class's steps after the shift: its drift (read off once as a matrix per
  // frame, unless -drift_every or -markov_class_drift operator says
  // otherwise), then the carry at the wrap.
  ChainStep *const afterDrift = o.carryWrap ? &wrapCarry : nullptr;

  // -markov_class_background stationary: the bed the classes' drift is
  // linearised on, from the classes' own period chains, iterated
  // (markov/class_background.hpp).
  BackgroundIterations background;
  if (o.classes && o.segregatedBackground && classDrift.moves())
    PetscCall(findBackground(chain, periodChain, solver, classDrift, fractions, o.driftMatrices, afterDrift, o.background,
                             &background));
  const double tBackground = MPI_Wtime();

  // Each size class's chain: the frame's shift, then the class's drift
  // linearised on the bed (markov/class_drift.hpp): the mean composition, or
  // with -markov_class_background stationary the one just found.
  std::vector<ClassAnswers> classes;
  if (o.classes) {
    for (int i = 0; i < fractions.size(); ++i) {
      ClassAnswers a;
      if (!classDrift.moves()) { // no drift (k_d = 0, one class): every class's chain is the bulk's, to the bit
        a.mixing = mixing;
        a.zoneMixTime = zoneMixTime;
        a.zones = passages;
        a.counts = counts;
        a.period = period;
        a.periodStationary = periodStationary;
        classes.push_back(std::move(a));
        continue;
      }
      DriftMatrices matrices;
      std::vector<ChainStep *> classSteps;
      const double start = MPI_Wtime();
      PetscCall(rcfd::classSteps(chain, classDrift, i, o.driftMatrices, afterDrift, &matrices, &classSteps));
      a.reach = matrices.reach();
      a.matrixSeconds = MPI_Wtime() - start;
      if (o.period) { // the class's chain over one period: where the class lives at frame 0
        PeriodSpectrum p;
        const std::string what = "the period chain of size class " + fractions.label(i);
        PetscCall(periodChain.solve(solver, classSteps, what.c_str(), &p));
        a.period = p;
        PetscCall(layout.gatherToAll(1, p.stationary, &a.periodStationary));
      }
      if (o.mix) PetscCall(tracerMixing(chain, o.mixing, &a.mixing, classSteps));
      if (o.mix && o.mixing.zoneStart) {
        a.zoneMixTime = a.mixing.time.back();
        a.mixing.time.pop_back();
      }
      PetscCall(zonePassages(chain, zoneList, o.passages, &a.zones, classSteps));
      if (o.passCounts.time > 0) PetscCall(passCounts(chain, zoneList, o.passCounts, &a.counts, classSteps));
      classes.push_back(std::move(a));
    }
  }
  const double tClasses = MPI_Wtime();

  // Mixing summary over the starts.
  struct MixingSummary {
    double mean = 0.0, worst = 0.0;
    int mixed = 0;
    bool all = false;
  };
  auto summarise = [](const MixingResult &m) {
    MixingSummary r;
    for (double t : m.time)
      if (!std::isnan(t)) r.mean += t, ++r.mixed, r.worst = std::max(r.worst, t);
    if (r.mixed) r.mean /= r.mixed;
    r.all = r.mixed == static_cast<int>(m.time.size());
    return r;
  };
  const MixingSummary bulkMixing = summarise(mixing);
  const double mixMean = bulkMixing.mean, mixWorst = bulkMixing.worst;
  const int mixed = bulkMixing.mixed;
  const bool allMixed = bulkMixing.all;
  const double dt = chain.dt();

  const std::string dir = o.directory + "/";
  PetscCall(collectively(comm, [&] {
    if (rank != 0) return;
    std::filesystem::create_directories(o.directory);
    const Mesh &mesh = db->mesh();
    std::ostringstream s;
    s << "# rcfd markov " << o.file << ": the averaged chain (" << averageName(o.average)
      << ") stationary share against the database's mean mass share, per cell"
      << (o.period ? "; the period chain's stationary share at frame 0 (bulk, and each size class's) against "
                     "frame 0's mass share"
                   : "")
      << "\ncell,x,y,z,stationary_share,mean_share";
    if (o.period) {
      s << ",period_stationary_share,frame0_share";
      for (int i = 0; i < static_cast<int>(classes.size()); ++i) s << ",period_stationary_" << fractions.label(i);
    }
    s << '\n';
    for (int c = 0; c < mesh.numCells(); ++c) {
      s << c << ',' << number(mesh.cellCentre[c][0]) << ',' << number(mesh.cellCentre[c][1]) << ','
        << number(mesh.cellCentre[c][2]) << ',' << number(stationary[c]) << ',' << number(mean[c]);
      if (o.period) {
        s << ',' << number(periodStationary[c]) << ',' << number(share0[c]);
        for (const ClassAnswers &a : classes) s << ',' << number(a.periodStationary[static_cast<size_t>(c)]);
      }
      s << '\n';
    }
    writeTextAtomically(dir + "stationary.csv", s.str());
    if (o.mix) {
      std::ostringstream r;
      r << "# tracer deviation max_i |c_i - 1| over cells with alpha_s >= " << o.mixing.alphaMin << ", over "
        << mixing.time.size() << " start cells; lambda2_decay = |lambda2|^n of the averaged chain\n"
        << "time,mean_deviation,worst_deviation,lambda2_decay" << (o.mixing.zoneStart ? ",zone_deviation" : "") << '\n';
      for (size_t n = 0; n < mixing.meanDeviation.size(); ++n) {
        r << number((n + 1) * dt) << ',' << number(mixing.meanDeviation[n]) << ',' << number(mixing.worstDeviation[n])
          << ',' << number(std::pow(spectrum.lambda2, static_cast<double>(n + 1)));
        if (o.mixing.zoneStart) r << ',' << (n < mixing.zoneDeviation.size() ? number(mixing.zoneDeviation[n]) : "");
        r << '\n';
      }
      writeTextAtomically(dir + "relaxation.csv", r.str());
      std::ostringstream m;
      m << "# mixing time per start cell (empty: not mixed within " << o.mixing.horizon << " s)\ncell,x,y,z,mixing_time\n";
      for (size_t c = 0; c < mixing.time.size(); ++c) {
        const int cell = o.mixing.starts[c];
        m << cell << ',' << number(mesh.cellCentre[cell][0]) << ',' << number(mesh.cellCentre[cell][1]) << ','
          << number(mesh.cellCentre[cell][2]) << ',' << (std::isnan(mixing.time[c]) ? "" : number(mixing.time[c]))
          << '\n';
      }
      if (o.mixing.zoneStart) // the tracer started as the zone's solid
        m << "zone " << o.mixZone << ",,,," << (std::isnan(zoneMixTime) ? "" : number(zoneMixTime)) << '\n';
      writeTextAtomically(dir + "mixing.csv", m.str());
    }
    for (const ZonePassages &p : passages) writeZone(dir, p, "", "", o.passages.departures.size(), dt);
    // Centres of the period chain's stationary distributions at frame 0: the
    // bulk's, frame 0's own and each class's (a segregation straight from the chain).
    const double bulkHeight = o.period ? centreHeight(mesh, db->metadata().gravity, periodStationary) : 0.0;
    std::vector<double> classHeight;
    for (const ClassAnswers &a : classes)
      classHeight.push_back(o.period ? centreHeight(mesh, db->metadata().gravity, a.periodStationary) : 0.0);
    if (!classes.empty()) {
      // Per class: its distributions, and one table of every class's numbers.
      std::ostringstream c;
      c << "# rcfd markov " << o.file << ": each size class's chain (the shift, then its drift linearised on the "
        << "bed's mean composition; docs/markov.md, \"Size classes\"); kac_share = E[visit] / (E[visit] + E[away])\n"
        << "class,diameter,zone,mean_residence,mean_away,kac_share,residence_tail,away_tail,conservation,passes_mean,"
        << "mixing_mean,mixing_worst,mixing_mixed,mixing_starts" << (o.mixing.zoneStart ? ",mixing_zone" : "")
        << ",period_lambda1,period_lambda2_modulus,period_relaxation_time,period_height,period_height_minus_bulk\n";
      for (int i = 0; i < fractions.size(); ++i) {
        const ClassAnswers &a = classes[static_cast<size_t>(i)];
        const MixingSummary m = summarise(a.mixing);
        for (const ZonePassages &p : a.zones)
          writeZone(dir, p, "_" + fractions.label(i), ", size class " + fractions.label(i),
                    o.passages.departures.size(), dt);
        auto row = [&](const std::string &zone, const std::string &numbers) {
          c << fractions.label(i) << ',' << number(fractions.diameter(i)) << ',' << zone << ',' << numbers << ','
            << (o.mix ? number(m.mean) : "") << ',' << (o.mix && m.all ? number(m.worst) : "") << ','
            << (o.mix ? std::to_string(m.mixed) : "") << ',' << (o.mix ? std::to_string(a.mixing.time.size()) : "");
          if (o.mixing.zoneStart) c << ',' << (std::isnan(a.zoneMixTime) ? "" : number(a.zoneMixTime));
          if (o.period)
            c << ',' << number(a.period.lambda1) << ',' << number(a.period.lambda2) << ','
              << number(a.period.relaxationTime) << ',' << number(classHeight[static_cast<size_t>(i)]) << ','
              << number(classHeight[static_cast<size_t>(i)] - bulkHeight);
          else
            c << ",,,,,";
          c << '\n';
        };
        if (a.zones.empty()) row("", ",,,,,,");
        for (size_t z = 0; z < a.zones.size(); ++z) {
          const ZonePassages &p = a.zones[z];
          row(p.zone, number(p.residence.mean) + ',' + number(p.away.mean) + ',' + number(kacShare(p)) + ',' +
                          number(p.residence.tail) + ',' + number(p.away.tail) + ',' +
                          number(std::max(p.residence.conservation, p.away.conservation)) + ',' +
                          (z < a.counts.size() ? number(a.counts[z].mean) : ""));
        }
        for (const PassCounts &p : a.counts)
          writePasses(dir, p, "_" + fractions.label(i), ", size class " + fractions.label(i),
                      o.passages.departures.size(), dt);
      }
      writeTextAtomically(dir + "classes.csv", c.str());
    }
    for (const PassCounts &c : counts) writePasses(dir, c, "", "", o.passages.departures.size(), dt);
    std::ostringstream sum;
    sum << "# rcfd markov " << o.file << " (docs/markov.md)\nquantity,value\n"
        << "frames," << chain.numFrames() << "\ndt_rec," << number(dt) << "\nchain_cells," << spectrum.cells
        << "\naverage," << averageName(o.average) << "\nlargest_column_error," << number(chain.columnError())
        << "\nlambda1," << number(spectrum.lambda1) << "\nlambda2_modulus," << number(spectrum.lambda2)
        << "\nlambda2_re," << number(spectrum.lambda2Re) << "\nlambda2_im," << number(spectrum.lambda2Im)
        << "\nrelaxation_time," << number(spectrum.relaxationTime) << "\nstationary_l1," << number(spectrum.l1)
        << "\nstationary_max," << number(spectrum.max) << "\nmean_share_residual," << number(spectrum.residual)
        << "\nstates_left_out_share," << number(spectrum.leftOut) << "\nabsorbing_cells," << spectrum.absorbing
        << "\nabsorbing_share," << number(spectrum.absorbingShare) << '\n';
    if (o.carryWrap) sum << "wrap,carry " << wrapCarry.kind() << '\n'; // (periodic when absent)
    if (o.period) {
      sum << "period_states," << period.states << "\nperiod_absorbing_cells," << period.absorbing
          << "\nperiod_left_out_share," << number(period.leftOut)
          << "\nperiod_residual," << number(period.residual) << "\nperiod_lambda1," << number(period.lambda1)
          << "\nperiod_lambda2_modulus," << number(period.lambda2) << "\nperiod_lambda2_re,"
          << number(period.lambda2Re) << "\nperiod_lambda2_im," << number(period.lambda2Im)
          << "\nperiod_relaxation_time," << number(period.relaxationTime) << "\nperiod_stationary_l1,"
          << number(period.l1) << "\nperiod_stationary_max," << number(period.max) << "\nperiod_restarts,"
          << period.iterations << "\nperiod_products," << period.products << "\nperiod_seconds,"
          << number(period.seconds) << "\nperiod_height," << number(bulkHeight) << "\nframe0_height,"
          << number(centreHeight(mesh, db->metadata().gravity, share0)) << '\n';
      for (int i = 0; i < static_cast<int>(classes.size()); ++i) {
        const PeriodNumbers &p = classes[static_cast<size_t>(i)].period;
        const std::string q = "class_" + fractions.label(i) + "_period_";
        sum << q << "states," << p.states << '\n' << q << "lambda1," << number(p.lambda1) << '\n' << q << "lambda2_modulus," << number(p.lambda2) << '\n'
            << q << "relaxation_time," << number(p.relaxationTime) << '\n' << q << "height,"
            << number(classHeight[static_cast<size_t>(i)]) << '\n' << q << "restarts," << p.iterations << '\n'
            << q << "products," << p.products << '\n' << q << "seconds," << number(p.seconds) << '\n';
      }
    }
    if (o.mix)
      sum << "mixing_starts," << mixing.time.size() << "\nmixing_mixed," << mixed << "\nmixing_mean,"
          << number(mixMean) << "\nmixing_worst," << (allMixed ? number(mixWorst) : "") << '\n';
    if (o.mix && o.mixing.zoneStart)
      sum << "mixing_zone_" << o.mixZone << ',' << (std::isnan(zoneMixTime) ? "" : number(zoneMixTime)) << '\n';
    for (const ZonePassages &p : passages)
      sum << "zone_" << p.zone << "_stationary_share," << number(p.stationaryShare) << "\nzone_" << p.zone
          << "_database_share," << number(p.databaseShare) << "\nzone_" << p.zone << "_mean_residence,"
          << number(p.residence.mean) << "\nzone_" << p.zone << "_mean_away," << number(p.away.mean) << "\nzone_"
          << p.zone << "_residence_tail," << number(p.residence.tail) << "\nzone_" << p.zone << "_away_tail,"
          << number(p.away.tail) << "\nzone_" << p.zone << "_conservation,"
          << number(std::max(p.residence.conservation, p.away.conservation)) << '\n';
    for (const PassCounts &c : counts)
      sum << "zone_" << c.zone << "_passes_time," << number(c.steps * dt) << "\nzone_" << c.zone << "_passes_mean,"
          << number(c.mean) << "\nzone_" << c.zone << "_passes_none," << number(c.probability[0]) << "\nzone_"
          << c.zone << "_passes_conservation," << number(c.conservation) << '\n';
    if (!background.centres.empty()) {
      sum << "background_iterations," << background.centres.size() << "\nbackground_last_change,"
          << number(background.lastChange) << '\n';
      std::ostringstream b;
      b << "# rcfd markov " << o.file << ": -markov_class_background stationary; each row the centre height [m] of "
        << "each class's period stationary distribution at frame 0 with the drift linearised on the background the "
        << "row before gave (row 0: the mean composition)\niteration";
      for (int i = 0; i < fractions.size(); ++i) b << ",centre_" << fractions.label(i);
      b << '\n';
      for (size_t it = 0; it < background.centres.size(); ++it) {
        b << it;
        for (double h : background.centres[it]) b << ',' << number(h);
        b << '\n';
      }
      writeTextAtomically(dir + "background.csv", b.str());
    }
    writeTextAtomically(dir + "summary.csv", sum.str());
  }));
  if (o.mix && o.plot)
    PetscCall(drawFigure(comm, "markov_relaxation.py",
                         {dir + "relaxation.csv", "-o", dir + "relaxation.png", "--relaxation_time",
                          number(spectrum.relaxationTime), "--tolerance", number(o.mixing.tolerance), "--title",
                          "tracer mixing, " + o.file}));
  if (o.period && o.plot)
    PetscCall(drawFigure(comm, "markov_stationary.py",
                         {dir + "stationary.csv", "-o", dir + "stationary.png", "--title",
                          "period chain at frame 0, " + o.file}));
  for (const PassCounts &c : counts)
    if (o.plot) { // the bulk's entries and each class's beside them
      std::vector<std::string> args{dir + "passes_" + c.zone + ".csv", "-o", dir + "passes_" + c.zone + ".png",
                                    "--title", "entries into zone " + c.zone + " within " + number(c.steps * dt) + " s, " + o.file};
      if (!classes.empty() && classDrift.moves()) {
        args.push_back("--classes");
        for (int i = 0; i < fractions.size(); ++i) args.push_back(dir + "passes_" + c.zone + "_" + fractions.label(i) + ".csv");
      }
      PetscCall(drawFigure(comm, "markov_passes.py", args));
    }
  for (const ZonePassages &p : passages)
    if (o.plot && (!p.residence.probability.empty() || !p.away.probability.empty()))
      PetscCall(drawFigure(comm, "markov_zone.py",
                           {dir + "zone_" + p.zone + ".csv", "-o", dir + "zone_" + p.zone + ".png", "--title",
                            "zone " + p.zone + ", " + o.file}));
  for (int i = 0; i < static_cast<int>(classes.size()); ++i)
    for (const ZonePassages &p : classes[static_cast<size_t>(i)].zones)
      if (o.plot && (!p.residence.probability.empty() || !p.away.probability.empty())) {
        const std::string name = dir + "zone_" + p.zone + "_" + fractions.label(i);
        PetscCall(drawFigure(comm, "markov_zone.py",
                             {name + ".csv", "-o", name + ".png", "--title",
                              "zone " + p.zone + ", size class " + fractions.label(i) + ", " + o.file}));
      }

  if (!o.quiet) {
    if (o.carryWrap)
      PetscCall(PetscPrintf(comm, "  the propagations carry their distributions from the last frame onto frame 0's bed (carry %s)\n",
                            wrapCarry.kind().c_str()));
    PetscCall(PetscPrintf(comm,
                          "Markov chain of %s: %d frames, dt_rec %g s; columns sum to 1 within %.1e; %d of the %d cells "
                          "hold or exchange solid in some frame (the others are left out of the propagations)\n"
                          "  averaged chain (%s): |Q m - m|_1 = %.3e for the mean mass share m\n"
                          "  %d cells keep their solid in every frame they hold some (absorbing; %.2e of the mass)\n"
                          "  on the %d other cells with mean alpha_s >= %g (the rest hold %.2e of the mass): lambda1 = %.10f, "
                          "lambda2 = %.8f%+.8fi, |lambda2| = %.8f, relaxation time %.4g s (SLEPc, %d restarts)\n"
                          "  stationary distribution against the mean mass share: L1 %.3e, max %.3e\n",
                          o.file.c_str(), chain.numFrames(), dt, chain.columnError(),
                          static_cast<int>(chain.numChainCellsGlobal()), db->mesh().numCells(), averageName(o.average),
                          spectrum.residual, spectrum.absorbing, spectrum.absorbingShare, spectrum.cells, o.alphaMeanMin, spectrum.leftOut, spectrum.lambda1,
                          spectrum.lambda2Re, spectrum.lambda2Im, spectrum.lambda2, spectrum.relaxationTime,
                          spectrum.iterations, spectrum.l1, spectrum.max));
    if (o.period)
      PetscCall(PetscPrintf(comm,
                            "  period chain (the %d frames' product%s; %d states: the cells holding solid at frame 0 but %d it "
                            "keeps for ever, %.2e of frame 0's mass): |P m0 - m0|_1 = %.3e for frame 0's share m0; lambda1 = %.10f, "
                            "|lambda2| = %.8f, relaxation time %.4g s; stationary against m0: L1 %.3e, max %.3e "
                            "(SLEPc, %d restarts, %lld products, %.3g s)\n",
                            chain.numFrames(), o.carryWrap ? ", the wrap carried" : "", period.states,
                            period.absorbing, period.leftOut, period.residual, period.lambda1, period.lambda2, period.relaxationTime, period.l1,
                            period.max, period.iterations, period.products, period.seconds));
    if (o.mix) {
      if (allMixed)
        PetscCall(PetscPrintf(comm, "  tracer mixing (within %g in cells with alpha_s >= %g), %zu start cells: mean %.4g s, worst %.4g s\n",
                              o.mixing.tolerance, o.mixing.alphaMin, mixing.time.size(), mixMean, mixWorst));
      else
        PetscCall(PetscPrintf(comm, "  tracer mixing (within %g in cells with alpha_s >= %g): %d of %zu start cells mixed within %g s (mean of those %.4g s)\n",
                              o.mixing.tolerance, o.mixing.alphaMin, mixed, mixing.time.size(), o.mixing.horizon, mixMean));
      if (o.mixing.zoneStart)
        PetscCall(PetscPrintf(comm, "  tracer started as the solid in zone %s: mixed after %.4g s%s\n", o.mixZone.c_str(),
                              zoneMixTime, std::isnan(zoneMixTime) ? " (not within the horizon)" : ""));
    }
    for (const ZonePassages &p : passages)
      if (p.residence.flux == 0 && p.away.flux == 0)
        PetscCall(PetscPrintf(comm, "  zone %s: mass share %.4f (stationary) / %.4f (frames); no solid crosses its boundary during the %zu departure frames\n",
                              p.zone.c_str(), p.stationaryShare, p.databaseShare, o.passages.departures.size()));
      else
      PetscCall(PetscPrintf(comm,
                            "  zone %s: mass share %.4f (stationary) / %.4f (frames); per visit %.4g s (tail %.1e), "
                            "away %.4g s (tail %.1e); Kac: %.4f; absorbed + left = 1 within %.1e\n",
                            p.zone.c_str(), p.stationaryShare, p.databaseShare, p.residence.mean, p.residence.tail,
                            p.away.mean, p.away.tail, kacShare(p),
                            std::max(p.residence.conservation, p.away.conservation)));
    for (const PassCounts &c : counts)
      PetscCall(PetscPrintf(comm, "  zone %s: entries within %g s: mean %.4g, none %.4f, %d or more %.2e; sum 1 within %.1e\n",
                            c.zone.c_str(), c.steps * dt, c.mean, c.probability[0], o.passCounts.maxPasses,
                            c.probability.back(), c.conservation));
    if (!background.centres.empty()) {
      PetscCall(PetscPrintf(comm, "  background of the size classes (-markov_class_background stationary): %zu iteration(s) of "
                                  "the classes' period chains, their centres",
                            background.centres.size()));
      for (size_t i = 0; i < background.centres.back().size(); ++i)
        PetscCall(PetscPrintf(comm, " %s %.4f m (mean composition's %.4f m)", fractions.label(static_cast<int>(i)).c_str(),
                              background.centres.back()[i], background.centres.front()[i]));
      PetscCall(PetscPrintf(comm, "; last change %.2e m%s\n", background.lastChange,
                            background.converged(o.background) ? "" : ", NOT within -markov_class_background_tolerance"));
    }
    for (int i = 0; i < static_cast<int>(classes.size()); ++i) {
      const ClassAnswers &a = classes[static_cast<size_t>(i)];
      const MixingSummary m = summarise(a.mixing);
      PetscCall(PetscPrintf(comm, "  size class %s (drift linearised on the %s", fractions.label(i).c_str(),
                            background.centres.empty() ? "mean composition" : "stationary background"));
      if (a.reach > 0)
        PetscCall(PetscPrintf(comm, ", a matrix per frame reaching %d face%s, %.3g s", a.reach, a.reach > 1 ? "s" : "",
                              a.matrixSeconds));
      PetscCall(PetscPrintf(comm, "):"));
      if (o.period)
        PetscCall(PetscPrintf(comm, " period chain (%d states) lambda1 %.8f, |lambda2| %.8f, relaxation %.4g s (%lld products, %.3g s);",
                              a.period.states, a.period.lambda1, a.period.lambda2, a.period.relaxationTime, a.period.products,
                              a.period.seconds));
      if (o.mix && m.all)
        PetscCall(PetscPrintf(comm, " tracer mixing mean %.4g s, worst %.4g s;", m.mean, m.worst));
      else if (o.mix)
        PetscCall(PetscPrintf(comm, " tracer mixing: %d of %zu starts within %g s (mean of those %.4g s);", m.mixed,
                              a.mixing.time.size(), o.mixing.horizon, m.mean));
      for (const ZonePassages &p : a.zones)
        PetscCall(PetscPrintf(comm, " zone %s per visit %.4g s, away %.4g s, Kac %.4f (absorbed + left = 1 within %.1e);",
                              p.zone.c_str(), p.residence.mean, p.away.mean, kacShare(p),
                              std::max(p.residence.conservation, p.away.conservation)));
      for (const PassCounts &c : a.counts)
        PetscCall(PetscPrintf(comm, " zone %s entries within %g s: mean %.4g;", c.zone.c_str(), c.steps * dt, c.mean));
      PetscCall(PetscPrintf(comm, "\n"));
    }
    char classTime[64] = "";
    if (!background.centres.empty())
      std::snprintf(classTime, sizeof classTime, ", background %.2f, size classes %.2f", tBackground - tZones,
                    tClasses - tBackground);
    else if (!classes.empty())
      std::snprintf(classTime, sizeof classTime, ", size classes %.2f", tClasses - tZones);
    PetscCall(PetscPrintf(comm, "  seconds: load %.2f, chain %.2f, eigenvalues %.2f, mixing %.2f, zones %.2f%s; wrote %s\n",
                          tLoad - t0, tChain - tLoad, tSpectrum - tChain, tMixing - tSpectrum, tZones - tMixing,
                          classTime,
                          o.directory.c_str()));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
