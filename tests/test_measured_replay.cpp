// -drift_model measured (issue 21): the replay drifts each fraction with the
// velocity the particle data show for its class in the sending cell's region
// and the step's frame.  Checked here:
// - the field rcfd build stores (RegionalDrift) on hand-made particles: per
//   region and class, velocities relative to each particle's cell bulk, a
//   class with no particle 0, counts and masses;
// - a hand-made two-frame database (two cells, identity shifts): one step of
//   each frame against the swaps worked out by hand (the lower cell sends the
//   rising fractions with its own velocity, the upper the sinking ones with
//   its own, the side that sent less tops up with its mixture; a class with
//   no particle in a cell does not drift there whatever velocity is stored;
//   frame 1 reverses frame 0);
// - a 4 x 1 x 12 bed with 2 x 1 x 3 regions and a random field over 6
//   frames against a face-by-face computation written here, to 1e-13 of the
//   largest mass, at 1 and 2 ranks; each fraction's total to 1e-12, no
//   negative mass, each cell's bulk kept;
// - refusals in one sentence: a database without the field, a fraction no
//   stored class matches within 1 %, -drift_agitation with it.
#include "check.hpp"
#include "box_meshes.hpp"
#include "fraction_sets.hpp"
#include "analysis/regional_drift.hpp"
#include "rcfd/measured_drift_field.hpp"
#include "rcfd/swaps.hpp"
#include "state_access.hpp"
#include "database/database_file_writer.hpp"

#include <cmath>
#include <random>

using namespace rcfd;
using rcfd::test::gatherNatural;
using rcfd::test::setNatural;

