// rcfd reference: what a run on a database built from the same particle
// snapshots should reproduce: centres of gravity per size class over time
// (cog.csv, the same columns as rcfd run writes), and the vertical profiles
// and bottom/top size distributions over an averaging window.
#include "cli/commands.hpp"
#include "base/petsc_compat.hpp"

#include "base/checked_options.hpp"
#include "cli/particle_input.hpp"
#include "analysis/particle_reference.hpp"
#include "analysis/zone_visits.hpp"
#include "mesh/box_mesh.hpp"
#include "base/atomic_file.hpp"
#include "rcfd/layout.hpp"
#include "rcfd/zone.hpp"
#include "base/collective.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <sstream>

namespace rcfd::cli {
namespace {

struct ReferenceOutputs {
  std::string directory = "reference";
  std::vector<double> classes; // m; empty: clustered from the first snapshot
  double windowBegin = -std::numeric_limits<double>::infinity();
  double windowEnd = std::numeric_limits<double>::infinity();
  PetscBool quiet = PETSC_FALSE;
  double passesTime = 0.0; // with -zones: entries within this time [s]; 0: none
  PetscInt passesMax = 20;
};

PetscErrorCode readReferenceOptions(MPI_Comm comm, ReferenceOutputs *o) {
  char dir[PETSC_MAX_PATH_LEN];
  PetscReal window[2] = {0, 0}, classes[64];
  PetscInt nwindow = 2, nclasses = 64;
  PetscBool setWindow = PETSC_FALSE, setClasses = PETSC_FALSE;
  PetscFunctionBeginUser;
  std::snprintf(dir, sizeof dir, "%s", o->directory.c_str());
  PetscOptionsBegin(comm, nullptr, "rcfd reference: segregation observables from particle snapshots",
                    "rcfd");
  PetscCall(PetscOptionsString("-o", "Output directory (cog.csv, profiles.csv, halves.csv)", "", dir,
                               dir, sizeof dir, nullptr));
  PetscCall(checkedRealArray(PetscOptionsObject, "-average_window",
                             "Time window t0,t1 [s] of the profiles and halves (default: all)", window,
                             &nwindow, &setWindow));
  PetscCall(checkedRealArray(PetscOptionsObject, "-classes",
                             "Size class diameters [m] (default: clustered from the first snapshot)", classes,
                             &nclasses, &setClasses));
  PetscCall(PetscOptionsBool("-quiet", "No progress or summary", "", o->quiet, &o->quiet, nullptr));
  PetscCall(checkedReal(PetscOptionsObject, "-passes_time",
                        "With -zones: distribution of the number of entries into each zone within this time [s]",
                        &o->passesTime, kNonNegative));
  PetscCall(checkedInt(PetscOptionsObject, "-passes_max", "With -passes_time: the last count holds this many or more",
                       &o->passesMax, 1, 100000));
  PetscOptionsEnd();
  PetscCheck(!setWindow || (nwindow == 2 && window[0] <= window[1]), comm, PETSC_ERR_USER_INPUT,
             "-average_window takes two times t0,t1 [s] with t0 <= t1");
  o->directory = dir;
  if (setWindow) {
    o->windowBegin = window[0];
    o->windowEnd = window[1];
  }
  if (setClasses) {
    for (PetscInt c = 0; c < nclasses; ++c)
      PetscCheck(classes[c] > 0, comm, PETSC_ERR_USER_INPUT,
                 "-classes: diameter %d is %g, expected a positive length in m", (int)c + 1,
                 (double)classes[c]);
    o->classes.assign(classes, classes + nclasses);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

PetscErrorCode referenceCommand(MPI_Comm comm) {
  ParticleInput in;
  ReferenceOutputs out;
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(readReferenceOptions(comm, &out));
  PetscCall(readParticleInputOptions(comm, &in));
  ZoneSet zones; // -zones: each zone's visits from the particles (docs/markov.md)
  PetscCall(zones.setFromOptions(comm));
  if (helpRequested()) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(rejectUnusedOptions(comm, "reference"));

  PetscCall(collectively(comm, [&] {
    if (rank != 0) return;
    const bool talk = !out.quiet;
    in.resolve();
    const std::vector<std::size_t> sel = in.selected();
    const ParticleBuildOptions read = in.buildOptions();
    ParticleSnapshot snap = readParticleSnapshot(in.files[sel.front()], read.read);

    ReferenceOptions opt;
    opt.axes = read.axes;
    opt.classes.relTol = in.classTolerance;
    opt.classes.diameter = out.classes;
    opt.profileMesh = resolveMesh(in.mesh, snap, opt.axes);
    opt.windowBegin = out.windowBegin;
    opt.windowEnd = out.windowEnd;
    opt.volume = in.volume;
    ParticleReference ref(opt);
    // Zones on the profile mesh (the database's, when the same -mesh_* options
    // are given), vertical axis z pointing up as the axes map makes it.
    std::vector<ZoneVisits> visits;
    if (!zones.all().empty()) {
      if (!opt.profileMesh) throw std::runtime_error("-zones needs a mesh (-mesh_cells or -mesh_cell_size)");
      const Mesh mesh = boxMesh(*opt.profileMesh);
      Layout layout;
      ZoneSet set = zones;
      if (Layout::create(PETSC_COMM_SELF, mesh, &layout) || set.setUp(mesh, layout, Vec3{0.0, 0.0, -1.0}))
        throw std::runtime_error("-zones: the zones do not fit the particles' mesh (see the message above)");
      for (const Zone &z : set.all()) {
        std::vector<char> inside(static_cast<std::size_t>(mesh.numCells()), 0);
        for (PetscInt i : z.localCells()) inside[static_cast<std::size_t>(layout.naturalCell(i))] = 1;
        visits.emplace_back(z.name(), *opt.profileMesh, std::move(inside));
      }
    }
    std::vector<Vec3> position;

    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    auto lastPrint = start;
    for (std::size_t k = 0; k < sel.size(); ++k) {
      if (k > 0) snap = readParticleSnapshot(in.files[sel[k]], read.read);
      ref.add(in.times[sel[k]], snap);
      if (!visits.empty()) {
        position.resize(snap.size());
        for (std::size_t p = 0; p < snap.size(); ++p) position[p] = opt.axes.apply(snap.position[p]);
        for (ZoneVisits &v : visits) v.add(snap.id, position, snap.mass);
      }
      const auto now = Clock::now();
      if (talk && (now - lastPrint > std::chrono::seconds(2) || k + 1 == sel.size())) {
        lastPrint = now;
        std::printf("  snapshot %zu/%zu, %.1f s\n", k + 1, sel.size(),
                    std::chrono::duration<double>(now - start).count());
        std::fflush(stdout);
      }
    }
    std::filesystem::create_directories(out.directory);
    const std::string dir = out.directory + "/";
    ref.writeCogCsv(dir + "cog.csv");
    ref.writeProfilesCsv(dir + "profiles.csv");
    ref.writeHalvesCsv(dir + "halves.csv");
    // Snapshot spacing: a visit of n snapshot intervals lasts n dt.
    const double dt = sel.size() > 1 ? (in.times[sel.back()] - in.times[sel.front()]) / double(sel.size() - 1) : 0.0;
    for (const ZoneVisits &v : visits) {
      const std::vector<double> residence = v.distribution(false), away = v.distribution(true);
      std::ostringstream z;
      z << "# zone " << v.name() << " from the particles of " << in.origin() << " (" << v.snapshots()
        << " snapshots, dt " << dt << " s): probability that a visit lasts t (residence) and that the time "
        << "outside between leaving and entering again is t (away), mass-weighted, corrected for the end of "
        << "the snapshots; complete visits " << v.complete(false) << ", cut " << v.censored(false)
        << "; complete times away " << v.complete(true) << ", cut " << v.censored(true) << "; share of time "
        << "in the zone " << v.share() << "\ntime,residence,away\n";
      // Empty beyond a distribution's last time (docs/markov.md: the end of the snapshots).
      auto field = [](const std::vector<double> &p, std::size_t n) {
        char v[32] = "";
        if (n < p.size()) std::snprintf(v, sizeof v, "%.10g", p[n]);
        return std::string(v);
      };
      for (std::size_t n = 0; n < std::max(residence.size(), away.size()); ++n) {
        char t[32];
        std::snprintf(t, sizeof t, "%.10g", double(n + 1) * dt);
        z << t << ',' << field(residence, n) << ',' << field(away, n) << '\n';
      }
      writeTextAtomically(dir + "zone_" + v.name() + ".csv", z.str());
      const int steps = dt > 0 ? static_cast<int>(std::lround(out.passesTime / dt)) : 0;
      const std::vector<double> passes = v.passCounts(steps, static_cast<int>(out.passesMax));
      if (out.passesTime > 0 && passes.empty()) {
        char why[160];
        std::snprintf(why, sizeof why, "-passes_time %g s: expected a time from one snapshot interval to the %g s the snapshots span",
                      out.passesTime, dt * double(sel.size() - 1));
        throw std::runtime_error(why);
      }
      if (!passes.empty()) {
        std::ostringstream c;
        c << "# zone " << v.name() << ": probability of j entries into the zone within " << steps * dt
          << " s (the last row: that many or more), from the particles, every start snapshot\npasses,probability\n";
        double mean = 0.0;
        for (std::size_t j = 0; j < passes.size(); ++j) {
          char line[48];
          std::snprintf(line, sizeof line, "%zu,%.10g\n", j, passes[j]);
          c << line;
          mean += double(j) * passes[j];
        }
        writeTextAtomically(dir + "passes_" + v.name() + ".csv", c.str());
        if (talk)
          std::printf("  zone %s: entries within %g s: mean %.4g, none %.4f\n", v.name().c_str(), steps * dt, mean,
                      passes[0]);
      }
      if (!talk) continue;
      double mass[2] = {0, 0}, mean[2] = {0, 0};
      for (std::size_t n = 0; n < residence.size(); ++n)
        mass[0] += residence[n], mean[0] += double(n + 1) * dt * residence[n];
      for (std::size_t n = 0; n < away.size(); ++n) mass[1] += away[n], mean[1] += double(n + 1) * dt * away[n];
      std::printf("  zone %s: share of time %.4f; per visit %.4g s (%.4f of the visits within %.3g s, %zu "
                  "complete), away %.4g s (%.4f within %.3g s, %zu complete); means over those\n",
                  v.name().c_str(), v.share(), mass[0] > 0 ? mean[0] / mass[0] : 0.0, mass[0],
                  double(residence.size()) * dt, v.complete(false), mass[1] > 0 ? mean[1] / mass[1] : 0.0, mass[1],
                  double(away.size()) * dt, v.complete(true));
    }
    if (!talk) return;

    const SizeClasses &cls = ref.classes();
    std::printf("Wrote %scog.csv (%zu snapshots, t = %.6g to %.6g s), profiles.csv and halves.csv "
                "(%zu snapshots in the averaging window)\n",
                dir.c_str(), sel.size(), in.times[sel.front()], in.times[sel.back()],
                ref.windowSnapshots());
    std::printf("  size classes:");
    for (std::size_t c = 0; c < cls.diameter.size(); ++c)
      std::printf(" %s", cls.label(static_cast<int>(c)).c_str());
    std::printf("\n");
    if (ref.windowSnapshots() > 0 && cls.diameter.size() >= 2) {
      double sum = 0.0;
      std::size_t n = 0;
      for (const CogSample &s : ref.series())
        if (s.time >= out.windowBegin && s.time <= out.windowEnd) sum += ref.deltaZ(s), ++n;
      const auto h = ref.halves();
      std::printf("  in the window: mean delta_z %.4g mm; mass fraction of %s bottom %.4f, top %.4f\n",
                  1e3 * sum / double(n), cls.label(0).c_str(), h.bottom[0], h.top[0]);
    }
    if (ref.outsideProfileMesh() > 0)
      std::printf("  %zu particle-snapshots outside the profile mesh were left out of the profiles\n",
                  ref.outsideProfileMesh());
  }));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
