// rcfd build: a database from DEM particle snapshots, and optionally the
// initial composition of a run (-init_out) from the first snapshot used.
// With -eulerian it builds from Eulerian frames instead (build_eulerian_command.cpp).
#include "cli/commands.hpp"
#include "base/checked_options.hpp"
#include "base/petsc_compat.hpp"
#include "mesh/box_mesh.hpp"

#include "cli/particle_input.hpp"
#include "analysis/measured_drift.hpp"
#include "analysis/particle_reference.hpp"
#include "analysis/regional_drift.hpp"
#include "rcfd/database.hpp"
#include "mesh/vessel_mesh.hpp"
#include "base/atomic_file.hpp"
#include "base/collective.hpp"
#include "base/constants.hpp"
#include "base/h5.hpp"
#include "database/database_file_writer.hpp"
#include "rcfd/vessel.hpp"
#include "builders/particles/particle_vessel.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <numeric>
#include <sstream>

namespace rcfd::cli {
namespace {

struct BuildOutputs {
  std::string database = "particles.h5", initOut;
  double gravity = kGravity;
  PetscBool quiet = PETSC_FALSE;
  DriftRegions driftRegions{2, 2, 2}; // of /extra/measured_drift_field (docs/drift.md, "Measured-drift replay")
};

PetscErrorCode readBuildOptions(MPI_Comm comm, BuildOutputs *o) {
  char db[PETSC_MAX_PATH_LEN], init[PETSC_MAX_PATH_LEN] = "";
  PetscBool setInit = PETSC_FALSE;
  PetscInt region[3] = {o->driftRegions.rx, o->driftRegions.ry, o->driftRegions.rz}, nregion = 3;
  PetscBool setRegion = PETSC_FALSE;
  PetscFunctionBeginUser;
  std::snprintf(db, sizeof db, "%s", o->database.c_str());
  PetscOptionsBegin(comm, nullptr,
                    "rcfd build: a database from particle snapshots (from Eulerian frames: "
                    "rcfd build -eulerian PATTERN -help)",
                    "rcfd");
  PetscCall(PetscOptionsString("-o", "Output database file", "", db, db, sizeof db, nullptr));
  PetscCall(PetscOptionsString("-init_out",
                               "Also write the first snapshot's masses per cell and size class "
                               "(HDF5 /masses, for rcfd run -init file)",
                               "", "", init, sizeof init, &setInit));
  PetscCall(checkedReal(PetscOptionsObject, "-gravity",
                        "Magnitude of gravity [m/s^2]", &o->gravity, kPositive));
  PetscCall(PetscOptionsBool("-quiet", "No progress or report", "", o->quiet, &o->quiet, nullptr));
  PetscCall(checkedIntArray(PetscOptionsObject, "-measured_drift_region",
                            "Cells nx,ny,nz per region of the measured drift field (-drift_model measured)", region,
                            &nregion, &setRegion));
  PetscOptionsEnd();
  PetscCheck(!setRegion || (nregion == 3 && region[0] >= 1 && region[1] >= 1 && region[2] >= 1), comm,
             PETSC_ERR_USER_INPUT, "-measured_drift_region takes three positive cell counts nx,ny,nz");
  o->driftRegions = {static_cast<int>(region[0]), static_cast<int>(region[1]), static_cast<int>(region[2])};
  PetscCheck(o->gravity > 0, comm, PETSC_ERR_USER_INPUT, "-gravity must be positive");
  o->database = db;
  if (setInit) o->initOut = init;
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::string fileName(const std::string &path) {
  return std::filesystem::path(path).filename().string();
}

std::string join(const std::vector<double> &v, double scale, const char *format) {
  std::string out;
  char text[64];
  for (std::size_t i = 0; i < v.size(); ++i) {
    std::snprintf(text, sizeof text, format, v[i] * scale);
    out += (i ? "," : "") + std::string(text);
  }
  return out;
}

/// /masses [cells x classes] in natural cell order, with the class diameters
/// and mass shares as attributes; written under a temporary name first.
void writeInitialMasses(const std::string &path, const std::vector<double> &masses,
                        const SizeClasses &classes, const std::vector<double> &shares,
                        const std::string &note) {
  AtomicFile target(path);
  h5::File f = h5::File::create(target, h5::Checksums::fletcher32); // a damaged init file is refused
  f.write("/masses", masses, static_cast<hsize_t>(classes.diameter.size()));
  f.writeAttr("/masses", "diameters", classes.diameter);
  f.writeAttr("/masses", "mass_shares", shares);
  f.writeAttr("/masses", "note", note);
  f.close();
  target.commit();
}

} // namespace

namespace {
// -vessel from-particles [-vessel_margin M] (docs/vessels.md); any other -vessel is
// Vessel::setFromOptions's to read.
PetscErrorCode readParticleVesselOptions(MPI_Comm comm, PetscBool *fromParticles, PetscReal *margin) {
  char name[64] = "";
  PetscBool set = PETSC_FALSE, marginSet = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(nullptr, nullptr, "-vessel", name, sizeof name, &set));
  *fromParticles = set && std::string(name) == "from-particles" ? PETSC_TRUE : PETSC_FALSE;
  PetscOptionsBegin(comm, nullptr, "Vessel from the particles (docs/vessels.md)", nullptr);
  PetscCall(checkedReal(PetscOptionsObject, "-vessel_margin",
                        "with -vessel from-particles: cells closer than this to a particle centre are inside too [m]",
                        margin, kNonNegative, &marginSet));
  PetscOptionsEnd();
  PetscCheck(!marginSet || *fromParticles, comm, PETSC_ERR_USER_INPUT,
             "-vessel_margin belongs to -vessel from-particles; an analytic vessel is given by its shapes");
  PetscFunctionReturn(PETSC_SUCCESS);
}
} // namespace

PetscErrorCode buildCommand(MPI_Comm comm) {
  ParticleInput in;
  BuildOutputs out;
  PetscMPIInt rank;
  PetscBool eulerian = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-eulerian", &eulerian));
  if (eulerian) {
    PetscCall(buildEulerianCommand(comm));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(readBuildOptions(comm, &out));
  PetscCall(readParticleInputOptions(comm, &in));
  OperatingConditions conditions; // recorded in the file when given (format version 2)
  PetscCall(OperatingConditions::fromOptions(comm, &conditions));
  Vessel vessel; // -vessel (docs/vessels.md): completed by the box once the particles give it
  PetscBool fromParticles = PETSC_FALSE; // -vessel from-particles: the cells the particles reached
  PetscReal margin = 0.0;
  PetscCall(readParticleVesselOptions(comm, &fromParticles, &margin));
  if (!fromParticles) PetscCall(vessel.setFromOptions(comm));
  if (helpRequested()) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(rejectUnusedOptions(comm, "build"));

  // Reading snapshots and writing the file are serial: rank 0 works, the
  // others wait for the verdict.
  PetscCall(collectively(comm, [&] {
    if (rank != 0) return;
    const bool talk = !out.quiet;
    in.resolve();
    const std::vector<std::size_t> sel = in.selected();
    if (sel.size() < 2)
      throw std::runtime_error("the window and stride select " + std::to_string(sel.size()) +
                               " snapshot of the " + std::to_string(in.files.size()) + " " +
                               in.origin() + "; a database frame needs two.");
    double dtRec = 0.0;
    try {
      dtRec = uniformInterval(in.times, sel);
    } catch (const std::runtime_error &e) { // name where the times came from
      throw std::runtime_error((in.timesFile.empty() ? "-dump_dt" : "-times '" + in.timesFile + "'") +
                               std::string(": ") + e.what());
    }
    ParticleBuildOptions opt = in.buildOptions();
    const ParticleSnapshot first = readParticleSnapshot(in.files[sel.front()], opt.read);
    opt.mesh = resolveMesh(in.mesh, first, opt.axes);
    const BoxSpec &box = opt.mesh;
    const Vessel inBox = vesselInBox(vessel, box);
    const Mesh mesh = [&] {
      if (!fromParticles) return inBox.isWholeBox() ? boxMesh(box) : cutVesselMesh(inBox, box);
      // The vessel is where the particles were in the snapshots the frames are built from:
      // one pass over them before the build's own.
      VisitedCells visited(box, opt.axes, margin);
      visited.add(first);
      for (std::size_t k = 1; k < sel.size(); ++k) visited.add(readParticleSnapshot(in.files[sel[k]], opt.read));
      return visited.mesh();
    }();
    if (mesh.isMasked()) opt.vessel = &mesh;
    // A particle the frames count: centred inside the vessel's shapes, or in its cells when it has none.
    auto insideVessel = [&](const Vec3 &x) {
      return fromParticles ? mesh.cellOfBoxCell(box.locate(x)) >= 0 : inBox.contains(x);
    };
    if (talk && fromParticles)
      std::printf("Vessel from the particles (margin %g m): %d of the box's %d cells\n", (double)margin,
                  mesh.numCells(), box.numCells());

    DatabaseMetadata meta;
    meta.dtRec = dtRec;
    meta.solidDensity = in.solidDensity;
    meta.gravity = {0.0, 0.0, -out.gravity};
    meta.conditions = conditions;
    {
      std::ostringstream s;
      s.precision(9);
      s << "rcfd build: " << sel.size() << " particle snapshots of " << in.origin() << ", "
        << fileName(in.files[sel.front()]) << " (t = " << in.times[sel.front()] << " s) to "
        << fileName(in.files[sel.back()]) << " (t = " << in.times[sel.back()]
        << " s), stride " << in.stride << "; frame 0 is t = " << in.times[sel.front()]
        << " s";
      meta.source = s.str();
    }
    if (talk)
      std::printf("Building %s from %zu of %zu snapshots (%s), dt_rec = %.6g s, mesh %d x %d x %d "
                  "cells from (%.4g, %.4g, %.4g) to (%.4g, %.4g, %.4g) m\n",
                  out.database.c_str(), sel.size(), in.files.size(), in.origin().c_str(), dtRec,
                  box.nx, box.ny, box.nz, box.origin[0], box.origin[1], box.origin[2],
                  box.origin[0] + box.length[0], box.origin[1] + box.length[1],
                  box.origin[2] + box.length[2]),
          std::fflush(stdout);

    // The initial composition is computed now and written only once the
    // database is, so that a build that fails leaves no file behind.
    std::function<void()> initial;
    if (!out.initOut.empty()) {
      const SizeClasses classes = SizeClasses::cluster(first.diameter, in.classTolerance);
      std::size_t outside = 0;
      // In a vessel, the particles the frames count: those centred inside its shapes.
      const ParticleSnapshot *counting = &first;
      ParticleSnapshot counted;
      std::size_t beyond = 0;
      if (mesh.isMasked()) {
        counted = first;
        counting = &counted;
        std::size_t kept = 0;
        for (std::size_t p = 0; p < first.size(); ++p) {
          if (!insideVessel(opt.axes.apply(first.position[p]))) continue;
          counted.id[kept] = first.id[p];
          counted.type[kept] = first.type[p];
          counted.position[kept] = first.position[p];
          counted.diameter[kept] = first.diameter[p];
          counted.mass[kept++] = first.mass[p];
        }
        counted.id.resize(kept), counted.type.resize(kept), counted.position.resize(kept);
        counted.diameter.resize(kept), counted.mass.resize(kept);
        beyond = first.size() - kept;
      }
      auto masses = classMassesPerCell(*counting, opt.axes, box, classes, opt.volume, &outside);
      outside += beyond;
      const std::size_t nc = classes.diameter.size();
      if (mesh.isMasked()) { // the vessel's cells; what lies in box cells outside it is left out
        std::vector<double> inside(static_cast<std::size_t>(mesh.numCells()) * nc);
        for (int c = 0; c < mesh.numCells(); ++c)
          std::copy_n(&masses[static_cast<std::size_t>(mesh.boxCell(c)) * nc], nc, &inside[c * nc]);
        for (const auto &[b, c] : mesh.mergedBoxCells()) // tiny cut cells merged: their masses too
          for (std::size_t k = 0; k < nc; ++k) inside[c * nc + k] += masses[static_cast<std::size_t>(b) * nc + k];
        masses.swap(inside);
      }
      std::vector<double> total(nc, 0.0);
      for (std::size_t k = 0; k < masses.size(); ++k) total[k % nc] += masses[k];
      const double sum = std::accumulate(total.begin(), total.end(), 0.0);
      if (!(sum > 0.0))
        throw std::runtime_error("particle snapshot '" + first.source +
                                 "' has no particle inside the mesh, so -init_out has no mass.");
      std::vector<double> shares(nc);
      for (std::size_t c = 0; c < nc; ++c) shares[c] = total[c] / sum;
      shares.back() = 1.0 - std::accumulate(shares.begin(), shares.end() - 1, 0.0);
      std::ostringstream note;
      note.precision(9);
      note << "masses [kg] per cell (natural order) and size class of " << first.source
           << " (t = " << in.times[sel.front()] << " s); classes by diameter [m] in attribute "
           << "diameters, mass shares in mass_shares; " << outside
           << " particles outside the mesh left out";
      const std::string message = [&] {
        char text[2048];
        std::snprintf(text, sizeof text, "Wrote %s: initial masses of %zu size classes (%s mm, mass shares %s) in %d cells"
                    "%s; use: rcfd run -init file -init_file %s -fractions_diameters %s "
                    "-fractions_mass_shares %s\n",
                    out.initOut.c_str(), nc, join(classes.diameter, 1e3, "%.4g").c_str(),
                    join(shares, 1.0, "%.4f").c_str(), mesh.numCells(),
                    outside ? (" (" + std::to_string(outside) + " particles outside left out)").c_str()
                            : "",
                    out.initOut.c_str(), join(classes.diameter, 1.0, "%.9g").c_str(),
                    join(shares, 1.0, "%.9g").c_str());
        return std::string(text);
      }();
      initial = [=, path = out.initOut, text = note.str()] {
        writeInitialMasses(path, masses, classes, shares, text);
        if (talk) std::printf("%s", message.c_str());
      };
    }

    DatabaseFileWriter writer(out.database, mesh, meta);
    ParticleFrameBuilder builder(opt, [&](const FrameRecord &f) { writer.append(f); });
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    auto lastPrint = start;
    builder.add(first);
    // Each size class's drift relative to its cell's bulk, stored for rcfd calibrate.
    MeasuredDrift measured(SizeClasses::cluster(first.diameter, in.classTolerance), opt.axes, box);
    RegionalDrift regional(SizeClasses::cluster(first.diameter, in.classTolerance), opt.axes, box, out.driftRegions);
    ParticleSnapshot previous = first;
    for (std::size_t k = 1; k < sel.size(); ++k) {
      ParticleSnapshot next = readParticleSnapshot(in.files[sel[k]], opt.read);
      builder.add(next);
      measured.add(previous, next, dtRec);
      regional.add(previous, next, dtRec);
      previous = std::move(next);
      const auto now = Clock::now();
      if (talk && (now - lastPrint > std::chrono::seconds(2) || k + 1 == sel.size())) {
        lastPrint = now;
        std::printf("  snapshot %zu/%zu (%s), %.1f s\n", k + 1, sel.size(),
                    fileName(in.files[sel[k]]).c_str(),
                    std::chrono::duration<double>(now - start).count());
        std::fflush(stdout);
      }
    }
    const ParticleBuildReport &rep = builder.report();
    if (rep.cellsAlphaAtLeastOne > 0) {
      char text[320];
      std::snprintf(text, sizeof text,
                    opt.volume == ParticleVolume::Centre
                        ? "alpha_s reaches %.3f (>= 1 in %zu cell-snapshots): particles are "
                          "counted in the cell that holds their centre, so cells this small "
                          "cannot hold them; use -particle_volume overlap or larger cells "
                          "(-mesh_cells or -mesh_cell_size)."
                        : "alpha_s reaches %.3f (>= 1 in %zu cell-snapshots) although each "
                          "particle is shared among the cells it overlaps: the particles "
                          "overlap each other more than a packing can; check the snapshots' "
                          "diameters and units.",
                    rep.maxAlphaS, rep.cellsAlphaAtLeastOne);
      throw std::runtime_error(text); // the writer removes its temporary file
    }
    writer.setNote("build_report", rep.summary());
    writer.writeMatrix("measured_drift", measuredDriftTable(measured.result()), kMeasuredDriftColumns,
                       "per size class: diameter [m], vertical velocity relative to the bulk solid of "
                       "its cell, up positive [m/s], its standard error from per-frame means [m/s], "
                       "particle displacements, frames, mass share of the matched particles");
    writer.writeMatrix("measured_drift_by_agitation", driftByAgitationTable(measured.byAgitation()),
                       kDriftByAgitationColumns,
                       "per bin of the cell's leaving share (1 - T[i,i]) and size class: the bin's mean "
                       "leaving share, then the columns of measured_drift (mass share within the bin)");
    writer.writeMatrix("measured_agitation_mean", {measured.meanAgitation()}, 1,
                       "mass-weighted mean leaving share of the matched particles' cells (a bar)");
    writer.writeMatrix(kMeasuredDriftLayoutName, regional.layoutRow(), static_cast<int>(regional.layoutRow().size()),
                       "region size of measured_drift_field in cells (nx, ny, nz), then its size classes' "
                       "diameters [m]");
    writer.writeMatrix(kMeasuredDriftFieldName, regional.table(), regional.columns(),
                       "per frame (rows frame-major), region and size class: the mass-weighted mean vertical "
                       "velocity relative to the bulk solid of the particle's cell, up positive [m/s] (0 where "
                       "the class has no particle), the particles and their mass [kg]");
    writer.finish();
    if (initial) initial();
    if (talk)
      std::printf("Wrote %s: %zu frames every %.6g s\n%s\nmeasured drift field: regions of %d x %d x %d cells, "
                  "%.0f %% of its occupied entries rest on fewer than 10 particles\n",
                  out.database.c_str(), rep.frames, dtRec, rep.summary().c_str(), out.driftRegions.rx,
                  out.driftRegions.ry, out.driftRegions.rz, 100.0 * regional.shareBelow(10));
  }));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
