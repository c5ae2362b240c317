#include "cli/commands.hpp"
#include "base/checked_options.hpp"
#include "base/petsc_compat.hpp"
#include "mesh/box_mesh.hpp"

#include "analysis/span_statistics.hpp"
#include "builders/synthetic/synthetic_bed.hpp"
#include "builders/synthetic/two_phase_scaling.hpp"
#include "database/min_fluidization.hpp"
#include "rcfd/database.hpp"
#include "mesh/vessel_mesh.hpp"
#include "base/collective.hpp"
#include "base/atomic_file.hpp"
#include "database/database_file_writer.hpp"

#include <cmath>
#include <cstdio>
#include <string>

namespace rcfd::cli {
namespace {

/// The operating point that sets the bubbling (-synth_superficial_velocity,
/// -synth_min_fluidization_velocity); unset: the default bed as it is.
struct SynthOperatingPoint {
  PetscReal superficialVelocity = kSyntheticReferenceVelocity;
  PetscReal minFluidizationVelocity = NAN; // NaN: Wen & Yu at the reference inventory
  PetscBool velocitySet = PETSC_FALSE, minFluidizationSet = PETSC_FALSE;
  bool given() const { return velocitySet || minFluidizationSet; }
};

/// Where the per-frame series go (-synth_series), and whether the database is
/// skipped (-synth_series_only: long spans for stationarity, docs/synthetic.md).
struct SynthSeriesOutput {
  std::string path; // empty: none
  PetscBool only = PETSC_FALSE;
};

PetscErrorCode readSynthOptions(MPI_Comm comm, SyntheticBedOptions *o, std::string *path,
                                SynthOperatingPoint *point, SynthSeriesOutput *series, PetscBool *quiet) {
  char text[PETSC_MAX_PATH_LEN] = "default-bed.h5", seriesPath[PETSC_MAX_PATH_LEN] = "";
  PetscInt cells[3] = {o->box.nx, o->box.ny, o->box.nz}, ncells = 3;
  PetscReal length[3] = {o->box.length[0], o->box.length[1], o->box.length[2]};
  PetscInt nlength = 3, frames = o->numFrames, seed = static_cast<PetscInt>(o->seed),
           parcels = o->parcelsPerCell;
  PetscBool setCells = PETSC_FALSE, setLength = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, nullptr, "rcfd synth: the embedded default database", "rcfd");
  PetscCall(PetscOptionsString("-o", "Output database file", "", text, text, sizeof text, nullptr));
  PetscCall(checkedIntArray(PetscOptionsObject, "-synth_cells", "Cells nx,ny,nz", cells, &ncells, &setCells));
  PetscCall(checkedRealArray(PetscOptionsObject, "-synth_length", "Box size lx,ly,lz [m]", length, &nlength,
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
  const char *const nucleations[] = {"steady", "poisson"};
  PetscInt nucleation = static_cast<PetscInt>(o->nucleation);
  PetscCall(PetscOptionsEList("-synth_nucleation",
                              "Bubbles nucleate steadily over the distributor (stationary bed) or as a Poisson process"
                              " (the default)",
                              "", nucleations, 2, nucleations[nucleation], &nucleation, nullptr));
  o->nucleation = static_cast<SyntheticBedOptions::Nucleation>(nucleation);
  PetscInt strips = o->nucleationStrips;
  PetscCall(checkedInt(PetscOptionsObject, "-synth_nucleation_strips",
                       "Strips of the distributor along x that steady nucleation visits in shuffled rounds"
                       " (about a bubble wide)", &strips, 1, 1000));
  o->nucleationStrips = static_cast<int>(strips);
  // At most an hour: a larger warm-up (1e9 s) is a typo that would keep synth busy for days.
  constexpr ValueRange kWarmUp{0.0, 3600.0, true, true, "a time in [0, 3600] s"};
  PetscCall(checkedReal(PetscOptionsObject, "-synth_warm_up",
                        "Simulated time before frame 0 [s]", &o->warmUpTime, kWarmUp));
  PetscCall(checkedReal(PetscOptionsObject, "-synth_superficial_velocity",
                        "Superficial gas velocity U [m/s]: sets bubble sizes and nucleation by two-phase theory"
                        " (docs/synthetic.md; not given: the default bed, which stands for 1.1 m/s)",
                        &point->superficialVelocity, kPositive, &point->velocitySet));
  PetscCall(checkedReal(PetscOptionsObject, "-synth_min_fluidization_velocity",
                        "Minimum fluidization velocity U_mf [m/s] (nan: Wen & Yu at d32 = 2.026 mm,"
                        " the bi-wide inventory, with -gas_density and -gas_kinematic_viscosity)",
                        &point->minFluidizationVelocity, kPositive, &point->minFluidizationSet));
  PetscCall(PetscOptionsString("-synth_series",
                               "CSV of every frame's time, mean bed height and z_CoG (columns frame, t_s,"
                               " bed_height_m, z_cog_m)", "", seriesPath, seriesPath, sizeof seriesPath, nullptr));
  PetscCall(PetscOptionsBool("-synth_series_only",
                             "Run the bed for -synth_series and the report only: no database (long spans are"
                             " cheap without the shifts)", "", series->only, &series->only, nullptr));
  PetscCall(PetscOptionsBool("-quiet", "No report", "", *quiet, quiet, nullptr));
  PetscOptionsEnd();
  PetscCheck(!series->only || seriesPath[0], comm, PETSC_ERR_USER_INPUT,
             "-synth_series_only needs -synth_series FILE: without a database the series is the only output");
  series->path = seriesPath;
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

/// u_mf by Wen & Yu (1966), the answers' default correlation, of the inventory
/// the default bed stands for, in `gas`.
double referenceMinFluidization(const GasProperties &gas, double solidDensity, double gravity) {
  return minFluidizationVelocity(findUmfCorrelation("wen-yu"), kSyntheticReferenceSauterDiameter,
                                 solidDensity, gas, gravity);
}

/// Scales the bed's bubbles to the operating point (two_phase_scaling.hpp),
/// records u_sup in `conditions` and describes the point in `note`.  The
/// excess gas of the default bed is U_ref - U_mf of the reference inventory in
/// the default gas, so that -synth_superficial_velocity 1.1 alone is the
/// default bed, bit for bit.
PetscErrorCode applyOperatingPoint(MPI_Comm comm, SynthOperatingPoint point, OperatingConditions *conditions,
                                   SyntheticBedOptions *o, std::string *note) {
  PetscFunctionBeginUser;
  const double solidDensity = DatabaseMetadata{}.solidDensity;
  GasProperties gas;
  if (std::isfinite(conditions->gasDensity)) gas.density = conditions->gasDensity;
  if (std::isfinite(conditions->gasKinematicViscosity)) gas.kinematicViscosity = conditions->gasKinematicViscosity;
  PetscCheck(gas.density < solidDensity, comm, PETSC_ERR_USER_INPUT,
             "-gas_density %g kg/m^3 must be below the solid density %g kg/m^3", gas.density,
             solidDensity);
  const double referenceExcess =
      kSyntheticReferenceVelocity - referenceMinFluidization(GasProperties{}, solidDensity, o->gravity);
  const bool derived = !point.minFluidizationSet;
  if (derived) point.minFluidizationVelocity = referenceMinFluidization(gas, solidDensity, o->gravity);
  const double U = point.superficialVelocity, Umf = point.minFluidizationVelocity;
  PetscCheck(U > Umf, comm, PETSC_ERR_USER_INPUT,
             "-synth_superficial_velocity %g m/s must exceed the minimum fluidization velocity"
             " %g m/s (%s): below it the bed does not bubble",
             U, Umf, derived ? "Wen & Yu at d32 = 2.026 mm; -synth_min_fluidization_velocity sets it"
                             : "-synth_min_fluidization_velocity");
  PetscCheck(!std::isfinite(conditions->superficialVelocity) || conditions->superficialVelocity == U, comm,
             PETSC_ERR_USER_INPUT,
             "-superficial_velocity %g m/s and -synth_superficial_velocity %g m/s disagree; give one",
             conditions->superficialVelocity, U);
  const TwoPhaseScaling scaling = twoPhaseScaling((U - Umf) / referenceExcess);
  applyTwoPhaseScaling(scaling, o);
  conditions->superficialVelocity = U;
  char text[512];
  std::snprintf(text, sizeof text,
                "u_sup = %g m/s, u_mf = %.4g m/s (%s); excess gas %.4g times the default bed's (%.4g m/s):"
                " bubble diameters x%.4f, nucleation rate x%.4f, bubble hold-up predicted x%.4f",
                U, Umf, derived ? "Wen & Yu (1966) at d32 = 2.026 mm" : "given", scaling.excessRatio,
                referenceExcess, scaling.diameterFactor, scaling.nucleationFactor, scaling.holdUpFactor);
  *note = text;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/// "0.2670 / 0.2659 m (-0.4 %, +/- 0.9 % expected from the span)": a quantity over the two halves
/// and the standard error of their difference that a stationary bed's own correlation makes expected.
std::string halvesText(const HalvesDifference &d, double scale, const char *format, const char *unit) {
  char first[32], second[32], text[160];
  std::snprintf(first, sizeof first, format, scale * d.first);
  std::snprintf(second, sizeof second, format, scale * d.second);
  if (std::isfinite(d.standardError))
    std::snprintf(text, sizeof text, "%s / %s %s (%+.1f %%, +/- %.2g %% expected from the span)", first, second, unit,
                  100.0 * d.relative, 100.0 * d.standardError);
  else
    std::snprintf(text, sizeof text, "%s / %s %s (%+.1f %%)", first, second, unit, 100.0 * d.relative);
  return text;
}

/// Whether the span is statistically stationary, as its two halves see it
/// (docs/synthetic.md): mean bed height and Delta z_CoG of each half, each with the
/// standard error of the difference from batch means over the span (span_statistics.hpp).
void printHalves(MPI_Comm comm, const SyntheticBedReport &report) {
  if (report.surfaceHeight.size() < 2) return;
  const std::string height = halvesText(halvesOfMean(report.surfaceHeight), 1.0, "%.4f", "m");
  const std::string dynamics = halvesText(halvesOfMeanDeviation(report.centreOfGravity), 1e3, "%.3f", "mm");
  PetscCallVoid(PetscPrintf(comm, "Halves of the span: mean bed height %s, Delta z_CoG %s\n", height.c_str(),
                            dynamics.c_str()));
}

/// The per-frame series of the report as CSV (frame, t_s, bed_height_m, z_cog_m).
void writeSeries(const std::string &path, double dtRec, const SyntheticBedReport &report) {
  std::string text = "frame,t_s,bed_height_m,z_cog_m\n";
  char line[128];
  for (size_t k = 0; k < report.surfaceHeight.size(); ++k) {
    std::snprintf(line, sizeof line, "%zu,%.6f,%.9g,%.9g\n", k, static_cast<double>(k) * dtRec,
                  report.surfaceHeight[k], report.centreOfGravity[k]);
    text += line;
  }
  writeTextAtomically(path, text);
}

} // namespace

PetscErrorCode synthCommand(MPI_Comm comm) {
  SyntheticBedOptions options;
  SynthOperatingPoint point;
  SynthSeriesOutput series;
  std::string path, pointNote;
  PetscBool quiet = PETSC_FALSE;
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(readSynthOptions(comm, &options, &path, &point, &series, &quiet));
  PetscCall(options.vessel.setFromOptions(comm, options.box)); // -vessel: the whole box unless given
  Mesh vesselMesh; // the vessel's cells, cut once here (many cut cells take seconds to cut)
  PetscCall(collectively(comm, [&] { // shapes that hold every cell whole are the box: today's bed
    if (options.vessel.isWholeBox()) return;
    vesselMesh = cutVesselMesh(options.vessel, options.box);
    if (vesselMesh.isBox()) options.vessel = Vessel();
  }, PETSC_ERR_USER_INPUT));
  const Mesh *cut = options.vessel.isWholeBox() ? nullptr : &vesselMesh;
  OperatingConditions conditions; // recorded in the file when given (format version 2)
  PetscCall(OperatingConditions::fromOptions(comm, &conditions));
  if (helpRequested()) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(rejectUnusedOptions(comm, "synth"));
  if (point.given()) PetscCall(applyOperatingPoint(comm, point, &conditions, &options, &pointNote));
  PetscCall(collectively(comm, [&] { validateSyntheticBedOptions(options, cut); }, PETSC_ERR_USER_INPUT));

  // The generator is serial: rank 0 makes and writes the file, the others wait.
  SyntheticBedReport report;
  int cells = options.box.numCells();
  PetscCall(collectively(comm, [&] {
    if (rank != 0) return;
    if (series.only) {
      report = generateSyntheticBedSeries(options, cut);
      writeSeries(series.path, options.dtRec, report);
      return;
    }
    DatabaseMetadata meta;
    meta.dtRec = options.dtRec;
    meta.gravity = {0.0, 0.0, -options.gravity};
    meta.conditions = conditions;
    meta.source = "rcfd synth: kinematic stand-in for a bubbling bed (not physics), seed " +
                  std::to_string(options.seed);
    if (!pointNote.empty()) { // the conditions, for humans (the number is in the metadata)
      char at[64];
      std::snprintf(at, sizeof at, ", at u_sup = %g m/s", conditions.superficialVelocity);
      meta.source += at;
    }
    const Mesh mesh = cut ? *cut : boxMesh(options.box);
    cells = mesh.numCells();
    DatabaseFileWriter writer(path, mesh, meta);
    if (!pointNote.empty()) writer.setNote("synth_operating_point", pointNote);
    report = generateSyntheticBed(options, [&](const FrameRecord &frame) {
      writer.append(frame);
      if (!quiet && (writer.numFrames() % 50 == 0 || writer.numFrames() == options.numFrames))
        std::printf("  frame %d/%d\n", writer.numFrames(), options.numFrames), std::fflush(stdout);
    }, cut);
    writer.finish();
    if (!series.path.empty()) writeSeries(series.path, options.dtRec, report);
  }));
  if (!quiet && !pointNote.empty()) PetscCall(PetscPrintf(comm, "Operating point: %s\n", pointNote.c_str()));
  if (!quiet && series.only)
    PetscCall(PetscPrintf(comm, "Wrote %s: the series of %d frames every %g s (no database); mean bed height %.3f m\n",
                          series.path.c_str(), options.numFrames, options.dtRec, report.meanBedHeight));
  else if (!quiet)
    PetscCall(PetscPrintf(comm,
                          "Wrote %s: %d frames of %d cells every %g s; %ld parcels, largest alpha_s %.3f,"
                          " mean bed height %.3f m, %ld bubbles erupted, wrap mismatch %.2f %%\n",
                          path.c_str(), options.numFrames, cells, options.dtRec,
                          report.parcels, report.maxAlpha, report.meanBedHeight,
                          report.bubblesErupted, 100 * report.wrapMismatchRelative));
  if (!quiet) printHalves(comm, report); // rank 0 made the report; PetscPrintf prints rank 0's
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
