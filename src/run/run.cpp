#include "rcfd/run.hpp"

#include "util/collective.hpp"
#include "util/h5.hpp"

#include <petscviewerhdf5.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

namespace rcfd {
namespace {

std::vector<std::string> splitList(const std::string &text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

std::string formatRow(const BedSample &s, int digits) {
  std::ostringstream row;
  row.precision(digits);
  row << s.time << ',' << s.zCogBed;
  for (double z : s.zCog) row << ',' << z;
  row << ',' << s.deltaZ;
  for (double m : s.mass) row << ',' << m;
  row << ',' << s.minMass;
  return row.str();
}

} // namespace

Run::Run(MPI_Comm comm, const OperatorRegistry &registry) : comm(comm), registry(registry) {}
Run::~Run() = default;

PetscErrorCode Run::setFromOptions() {
  char text[PETSC_MAX_PATH_LEN];
  PetscBool set_;
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, nullptr, "rcfd run", "rcfd");
  text[0] = '\0';
  PetscCall(PetscOptionsString("-db", "Database file (HDF5), e.g. from rcfd synth", "", "", text,
                               sizeof text, &set_));
  if (set_) dbPath = text;
  PetscCall(PetscOptionsReal("-t_end", "Simulated time to run [s] (default: one pass over the frames)",
                             "", tEnd, &tEnd, nullptr));
  PetscCall(PetscOptionsString("-output_dir", "Directory for results", "", outputDir.c_str(), text,
                               sizeof text, &set_));
  if (set_) outputDir = text;
  PetscCall(PetscOptionsString("-pipeline", "Operators applied each step, in order", "",
                               pipelineSpec.c_str(), text, sizeof text, &set_));
  if (set_) pipelineSpec = text;
  PetscCall(PetscOptionsInt("-monitor_every", "Steps between rows of cog.csv", "", monitorEvery,
                            &monitorEvery, nullptr));
  PetscCall(PetscOptionsInt("-monitor_digits", "Significant digits in cog.csv", "", csvDigits,
                            &csvDigits, nullptr));
  PetscCall(PetscOptionsBool("-fields", "Write HDF5 + XDMF fields", "", writeFields, &writeFields,
                             nullptr));
  PetscCall(PetscOptionsReal("-fields_every", "Simulated time between field outputs [s] (0: start and end only)",
                             "", fieldsEvery, &fieldsEvery, nullptr));
  PetscCall(PetscOptionsString("-init", "Initial state: mixed, layered or file", "",
                               initKind.c_str(), text, sizeof text, &set_));
  if (set_) initKind = text;
  PetscCall(PetscOptionsString("-init_file", "HDF5 file with dataset /masses [cells x fractions] in kg",
                               "", "", text, sizeof text, &set_));
  if (set_) initFile = text;
  PetscCall(PetscOptionsReal("-solid_density", "Particle density [kg/m^3] (default: the database's)",
                             "", solidDensity, &solidDensity, nullptr));
  PetscCall(PetscOptionsBool("-quiet", "No progress or summary output", "", quiet, &quiet, nullptr));
  PetscCall(PetscOptionsReal("-progress_interval", "Wall seconds between progress lines", "",
                             progressInterval, &progressInterval, nullptr));
  PetscOptionsEnd();
  PetscCheck(!dbPath.empty(), comm, PETSC_ERR_USER_INPUT,
             "No database given: pass -db FILE (make one with 'rcfd synth -o FILE')");
  PetscCheck(monitorEvery >= 1, comm, PETSC_ERR_USER_INPUT, "-monitor_every must be at least 1");
  PetscCheck(initKind == "mixed" || initKind == "layered" || initKind == "file", comm,
             PETSC_ERR_USER_INPUT, "-init %s is not known; use mixed, layered or file", initKind.c_str());
  PetscCheck(initKind != "file" || !initFile.empty(), comm, PETSC_ERR_USER_INPUT,
             "-init file needs -init_file FILE");
  PetscCall(Database::optionsFromCommandLine(&loadOptions));
  PetscCall(FractionSet::fromOptions(comm, &set));

