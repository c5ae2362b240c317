// rcfd build -eulerian "DIR/frame_*.txt": a database from Eulerian CFD-DEM
// frames (x y z alpha Ux Uy Uz Usx Usy Usz per cell), shifts by tracing the
// solid velocity and proportional scaling (src/database/eulerian_frames.hpp).
#include "cli/commands.hpp"
#include "base/petsc_compat.hpp"
#include "mesh/box_mesh.hpp"

#include "base/checked_options.hpp"
#include "builders/eulerian/eulerian_frames.hpp"
#include "builders/particles/snapshot_series.hpp"
#include "rcfd/database.hpp"
#include "base/collective.hpp"
#include "base/constants.hpp"
#include "database/database_file_writer.hpp"
#include "mesh/vessel_mesh.hpp"
#include "rcfd/vessel.hpp"

#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sstream>

namespace rcfd::cli {
namespace {

struct EulerianInput {
  std::string pattern, database = "eulerian.h5";
  EulerianMeshRequest mesh;
  EulerianBuildOptions build;
  double solidDensity = kDefaultSolidDensity, gravity = kGravity;
  PetscBool quiet = PETSC_FALSE;
};

PetscErrorCode readEulerianOptions(MPI_Comm comm, EulerianInput *in) {
  char pattern[PETSC_MAX_PATH_LEN] = "", db[PETSC_MAX_PATH_LEN], interp[16] = "cell";
  PetscBool setCells = PETSC_FALSE, setLo = PETSC_FALSE, setHi = PETSC_FALSE, setDt = PETSC_FALSE;
  PetscInt cells[3] = {0, 0, 0}, ncells = 3, nlo = 3, nhi = 3;
  PetscInt tracers = in->build.tracersPerCell, iterations = in->build.scalingIterations,
           seed = static_cast<PetscInt>(in->build.seed), radius = in->build.maxSupportRadius;
  PetscReal lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  EulerianBuildOptions &b = in->build;
  PetscFunctionBeginUser;
  std::snprintf(db, sizeof db, "%s", in->database.c_str());
  PetscOptionsBegin(comm, nullptr, "rcfd build -eulerian: a database from Eulerian CFD-DEM frames",
                    "rcfd");
  PetscCall(PetscOptionsString("-eulerian",
                               "Frame files 'x y z alpha Ux Uy Uz Usx Usy Usz' per cell (alpha: void "
                               "fraction): a quoted glob pattern, taken in natural order",
                               "", pattern, pattern, sizeof pattern, nullptr));
  PetscCall(PetscOptionsString("-o", "Output database file", "", db, db, sizeof db, nullptr));
  PetscCall(checkedReal(PetscOptionsObject, "-dt_rec",
                        "Time between the frame files [s] (required)", &b.dtRec, kPositive, &setDt));
  PetscCall(checkedIntArray(PetscOptionsObject, "-mesh_cells",
                            "Cells nx,ny,nz (default: from the cell centres)", cells, &ncells, &setCells));
  PetscCall(checkedRealArray(PetscOptionsObject, "-mesh_lo",
                             "Lower corner x,y,z [m] (default: from the centres)", lo, &nlo, &setLo));
  PetscCall(checkedRealArray(PetscOptionsObject, "-mesh_hi",
                             "Upper corner x,y,z [m] (default: from the centres)", hi, &nhi, &setHi));
  PetscCall(checkedInt(PetscOptionsObject, "-tracers_per_cell",
                       "Tracers per occupied cell and frame", &tracers, 1, 1000000));
  PetscCall(checkedInt(PetscOptionsObject, "-tracer_seed",
                       "Seed of the tracers' jitter", &seed, 0, PETSC_MAX_INT));
  PetscCall(PetscOptionsString("-tracer_interpolation",
                               "Solid velocity at a tracer: trilinear (between cell centres, weighted "
                               "by alpha_s) or cell (constant per cell)",
                               "", interp, interp, sizeof interp, nullptr));
  PetscCall(checkedReal(PetscOptionsObject, "-tracer_courant",
                        "Largest tracer move per sub-step [cells]", &b.courant, kPositive));
  PetscCall(checkedReal(PetscOptionsObject, "-slow_cell_factor",
                        "Slow cell: V^(1/3)/|Us| > factor * dt_rec (0: no slow-cell split)",
                        &b.slowCellFactor, kPositive));
  PetscCall(checkedReal(PetscOptionsObject, "-empty_alpha_s",
                        "A cell with alpha_s at or below this is empty",
                        &b.emptyAlphaS, {0.0, 1.0, true, false, "a solid fraction in [0, 1)"}));
  PetscCall(checkedReal(PetscOptionsObject, "-scaling_support",
                        "Before scaling, each occupied cell sends this share of its solid to itself and to each "
                        "face neighbour that holds solid at t_k+1 (0: none)",
                        &b.supportSeed, kNonNegative));
  PetscCall(checkedInt(PetscOptionsObject, "-scaling_support_radius",
                       "Cells that scaling cannot serve get such seeds from up to this many cells away (1: never)",
                       &radius, 0, 1000));
  PetscCall(checkedInt(PetscOptionsObject, "-scaling_iterations",
                       "Most scaling iterations (sweeps and Newton steps) per frame (0: none)",
                       &iterations, 0, 100000000));
  PetscCall(checkedReal(PetscOptionsObject, "-scaling_tolerance",
                        "Stop scaling at |T a_k - a_k+1|_1 / |a_k|_1 below this",
                        &b.scalingTolerance, kPositive));
  PetscCall(checkedReal(PetscOptionsObject, "-solid_density",
                        "Particle density [kg/m^3]",
                        &in->solidDensity, {0.0, 1e6, false, true, "a positive density in kg/m^3"}));
  PetscCall(checkedReal(PetscOptionsObject, "-gravity",
                        "Magnitude of gravity [m/s^2], along -z", &in->gravity, kPositive));
  PetscCall(PetscOptionsBool("-quiet", "No progress or report", "", in->quiet, &in->quiet, nullptr));
  PetscOptionsEnd();
  if (helpRequested()) PetscFunctionReturn(PETSC_SUCCESS);

  PetscCheck(pattern[0], comm, PETSC_ERR_USER_INPUT,
             "Give the frame files with -eulerian \"DIR/frame_*.txt\"");
  PetscCheck(setDt && b.dtRec > 0, comm, PETSC_ERR_USER_INPUT,
             "Give the time between the frame files with -dt_rec SECONDS (> 0)");
  PetscCheck(!setCells || (ncells == 3 && cells[0] > 0 && cells[1] > 0 && cells[2] > 0), comm,
             PETSC_ERR_USER_INPUT, "-mesh_cells takes three positive counts nx,ny,nz");
  PetscCheck((!setLo || nlo == 3) && (!setHi || nhi == 3), comm, PETSC_ERR_USER_INPUT,
             "-mesh_lo and -mesh_hi take three values each (x, y, z)");
  PetscCheck(setLo == setHi, comm, PETSC_ERR_USER_INPUT,
             "Give both -mesh_lo and -mesh_hi, or neither (the box from the cell centres)");
  const std::string ip = interp;
  PetscCheck(ip == "trilinear" || ip == "cell", comm, PETSC_ERR_USER_INPUT,
             "-tracer_interpolation %s is not known; use trilinear or cell", interp);
  PetscCheck(seed >= 0, comm, PETSC_ERR_USER_INPUT, "-tracer_seed must be non-negative");
  PetscCheck(in->solidDensity > 0, comm, PETSC_ERR_USER_INPUT, "-solid_density must be positive");
  PetscCheck(in->gravity > 0, comm, PETSC_ERR_USER_INPUT, "-gravity must be positive");

  in->pattern = pattern;
  in->database = db;
  if (setCells)
    in->mesh.cells = std::array<int, 3>{static_cast<int>(cells[0]), static_cast<int>(cells[1]),
                                        static_cast<int>(cells[2])};
  if (setLo) {
    in->mesh.lo = Vec3{lo[0], lo[1], lo[2]};
    in->mesh.hi = Vec3{hi[0], hi[1], hi[2]};
  }
  b.tracersPerCell = static_cast<int>(tracers);
  b.scalingIterations = static_cast<int>(iterations);
  b.maxSupportRadius = static_cast<int>(radius);
  b.seed = static_cast<std::uint64_t>(seed);
  b.interpolation = ip == "cell" ? TracerInterpolation::cell : TracerInterpolation::trilinear;
  // The mesh is checked once the first frame is read.
  PetscCall(collectively(comm, [&] { validateEulerianBuildOptions(b); }, PETSC_ERR_USER_INPUT));
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::vector<std::string> listFrames(const std::string &pattern) {
  try {
    return globSnapshotFiles(pattern);
  } catch (const std::runtime_error &e) {
    // The lister speaks of particle snapshots; these are frames.
    if (std::string(e.what()).find("matches") == std::string::npos) throw;
    throw std::runtime_error("no Eulerian frame file matches '" + pattern + "'.");
  }
}

std::string fileName(const std::string &path) {
  return std::filesystem::path(path).filename().string();
}

} // namespace

PetscErrorCode buildEulerianCommand(MPI_Comm comm) {
  EulerianInput in;
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(readEulerianOptions(comm, &in));
  OperatingConditions conditions; // recorded in the file when given (format version 2)
  PetscCall(OperatingConditions::fromOptions(comm, &conditions));
  Vessel vessel; // -vessel (docs/vessels.md): the frames are on the box, the database on the vessel's cells
  PetscCall(vessel.setFromOptions(comm));
  // Traced shifts of merged cells would need a mass-weighted product of their members' rows (as coarsening's).
  PetscCheck(!(vessel.mergeBelow() > 0), comm, PETSC_ERR_SUP,
             "-vessel_merge_below is not supported by rcfd build -eulerian yet; build without it (rcfd synth and "
             "rcfd build from particle dumps take it)");
  if (helpRequested()) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(rejectUnusedOptions(comm, "build"));

  // Reading frames, tracing and writing are serial: rank 0 works, the
  // others wait for the verdict.
  PetscCall(collectively(comm, [&] {
    if (rank != 0) return;
    const bool talk = !in.quiet;
    const std::vector<std::string> files = listFrames(in.pattern);
    if (files.size() < 2)
      throw std::runtime_error("'" + in.pattern + "' matches " + std::to_string(files.size()) +
                               " Eulerian frame file; a database frame needs two.");
    const EulerianRows first = readEulerianRows(files.front());
    EulerianBuildOptions opt = in.build;
    opt.mesh = resolveEulerianMesh(in.mesh, first);
    const BoxSpec &box = opt.mesh;
    EulerianFrame frame0 = mapOntoMesh(first, box);
    const Vessel inBox = vesselInBox(vessel, box);
    const Mesh mesh = inBox.isWholeBox() ? boxMesh(box) : cutVesselMesh(inBox, box);
    if (mesh.isMasked()) opt.cellVolume = insideVolumes(mesh), opt.vessel = inBox;

    DatabaseMetadata meta;
    meta.dtRec = opt.dtRec;
    meta.solidDensity = in.solidDensity;
    meta.gravity = {0.0, 0.0, -in.gravity};
    meta.conditions = conditions;
    {
      std::ostringstream s;
      s.precision(9);
      s << "rcfd build: " << files.size() << " Eulerian frames '" << in.pattern << "', "
        << fileName(files.front()) << " to " << fileName(files.back()) << ", dt_rec = " << opt.dtRec
        << " s; shifts traced with " << opt.tracersPerCell << " tracers per cell (seed " << opt.seed
        << ") and scaled to mass consistency";
      meta.source = s.str();
    }
    if (talk)
      std::printf("Building %s from %zu Eulerian frames ('%s'), dt_rec = %.6g s, mesh %d x %d x %d "
                  "cells from (%.6g, %.6g, %.6g) to (%.6g, %.6g, %.6g) m\n",
                  in.database.c_str(), files.size(), in.pattern.c_str(), opt.dtRec, box.nx, box.ny,
                  box.nz, box.origin[0], box.origin[1], box.origin[2],
                  box.origin[0] + box.length[0], box.origin[1] + box.length[1],
                  box.origin[2] + box.length[2]),
          std::fflush(stdout);

    if (talk && mesh.isMasked())
      std::printf("Vessel %s: %d of the box's %d cells\n", mesh.vessel().c_str(), mesh.numCells(), box.numCells());
    DatabaseFileWriter writer(in.database, mesh, meta);
    EulerianFrameBuilder builder(opt, [&](const FrameRecord &f) {
      writer.append(mesh.isMasked() ? onVesselCells(f, mesh) : f);
    });
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    auto lastPrint = start;
    builder.add(std::move(frame0));
    for (std::size_t k = 1; k < files.size(); ++k) {
      builder.add(readEulerianFrame(files[k], box));
      const auto now = Clock::now();
      if (talk && (now - lastPrint > std::chrono::seconds(2) || k + 1 == files.size())) {
        lastPrint = now;
        std::printf("  frame %zu/%zu (%s), %.1f s\n", k + 1, files.size(), fileName(files[k]).c_str(),
                    std::chrono::duration<double>(now - start).count());
        std::fflush(stdout);
      }
    }
    const EulerianBuildReport &rep = builder.report();
    std::vector<double> perFrame;
    for (const auto &f : rep.frame)
      perFrame.insert(perFrame.end(), {f.residualBefore, f.residualAfter,
                                       static_cast<double>(f.iterations), f.massChange});
    writer.writeMatrix("eulerian_residuals", perFrame, 4,
                       "per frame k: |T a_k - a_k+1|_1 / |a_k|_1 of the traced shift, the same after "
                       "proportional scaling, the scaling iterations, and |sum a_k+1 - sum a_k| / "
                       "sum a_k (the floor of the residual)");
    writer.setNote("build_report", rep.summary());
    writer.finish();
    if (talk)
      std::printf("Wrote %s: %zu frames every %.6g s\n%s\n", in.database.c_str(), rep.frames,
                  opt.dtRec, rep.summary().c_str());
  }));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
