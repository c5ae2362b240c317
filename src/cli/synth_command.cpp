#include "cli/commands.hpp"
#include "base/checked_options.hpp"
#include "base/petsc_compat.hpp"

#include "builders/synthetic/synthetic_bed.hpp"
#include "rcfd/database.hpp"
#include "base/collective.hpp"

#include <cstdio>

namespace rcfd::cli {
namespace {

PetscErrorCode readSynthOptions(MPI_Comm comm, SyntheticBedOptions *o, std::string *path,
                                PetscBool *quiet) {
  char text[PETSC_MAX_PATH_LEN] = "default-bed.h5";
  PetscInt cells[3] = {o->box.nx, o->box.ny, o->box.nz}, ncells = 3;
  PetscReal length[3] = {o->box.length[0], o->box.length[1], o->box.length[2]};
  PetscInt nlength = 3, frames = o->numFrames, seed = static_cast<PetscInt>(o->seed),
           parcels = o->parcelsPerCell;
  PetscBool setCells = PETSC_FALSE, setLength = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, nullptr, "rcfd synth: the embedded default database", "rcfd");
  PetscCall(PetscOptionsString("-o", "Output database file", "", text, text, sizeof text, nullptr));
  PetscCall(PetscOptionsIntArray("-synth_cells", "Cells nx,ny,nz", "", cells, &ncells, &setCells));
  PetscCall(PetscOptionsRealArray("-synth_length", "Box size lx,ly,lz [m]", "", length, &nlength,
                                  &setLength));
  PetscCall(checkedInt(PetscOptionsObject, "-synth_frames", "Number of frames K", &frames, 1, 10000000));
  PetscCall(checkedReal(PetscOptionsObject, "-synth_dt",
                        "Time between frames dt_rec [s]", &o->dtRec, kPositive));
  PetscCall(checkedInt(PetscOptionsObject, "-synth_seed", "Random seed", &seed, 0, PETSC_MAX_INT));
  PetscCall(checkedReal(PetscOptionsObject, "-synth_bed_height",
                        "Settled bed height [m]", &o->bedHeight, kPositive));
  PetscCall(checkedReal(PetscOptionsObject, "-synth_packing",
                        "alpha_s of the dense phase", &o->packing, kOpenUnit));
  PetscCall(checkedInt(PetscOptionsObject, "-synth_parcels_per_cell",
                       "Parcels per dense cell", &parcels, 1, 10000));
  PetscCall(checkedReal(PetscOptionsObject, "-synth_nucleation_rate",
                        "Bubbles per second and m^2 of distributor", &o->nucleationRate, kNonNegative));
  PetscCall(checkedReal(PetscOptionsObject, "-synth_max_diameter",
                        "Largest bubble diameter [m]", &o->maxDiameter, kPositive));
  PetscCall(checkedReal(PetscOptionsObject, "-synth_warm_up",
                        "Simulated time before frame 0 [s]", &o->warmUpTime, kNonNegative));
  PetscCall(PetscOptionsBool("-quiet", "No report", "", *quiet, quiet, nullptr));
  PetscOptionsEnd();
  PetscCheck((!setCells || ncells == 3) && (!setLength || nlength == 3), comm, PETSC_ERR_USER_INPUT,
             "-synth_cells and -synth_length take three values each (x, y, z)");
  PetscCheck(frames >= 1 && seed >= 0 && parcels >= 1, comm, PETSC_ERR_USER_INPUT,
             "-synth_frames and -synth_parcels_per_cell must be positive and -synth_seed non-negative");
  const std::string tooBig = BoxSpec::sizeProblem(cells[0], cells[1], cells[2]);
  PetscCheck(tooBig.empty(), comm, PETSC_ERR_USER_INPUT, "-synth_cells %d,%d,%d %s", (int)cells[0],
             (int)cells[1], (int)cells[2], tooBig.c_str());
  o->box.nx = static_cast<int>(cells[0]);
  o->box.ny = static_cast<int>(cells[1]);
  o->box.nz = static_cast<int>(cells[2]);
  for (int a = 0; a < 3; ++a) o->box.length[a] = length[a];
  o->numFrames = static_cast<int>(frames);
  o->seed = static_cast<std::uint64_t>(seed);
  o->parcelsPerCell = static_cast<int>(parcels);
  *path = text;
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

PetscErrorCode synthCommand(MPI_Comm comm) {
  SyntheticBedOptions options;
  std::string path;
  PetscBool quiet = PETSC_FALSE;
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(readSynthOptions(comm, &options, &path, &quiet));
  OperatingConditions conditions; // recorded in the file when given (format version 2)
  PetscCall(OperatingConditions::fromOptions(comm, &conditions));
  if (helpRequested()) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(rejectUnusedOptions(comm, "synth"));
  PetscCall(collectively(comm, [&] { validateSyntheticBedOptions(options); }, PETSC_ERR_USER_INPUT));

  // The generator is serial: rank 0 makes and writes the file, the others wait.
  SyntheticBedReport report;
  PetscCall(collectively(comm, [&] {
    if (rank != 0) return;
    DatabaseMetadata meta;
    meta.dtRec = options.dtRec;
    meta.gravity = {0.0, 0.0, -options.gravity};
    meta.conditions = conditions;
    meta.source = "rcfd synth: kinematic stand-in for a bubbling bed (not physics), seed " +
                  std::to_string(options.seed);
    DatabaseWriter writer(path, Mesh::box(options.box), meta);
    report = generateSyntheticBed(options, [&](const FrameRecord &frame) {
      writer.append(frame);
      if (!quiet && (writer.numFrames() % 50 == 0 || writer.numFrames() == options.numFrames))
        std::printf("  frame %d/%d\n", writer.numFrames(), options.numFrames), std::fflush(stdout);
    });
    writer.finish();
  }));
  if (!quiet)
    PetscCall(PetscPrintf(comm,
                          "Wrote %s: %d frames of %d cells every %g s; %ld parcels, largest alpha_s %.3f,"
                          " mean bed height %.3f m, %ld bubbles erupted, wrap mismatch %.2f %%\n",
                          path.c_str(), options.numFrames, options.box.numCells(), options.dtRec,
                          report.parcels, report.maxAlpha, report.meanBedHeight,
                          report.bubblesErupted, 100 * report.wrapMismatchRelative));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