  std::vector<std::unique_ptr<Operator>> created;
  PetscCall(collectively(
      comm,
      [&] {
        for (const auto &name : splitList(pipelineSpec)) created.push_back(registry.create(name));
      },
      PETSC_ERR_USER_INPUT));
  for (auto &op : created) PetscCall(ops.add(std::move(op)));
  PetscCall(ops.setFromOptions(comm));
  PetscCall(ledger.setFromOptions(comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Run::setUp() {
  PetscFunctionBeginUser;
  PetscCall(Database::load(comm, dbPath, loadOptions, &db));
  if (solidDensity <= 0) solidDensity = db->metadata().solidDensity;
  if (tEnd < 0) tEnd = db->numFrames() * db->metadata().dtRec;
  steps = std::lround(tEnd / db->metadata().dtRec);
  PetscCall(fstate.create(db->layout(), set.size()));
  PetscCall(initialState());
  RunContext ctx{*db, set, solidDensity};
  PetscCall(ops.setUp(ctx));
  PetscCall(cog.setUp(*db, set));
  PetscCall(makeDirectories(comm, outputDir));
  std::string header = "time_s,z_cog_bed_m";
  for (int i = 0; i < set.size(); ++i) header += ",z_cog_" + set.label(i) + "_m";
  header += ",delta_z_m";
  for (int i = 0; i < set.size(); ++i) header += ",mass_" + set.label(i) + "_kg";
  header += ",min_cell_mass_kg";
  csv = std::make_unique<CsvSeries>(comm, outputDir + "/cog.csv", header);
  if (writeFields) PetscCall(fields.setUp(*db, set, solidDensity, outputDir, fstate.masses()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Run::initialState() {
  const int nf = set.size();
  const Layout &L = db->layout();
  const auto &vol = db->localVolumes();
  PetscFunctionBeginUser;
  if (initKind == "file") {
    // Dimensions first, so that a mismatch gets a sentence rather than a
    // PETSc size error.
    PetscCall(collectively(comm, [&] {
      // Opened on every rank without MPI-IO: only its header is read here.
      auto f = h5::File::openRead(initFile, MPI_COMM_NULL);
      const auto dims = f.extents("/masses");
      if (dims.size() != 2 || dims[0] != (hsize_t)L.numCells() || dims[1] != (hsize_t)nf)
        throw std::runtime_error("-init_file '" + initFile + "': /masses should be " +
                                 std::to_string(L.numCells()) + " cells x " + std::to_string(nf) +
                                 " fractions to match the database and -fractions_diameters");
    }));
    OwnedVec natural;
    OwnedScatter scatter;
    OwnedViewer v;
    PetscCall(L.naturalScatter(nf, fstate.masses(), natural.put(), scatter.put()));
    PetscCall(PetscObjectSetName((PetscObject)natural.get(), "masses"));
    PetscCall(PetscViewerHDF5Open(comm, initFile.c_str(), FILE_MODE_READ, v.put()));
    PetscCall(VecLoad(natural, v));
    PetscCall(VecScatterBegin(scatter, natural, fstate.masses(), INSERT_VALUES, SCATTER_REVERSE));
    PetscCall(VecScatterEnd(scatter, natural, fstate.masses(), INSERT_VALUES, SCATTER_REVERSE));
    PetscReal low;
    PetscCall(VecMin(fstate.masses(), nullptr, &low));
    PetscCheck(low >= 0 && std::isfinite(low), comm, PETSC_ERR_USER_INPUT,
               "-init_file '%s': /masses has a negative or non-finite mass (%g kg)", initFile.c_str(),
               (double)low);
    PetscFunctionReturn(PETSC_SUCCESS);
  }

  const PetscScalar *alpha;
  PetscScalar *m;
  PetscCall(VecGetArrayRead(db->alphaS(0), &alpha));
  PetscCall(VecGetArrayWrite(fstate.masses(), &m));
  if (initKind == "mixed") {
    for (PetscInt c = 0; c < L.numLocal(); ++c)
      for (int i = 0; i < nf; ++i) m[c * nf + i] = set.massShare(i) * solidDensity * alpha[c] * vol[c];
  } else { // layered: largest at the bottom, each fraction a layer of its mass share
    // Every rank needs the bulk mass of all cells below its own: gather the
    // first frame's alpha_s in natural order on every rank (one vector).
    PetscCall(VecRestoreArrayRead(db->alphaS(0), &alpha));
    OwnedVec all;
    OwnedScatter toAll, nat;
    OwnedVec naturalAlpha;
    PetscCall(L.naturalScatter(1, db->alphaS(0), naturalAlpha.put(), nat.put()));
    PetscCall(VecScatterBegin(nat, db->alphaS(0), naturalAlpha, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(nat, db->alphaS(0), naturalAlpha, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterCreateToAll(naturalAlpha, toAll.put(), all.put()));
    PetscCall(VecScatterBegin(toAll, naturalAlpha, all, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(toAll, naturalAlpha, all, INSERT_VALUES, SCATTER_FORWARD));
    const PetscScalar *a;
    PetscCall(VecGetArrayRead(all, &a));
    const Mesh &mesh = db->mesh();
    const Vec3 g = db->metadata().gravity;
    auto height = [&](int c) {
      const Vec3 &x = mesh.cellCentre[c];
      return -(g[0] * x[0] + g[1] * x[1] + g[2] * x[2]);
    };
    std::vector<int> order(mesh.numCells());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int p, int q) { return height(p) < height(q); });
    std::vector<double> below(mesh.numCells());
    double total = 0.0;
    for (int c : order) {
      below[c] = total;
      total += solidDensity * a[c] * mesh.cellVolume[c];
    }
    std::vector<int> byDiameter(nf);
    std::iota(byDiameter.begin(), byDiameter.end(), 0);
    std::stable_sort(byDiameter.begin(), byDiameter.end(),
                     [&](int p, int q) { return set.diameter(p) > set.diameter(q); });
    for (PetscInt r = 0; r < L.numLocal(); ++r) {
      const int c = static_cast<int>(L.ownedNatural()[r]);
      const double lo = below[c], hi = lo + solidDensity * a[c] * mesh.cellVolume[c];
      double layerStart = 0.0;
      for (int i : byDiameter) {
        const double layerEnd = layerStart + set.massShare(i) * total;
        m[r * nf + i] = std::max(0.0, std::min(hi, layerEnd) - std::max(lo, layerStart));
        layerStart = layerEnd;
      }
    }
    PetscCall(VecRestoreArrayRead(all, &a));
    PetscCall(VecRestoreArrayWrite(fstate.masses(), &m));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(VecRestoreArrayRead(db->alphaS(0), &alpha));
  PetscCall(VecRestoreArrayWrite(fstate.masses(), &m));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Run::monitor(const StepInfo &step, double time) {
  PetscFunctionBeginUser;
  BedSample s;
  PetscCall(cog.measure(time, fstate.masses(), &s));
  samples.push_back(s);
  csv->add(formatRow(s, static_cast<int>(csvDigits)));
  (void)step;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Run::progress(long step, double time, bool last) {
  PetscFunctionBeginUser;
  if (quiet) PetscFunctionReturn(PETSC_SUCCESS);
  const double now = MPI_Wtime();
  if (!last && now - lastProgress < progressInterval) PetscFunctionReturn(PETSC_SUCCESS);
  lastProgress = now;
  const double elapsed = now - wallStart;
  const double rate = elapsed > 0 ? step / elapsed : 0.0;
  const double eta = rate > 0 ? (steps - step) / rate : 0.0;
  PetscCall(PetscPrintf(comm, "  t = %8.3f / %.3f s  step %ld/%ld  %8.0f steps/s  %6.1f s simulated per wall s  ETA %.1f s\n",
                        time, tEnd, step, steps, rate, rate * db->metadata().dtRec, eta));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Run::solve() {
  PetscFunctionBeginUser;
  const int K = db->numFrames();
  const double dt = db->metadata().dtRec;
  std::vector<double> initialMass;
  PetscCall(fstate.totals(&initialMass));
  const bool ledgerOn = ops.conservesMass();
  if (ledgerOn) PetscCall(ledger.start(fstate));
  StepInfo info;
  info.dt = dt;
  info.frame = 0;
  PetscCall(monitor(info, 0.0));
  if (writeFields) PetscCall(fields.write(0.0, 0, fstate.masses()));
  double nextFields = fieldsEvery > 0 ? fieldsEvery : INFINITY;
  wallStart = lastProgress = MPI_Wtime();
  double lastFlush = wallStart;
  for (long s = 0; s < steps; ++s) {
    info.step = s;
    info.time = s * dt;
    info.frame = static_cast<int>(s % K);
    info.nextFrame = static_cast<int>((s + 1) % K);
    info.jump = info.nextFrame != info.frame + 1;
    PetscCall(ops.apply(info, fstate));
    if (ledgerOn) PetscCall(ledger.check(s + 1, fstate));
    const double t = (s + 1) * dt;
    if ((s + 1) % monitorEvery == 0 || s + 1 == steps) PetscCall(monitor(info, t));
    if (writeFields && t >= nextFields - 1e-9 * dt && s + 1 < steps) {
      PetscCall(fields.write(t, info.nextFrame, fstate.masses()));
      nextFields += fieldsEvery;
    }
    if (MPI_Wtime() - lastFlush > 10.0) { // results so far survive an interruption
      PetscCall(csv->flush());
      lastFlush = MPI_Wtime();
    }
    PetscCall(progress(s + 1, t, false));
  }
  if (writeFields) PetscCall(fields.write(steps * dt, static_cast<int>(steps % K), fstate.masses()));
  PetscCall(csv->flush());
  PetscCall(progress(steps, steps * dt, true));

  PetscCall(ops.viewRequested(PETSC_VIEWER_STDOUT_(comm)));
  std::vector<double> finalMass;
  PetscCall(fstate.totals(&finalMass));
  double worst = 0.0;
  for (size_t i = 0; i < finalMass.size(); ++i)
    if (initialMass[i] > 0) worst = std::max(worst, std::fabs(finalMass[i] / initialMass[i] - 1.0));
  double low;
  PetscCall(fstate.minimum(&low));
  if (!quiet) {
    const double wall = MPI_Wtime() - wallStart;
    PetscCall(PetscPrintf(comm,
                          "Done: %ld steps, %.4g s simulated in %.3g s wall (%.3g wall s per simulated s)\n"
                          "  largest relative change of a fraction's mass: %.2e (round-off removed by the ledger: %.2e);"
                          " smallest cell mass: %.3g kg\n"
                          "  results: %s/cog.csv%s\n",
                          steps, steps * dt, wall, steps > 0 ? wall / (steps * dt) : 0.0, worst,
                          ledger.largestCorrection(), low,
                          outputDir.c_str(), writeFields ? (", " + outputDir + "/fields.xmf").c_str() : ""));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Run::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(db->view(viewer));
  PetscCall(set.view(viewer));
  PetscCall(ops.view(viewer));
  PetscCall(PetscViewerASCIIPrintf(viewer, "Run: %.4g s simulated in %ld steps, initial state %s, output in %s\n",
                                   tEnd, steps, initKind.c_str(), outputDir.c_str()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
