#include "cli/particle_input.hpp"
#include "base/petsc_compat.hpp"

#include "base/checked_options.hpp"
#include "cli/commands.hpp"

#include <stdexcept>

namespace rcfd::cli {

ParticleBuildOptions ParticleInput::buildOptions() const {
  ParticleBuildOptions o;
  o.axes = axes();
  o.stride = stride;
  o.first = first;
  o.last = last;
  o.read.defaultDensity = solidDensity;
  o.volume = volume;
  return o;
}

std::string ParticleInput::origin() const {
  return dumps.empty() ? "list '" + dumpList + "'" : "dumps '" + dumps + "'";
}

void ParticleInput::resolve() {
  files = dumps.empty() ? readSnapshotList(dumpList) : globSnapshotFiles(dumps);
  if (!timesFile.empty()) {
    times = readSnapshotTimes(timesFile);
    if (times.size() != files.size())
      throw std::runtime_error("-times '" + timesFile + "' lists " + std::to_string(times.size()) +
                               " times but the " + origin() + " give " +
                               std::to_string(files.size()) + " snapshot files.");
  } else {
    times.resize(files.size());
    for (std::size_t i = 0; i < files.size(); ++i) times[i] = static_cast<double>(i) * dumpDt;
  }
}

PetscErrorCode readParticleInputOptions(MPI_Comm comm, ParticleInput *in) {
  char dumps[PETSC_MAX_PATH_LEN] = "", list[PETSC_MAX_PATH_LEN] = "",
       times[PETSC_MAX_PATH_LEN] = "", axis[8] = "z";
  PetscBool setDumps = PETSC_FALSE, setList = PETSC_FALSE, setTimes = PETSC_FALSE,
            setDt = PETSC_FALSE, setCells = PETSC_FALSE, setLo = PETSC_FALSE, setHi = PETSC_FALSE,
            setWindow = PETSC_FALSE;
  PetscInt gravitySign = in->gravitySign, stride = in->stride, cells[3] = {0, 0, 0}, ncells = 3,
           window[2] = {0, -1}, nwindow = 2;
  PetscReal lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0}, cellSize = in->mesh.cellSize;
  PetscInt nlo = 3, nhi = 3;
  const char *const volumeRules[] = {"centre", "overlap"};
  PetscInt volumeRule = in->volume == ParticleVolume::Centre ? 0 : 1;
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, nullptr, "Particle snapshots (LIGGGHTS/LAMMPS dumps or CSV)", "rcfd");
  PetscCall(PetscOptionsString("-dumps", "Snapshot files: a quoted glob pattern, taken in natural order",
                               "", "", dumps, sizeof dumps, &setDumps));
  PetscCall(PetscOptionsString("-dump_list", "Or a file naming one snapshot a line, in time order",
                               "", "", list, sizeof list, &setList));
  PetscCall(PetscOptionsString("-times", "File of 'index time' lines, one per snapshot [s]", "", "",
                               times, sizeof times, &setTimes));
  PetscCall(checkedReal(PetscOptionsObject, "-dump_dt",
                        "Or the time between snapshot files [s]", &in->dumpDt, kPositive, &setDt));
  PetscCall(PetscOptionsString("-vertical_axis", "File axis that points along gravity: x, y or z",
                               "", axis, axis, sizeof axis, nullptr));
  PetscCall(PetscOptionsInt("-gravity_sign", "-1: gravity points to -vertical_axis; +1: to +axis",
                            "", gravitySign, &gravitySign, nullptr));
  PetscCall(checkedIntArray(PetscOptionsObject, "-mesh_cells", "Cells nx,ny,nz of the box mesh", cells, &ncells,
                            &setCells));
  PetscCall(checkedReal(PetscOptionsObject, "-mesh_cell_size",
                        "Or the cell size [m] (counts rounded)", &cellSize, kPositive));
  PetscCall(checkedRealArray(PetscOptionsObject, "-mesh_lo",
                             "Lower corner x,y,z [m, z up] (default: the first snapshot's box)", lo, &nlo,
                             &setLo));
  PetscCall(checkedRealArray(PetscOptionsObject, "-mesh_hi",
                             "Upper corner x,y,z [m, z up] (default: the first snapshot's box)", hi, &nhi,
                             &setHi));
  PetscCall(checkedInt(PetscOptionsObject, "-frame_stride",
                       "Use every n-th snapshot (dt_rec = n * snapshot interval)",
                       &stride, 1, PETSC_MAX_INT));
  PetscCall(checkedIntArray(PetscOptionsObject, "-window",
                            "First and last snapshot index to use, inclusive (last -1: to the end)", window,
                            &nwindow, &setWindow));
  PetscCall(checkedReal(PetscOptionsObject, "-solid_density",
                        "Particle density [kg/m^3] for files without density or mass columns",
                        &in->solidDensity, {0.0, 1e6, false, true, "a positive density in kg/m^3"}));
  PetscCall(checkedReal(PetscOptionsObject, "-class_tolerance",
                        "Relative diameter spread within one size class",
                        &in->classTolerance, {0.0, 1.0, true, false, "a relative tolerance in [0, 1)"}));
  PetscCall(PetscOptionsEList("-particle_volume",
                              "Cells a particle's volume is counted in: centre (all of it in its "
                              "centre's cell) or overlap (the part of the sphere each cell holds; "
                              "for particles nearly as large as the cells)",
                              "", volumeRules, 2, volumeRules[volumeRule], &volumeRule, nullptr));
  PetscOptionsEnd();
  in->volume = volumeRule == 0 ? ParticleVolume::Centre : ParticleVolume::Overlap;
  if (helpRequested()) PetscFunctionReturn(PETSC_SUCCESS);

  PetscCheck(setDumps != setList, comm, PETSC_ERR_USER_INPUT,
             "Give the snapshots with exactly one of -dumps \"DIR/dump.*.gz\" or -dump_list FILE");
  PetscCheck(setTimes || (setDt && in->dumpDt > 0), comm, PETSC_ERR_USER_INPUT,
             "Give the snapshot times with -times FILE (index and time per line) or -dump_dt SECONDS (> 0)");
  PetscCheck(!(setTimes && setDt), comm, PETSC_ERR_USER_INPUT,
             "Give either -times or -dump_dt, not both");
  const std::string a = axis;
  PetscCheck(a == "x" || a == "y" || a == "z", comm, PETSC_ERR_USER_INPUT,
             "-vertical_axis %s is not known; use x, y or z", axis);
  PetscCheck(gravitySign == 1 || gravitySign == -1, comm, PETSC_ERR_USER_INPUT,
             "-gravity_sign must be -1 (gravity towards -vertical_axis) or +1");
  PetscCheck(!setCells || (ncells == 3 && cells[0] > 0 && cells[1] > 0 && cells[2] > 0), comm,
             PETSC_ERR_USER_INPUT, "-mesh_cells takes three positive counts nx,ny,nz");
  PetscCheck((!setLo || nlo == 3) && (!setHi || nhi == 3), comm, PETSC_ERR_USER_INPUT,
             "-mesh_lo and -mesh_hi take three values each (x, y, z)");
  PetscCheck(setLo == setHi, comm, PETSC_ERR_USER_INPUT,
             "Give both -mesh_lo and -mesh_hi, or neither (the first snapshot's box)");
  PetscCheck(setCells || cellSize > 0, comm, PETSC_ERR_USER_INPUT,
             "The mesh needs -mesh_cells nx,ny,nz or -mesh_cell_size h (> 0)");
  PetscCheck(stride >= 1, comm, PETSC_ERR_USER_INPUT, "-frame_stride must be at least 1");
  PetscCheck(!setWindow || (nwindow == 2 && window[0] >= 0 && (window[1] < 0 || window[1] >= window[0])),
             comm, PETSC_ERR_USER_INPUT,
             "-window takes two snapshot indices first,last with 0 <= first <= last (last -1: to the end)");
  PetscCheck(in->solidDensity > 0, comm, PETSC_ERR_USER_INPUT, "-solid_density must be positive");
  PetscCheck(in->classTolerance >= 0 && in->classTolerance < 1, comm, PETSC_ERR_USER_INPUT,
             "-class_tolerance must be in [0, 1)");

  in->dumps = setDumps ? dumps : "";
  in->dumpList = setList ? list : "";
  in->timesFile = setTimes ? times : "";
  in->verticalAxis = a[0] - 'x';
  in->gravitySign = static_cast<int>(gravitySign);
  if (setCells)
    in->mesh.cells = std::array<int, 3>{static_cast<int>(cells[0]), static_cast<int>(cells[1]),
                                        static_cast<int>(cells[2])};
  in->mesh.cellSize = cellSize;
  if (setLo) {
    in->mesh.lo = Vec3{lo[0], lo[1], lo[2]};
    in->mesh.hi = Vec3{hi[0], hi[1], hi[2]};
  }
  in->stride = static_cast<int>(stride);
  in->first = static_cast<std::size_t>(window[0]);
  if (window[1] >= 0) in->last = static_cast<std::size_t>(window[1]);
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