namespace {

constexpr double kDt = 5e-3, kRho = 1440.0;
std::string dir;
int counter = 0;

BoxSpec box(int nx, int nz, double h) {
  BoxSpec s;
  s.nx = nx, s.ny = 1, s.nz = nz;
  s.length = {nx * h, h, nz * h};
  return s;
}

// A database of `frames` identity shifts with alpha_s 0.5 and, unless
// `layout` is empty, the measured drift field (written as rcfd build does).
std::unique_ptr<Database> fieldDb(const BoxSpec &spec, int frames, const std::vector<double> &layout,
                                  const std::vector<double> &field) {
  const std::string path = dir + "/measured_" + std::to_string(counter++) + ".h5";
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  const Mesh mesh = rcfd::test::boxMesh(spec);
  if (rank == 0) {
    DatabaseFileWriter w(path, mesh, DatabaseMetadata{});
    FrameRecord f;
    f.alphaS.assign(mesh.numCells(), 0.5);
    f.shift = shiftFromTransfers(mesh.numCells(), {}, {}, {});
    for (int k = 0; k < frames; ++k) w.append(f);
    if (!layout.empty()) {
      w.writeMatrix(kMeasuredDriftLayoutName, layout, static_cast<int>(layout.size()), "test");
      w.writeMatrix(kMeasuredDriftFieldName, field, 3 * static_cast<int>(layout.size() - 3), "test");
    }
    w.finish();
  }
  MPI_Barrier(PETSC_COMM_WORLD);
  std::unique_ptr<Database> db;
  PetscCallAbort(PETSC_COMM_WORLD, Database::load(PETSC_COMM_WORLD, path, DatabaseLoadOptions{}, &db));
  return db;
}

// A drift operator of -drift_model measured, and one more option when given.
std::unique_ptr<DriftOperator> measuredDrift(const std::string &option = "", const std::string &value = "") {
  auto op = std::make_unique<DriftOperator>();
  const std::string prefix = "m" + std::to_string(counter++) + "_";
  std::string options = "-" + prefix + "model measured";
  if (!option.empty()) options += " -" + prefix + option + " " + value;
  PetscCallAbort(PETSC_COMM_WORLD, PetscOptionsInsertString(nullptr, options.c_str()));
  op->setOptionsPrefix(prefix);
  PetscCallAbort(PETSC_COMM_WORLD, op->setFromOptions(PETSC_COMM_WORLD));
  return op;
}

std::string refusal(PetscErrorCode ierr) {
  char *text = nullptr;
  PetscErrorMessage(ierr, nullptr, &text);
  return ierr && text ? text : "";
}

// Steps of the frames given, from natural-ordered masses; natural masses back.
std::vector<double> stepFrames(const Database &db, DriftOperator &op, const std::vector<double> &m0, int nf,
                               const std::vector<int> &frames) {
  FractionState st;
  PetscCallAbort(PETSC_COMM_WORLD, st.create(db.layout(), nf));
  setNatural(db, st, m0);
  StepInfo info;
  info.dt = kDt;
  for (std::size_t s = 0; s < frames.size(); ++s) {
    info.step = static_cast<long>(s), info.frame = frames[s];
    PetscCallAbort(PETSC_COMM_WORLD, op.apply(info, st));
  }
  return gatherNatural(db, st.masses(), nf);
}

ParticleSnapshot particles(const std::vector<double> &x, const std::vector<double> &z,
                           const std::vector<double> &d) {
  ParticleSnapshot s;
  for (std::size_t p = 0; p < x.size(); ++p) {
    s.id.push_back(static_cast<int64_t>(p));
    s.type.push_back(1);
    s.position.push_back({x[p], 0.005, z[p]});
    s.diameter.push_back(d[p]);
    s.mass.push_back(d[p] > 2e-3 ? 8.0 : 1.0);
  }
  return s;
}

// Two cells side by side in one region (2 x 1 x 1), a third cell above in
// another.  Cell 0: a small (mass 1) rising 3 mm and a large (8) sinking
// 1 mm; cell 1: a small rising 1 mm alone; cell 2: a large alone.  Relative
// to its own cell's bulk the small of cell 0 moves 3 - (3 - 8)/9 mm, the one
// of cell 1 nothing; the region's small class is their mass-weighted mean.
void recordedField() {
  SizeClasses classes;
  classes.diameter = {1e-3, 3e-3};
  BoxSpec b;
  b.nx = 2, b.ny = 1, b.nz = 2;
  b.length = {0.02, 0.01, 0.02};
  RegionalDrift field(classes, AxisMap{}, b, {2, 1, 1});
  const double dt = 0.01;
  field.add(particles({0.005, 0.005, 0.015, 0.005}, {0.005, 0.005, 0.005, 0.015}, {1e-3, 3e-3, 1e-3, 3e-3}),
            particles({0.005, 0.005, 0.015, 0.005}, {0.008, 0.004, 0.006, 0.015}, {1e-3, 3e-3, 1e-3, 3e-3}), dt);
  const std::vector<double> &t = field.table();
  RCFD_CHECK(t.size() == 2 * 6 && field.framesAdded() == 1 && field.columns() == 6);
  const double bulk0 = (3e-3 - 8e-3) / 9.0;
  const double small = (1.0 * (3e-3 - bulk0) / dt + 1.0 * 0.0) / 2.0, large = (-1e-3 - bulk0) / dt;
  RCFD_CHECK_CLOSE(t[0], small, 1e-12);
  RCFD_CHECK(t[1] == 2.0 && t[2] == 2.0);
  RCFD_CHECK_CLOSE(t[3], large, 1e-12);
  RCFD_CHECK(t[4] == 1.0 && t[5] == 8.0);
  // Region 1 (cells 2 and 3): one large particle at rest relative to itself, no small one.
  RCFD_CHECK(t[6] == 0.0 && t[7] == 0.0 && t[8] == 0.0 && t[9] == 0.0 && t[10] == 1.0 && t[11] == 8.0);
  // No net flux relative to the bulk: sum m u over the region is 0.
  RCFD_CHECK_CLOSE(t[0] * t[2] + t[3] * t[5], 0.0, 1e-12);
  const std::vector<double> layout = field.layoutRow();
  RCFD_CHECK(layout == (std::vector<double>{2, 1, 1, 1e-3, 3e-3}));
}

// Two cells (0 below 1), 1 cm cubes (A/V = 100 1/m), 50/50 of 1 and 3 mm.
// Frame 0: cell 0 u = (+0.02, -0.02), cell 1 u = (+0.01, -0.03) m/s.  The
// lower cell sends p = m 0.02 * 100 * dt = 0.01 m of the small fraction, the
// upper 0.015 m of the large; the lower tops up 0.005 m of its 50/50 mixture;
// the net is 0.0125 m of small up and as much large down.
// Frame 1: cell 0 small count 0 (stored 0.5 must be ignored), large -0.01;
// cell 1 small -0.02, large +0.02: only the upper cell's small sinks, with
// 0.01 of its small mass; the lower tops up with its own mixture.
void handValues() {
  const std::vector<double> layout{1, 1, 1, 1e-3, 3e-3};
  const std::vector<double> field{
      0.02, 5, 1e-6, -0.02, 5, 1e-6,  // frame 0, cell 0: (velocity, particles, mass) per class
      0.01, 5, 1e-6, -0.03, 5, 1e-6,  // frame 0, cell 1
      0.5, 0, 0.0, -0.01, 3, 1e-6,    // frame 1, cell 0: no small particle
      -0.02, 4, 1e-6, 0.02, 4, 1e-6}; // frame 1, cell 1
  auto db = fieldDb(box(1, 2, 0.01), 2, layout, field);
  FractionSet set = rcfd::test::fractionSet({1e-3, 3e-3}, {0.5, 0.5});
  RunContext ctx{*db, set, kRho};
  auto drift = measuredDrift();
  RCFD_CHECK(drift->needed(ctx));
  PetscCallAbort(PETSC_COMM_WORLD, drift->setUp(ctx));
  const double m = 0.5 * kRho * 0.5 * 1e-6; // each fraction in each cell
  const std::vector<double> m0{m, m, m, m};
  const auto a = stepFrames(*db, *drift, m0, 2, {0});
  const double x0 = 0.0125 * m;
  const std::vector<double> expect0{m - x0, m + x0, m + x0, m - x0};
  for (int j = 0; j < 4; ++j) RCFD_CHECK_CLOSE(a[j], expect0[j], 1e-14 * m);
  // Frame 1 from there: the upper cell sends 0.01 of its small mass down; the
  // lower cell tops up the same bulk in its own proportions.
  const auto b = stepFrames(*db, *drift, a, 2, {1});
  const double sent = 0.01 * a[2], lower = a[0] + a[1];
  const std::vector<double> expect1{a[0] + sent - sent * a[0] / lower, a[1] - sent * a[1] / lower,
                                    a[2] - sent + sent * a[0] / lower, a[3] + sent * a[1] / lower};
  for (int j = 0; j < 4; ++j) RCFD_CHECK_CLOSE(b[j], expect1[j], 1e-14 * m);
  // Two steps through the operator equal the two steps above.
  const auto both = stepFrames(*db, *drift, m0, 2, {0, 1});
  for (int j = 0; j < 4; ++j) RCFD_CHECK_CLOSE(both[j], expect1[j], 1e-14 * m);
  PetscPrintf(PETSC_COMM_WORLD, "hand values: frame 0 moves %.4e kg each way, frame 1 %.4e kg of small down\n", x0,
              sent);
}

// The face-by-face swaps of one sub-step, written plainly: per vertical face
// of the box (natural cells), the lower cell sends the rising fractions with
// its region's velocities, the upper the sinking ones, the smaller side tops
// up, the face limiter as in docs/drift.md.
std::vector<double> referenceStep(const BoxSpec &b, const DriftRegions &regions, const std::vector<double> &u,
                                  int nf, std::vector<double> m, double dt, int substeps) {
  const double h = b.length[2] / b.nz, aOverV = 1.0 / h;
  const double faceShare = 0.999 * 0.5 / 2; // max_share 0.5, two vertical faces per inner cell
  for (int s = 0; s < substeps; ++s) {
    std::vector<double> change(m.size(), 0.0);
    for (int k = 0; k + 1 < b.nz; ++k)
      for (int i = 0; i < b.nx; ++i) {
        const int L = i + b.nx * k, U = L + b.nx;
        const double *uL = &u[regions.regionOf(b, L) * nf], *uU = &u[regions.regionOf(b, U) * nf];
        double ML = 0, MU = 0, pL = 0, pU = 0;
        for (int f = 0; f < nf; ++f) {
          ML += m[L * nf + f], MU += m[U * nf + f];
          pL += m[L * nf + f] * std::max(uL[f], 0.0) * aOverV * dt / substeps;
          pU += m[U * nf + f] * std::max(-uU[f], 0.0) * aOverV * dt / substeps;
        }
        const double X = std::max(pL, pU), floor = 1e-3 * kRho * h * h * h; // alpha_min's mass
        if (!(X > 0) || ML < floor || MU < floor) continue;
        const double lambda = std::min(1.0, faceShare * std::min(ML, MU) / X);
        for (int f = 0; f < nf; ++f) {
          const double up = lambda * (m[L * nf + f] * std::max(uL[f], 0.0) * aOverV * dt / substeps +
                                      (X - pL) * m[L * nf + f] / ML);
          const double down = lambda * (m[U * nf + f] * std::max(-uU[f], 0.0) * aOverV * dt / substeps +
                                        (X - pU) * m[U * nf + f] / MU);
          change[L * nf + f] += down - up;
          change[U * nf + f] += up - down;
        }
      }
    for (std::size_t j = 0; j < m.size(); ++j) m[j] += change[j];
  }
  return m;
}

// A 4 x 1 x 12 bed, regions of 2 x 1 x 3 cells, 3 fractions, 6 frames of
// random velocities (frame 3 up to 2 m/s: 4 sub-steps, limiter acting),
// some classes without particles; random masses.
void againstReference() {
  const BoxSpec b = box(4, 12, 0.005);
  const DriftRegions regions{2, 1, 3};
  const int R = regions.count(b), K = 6, nf = 3;
  RCFD_CHECK(R == 8);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<double> layout{2, 1, 3, 1.4e-3, 2.3e-3, 2.9e-3, 3.6e-3}; // a stored class the run does not use
  std::vector<double> field;
  for (int k = 0; k < K; ++k)
    for (int r = 0; r < R; ++r)
      for (int c = 0; c < 4; ++c) {
        const bool empty = U(rng) < 0.15;
        field.insert(field.end(), {(U(rng) - 0.5) * (k == 3 ? 4.0 : 0.1), empty ? 0.0 : 3.0, empty ? 0.0 : 1e-5});
      }
  auto db = fieldDb(b, K, layout, field);
  FractionSet set = rcfd::test::fractionSet({1.4e-3, 2.31e-3, 3.6e-3}, {0.3, 0.4, 0.3}); // 2.31 mm matches 2.3 within 1 %
  RunContext ctx{*db, set, kRho};
  auto drift = measuredDrift();
  PetscCallAbort(PETSC_COMM_WORLD, drift->setUp(ctx));
  std::vector<double> m0;
  for (int c = 0; c < b.nx * b.nz; ++c)
    for (int f = 0; f < nf; ++f) m0.push_back((c % 7 == 3 ? 1e-4 : 1.0) * (0.2 + U(rng)) * 1e-5);
  std::vector<int> frames{0, 1, 2, 3, 4, 5, 3, 1};
  const auto got = stepFrames(*db, *drift, m0, nf, frames);
  const int classOf[3] = {0, 1, 3};
  std::vector<double> want = m0;
  for (int k : frames) {
    std::vector<double> u(R * nf);
    double largest = 0.0;
    for (int r = 0; r < R; ++r)
      for (int f = 0; f < nf; ++f) {
        const double *v = &field[((k * R + r) * 4 + classOf[f]) * 3];
        u[r * nf + f] = v[1] > 0 ? v[0] : 0.0;
      }
    for (int r = 0; r < R; ++r) // the sub-step rule takes the frame's largest over every stored class used
      for (int f = 0; f < nf; ++f) largest = std::max(largest, std::fabs(u[r * nf + f]));
    const int substeps = std::max(1, static_cast<int>(std::ceil(largest * (1.0 / 0.005) * kDt / 0.5)));
    want = referenceStep(b, regions, u, nf, want, kDt, substeps);
  }
  double worst = 0.0, scale = 0.0, negative = 0.0;
  std::vector<double> total0(nf, 0.0), total(nf, 0.0);
  for (std::size_t j = 0; j < got.size(); ++j) {
    worst = std::max(worst, std::fabs(got[j] - want[j]));
    scale = std::max(scale, m0[j]);
    negative = std::min(negative, got[j]);
    total0[j % nf] += m0[j], total[j % nf] += got[j];
  }
  double bulk = 0.0, moved = 0.0;
  for (int c = 0; c < b.nx * b.nz; ++c) {
    double before = 0.0, after = 0.0;
    for (int f = 0; f < nf; ++f) before += m0[c * nf + f], after += got[c * nf + f];
    bulk = std::max(bulk, std::fabs(after - before) / scale);
    moved = std::max(moved, std::fabs(got[c * nf] - m0[c * nf]) / scale);
  }
  PetscPrintf(PETSC_COMM_WORLD,
              "against the face-by-face swaps: %.1e of the largest mass, bulk per cell %.1e, moved %.2e, "
              "sub-steps %d over %ld steps\n",
              worst / scale, bulk, moved, (int)drift->substepsTaken(), drift->stepsTaken());
  RCFD_CHECK(worst < 1e-13 * scale);
  RCFD_CHECK(bulk < 1e-14);
  RCFD_CHECK(moved > 1e-3); // the field did move mass
  RCFD_CHECK(negative >= 0.0);
  for (int f = 0; f < nf; ++f) RCFD_CHECK(std::fabs(total[f] - total0[f]) <= 1e-12 * total0[f]);
  RCFD_CHECK(drift->substepsTaken() > drift->stepsTaken()); // frame 3 needs more than one
}

void refusals() {
  FractionSet set = rcfd::test::fractionSet({1e-3, 3e-3}, {0.5, 0.5});
  auto without = fieldDb(box(1, 2, 0.01), 2, {}, {});
  {
    RunContext ctx{*without, set, kRho};
    auto drift = measuredDrift();
    const std::string text = refusal(drift->setUp(ctx));
    PetscPrintf(PETSC_COMM_WORLD, "no field: %s\n", text.c_str());
    RCFD_CHECK(text.find("has no measured drift field") != std::string::npos);
    RCFD_CHECK(text.find(without->path()) != std::string::npos);
  }
  const std::vector<double> layout{1, 1, 1, 1e-3, 3e-3};
  const std::vector<double> field(2 * 2 * 6, 0.0);
  auto db = fieldDb(box(1, 2, 0.01), 2, layout, field);
  {
    FractionSet other = rcfd::test::fractionSet({1e-3, 2.95e-3}, {0.5, 0.5}); // 1.7 % from 3 mm
    RunContext ctx{*db, other, kRho};
    auto drift = measuredDrift();
    const std::string text = refusal(drift->setUp(ctx));
    PetscPrintf(PETSC_COMM_WORLD, "mismatch: %s\n", text.c_str());
    RCFD_CHECK(text.find("fraction 1 (2.95 mm) matches no class") != std::string::npos);
  }
  {
    RunContext ctx{*db, set, kRho};
    auto drift = measuredDrift("agitation", "leaving");
    const std::string text = refusal(drift->setUp(ctx));
    PetscPrintf(PETSC_COMM_WORLD, "with agitation: %s\n", text.c_str());
    RCFD_CHECK(text.find("do not apply") != std::string::npos);
  }
}

} // namespace

int main(int argc, char **argv) {
  return rcfd::test::rankTestMain(argc, argv, "measured_replay", [](const std::string &d) {
    dir = d;
    recordedField();
    handValues();
    againstReference();
    refusals();
    return 0;
  });
}
