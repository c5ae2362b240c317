// The answers' monitors on a hand-made layered bed with known answers, on 1
// and 2 ranks: profiles, halves (median and fixed split), the bottom layer's
// d32 and u_mf with a zone, the warning at exactly the step where u_mf reaches
// u_sup and never again, Lacey's index, bed dynamics, a mid-plane snapshot,
// and profiles and halves equal to rcfd reference's counting of particles
// standing for the same state.
#include "check.hpp"
#include "box_meshes.hpp"
#include "fraction_sets.hpp"
#include "base/petsc_compat.hpp"
#include "state_access.hpp"

#include "analysis/particle_reference.hpp"
#include "base/h5.hpp"
#include "observable/answers.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

using namespace rcfd;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Rows of a CSV file (comment lines skipped), each as its fields; row 0 is the header.
std::vector<std::vector<std::string>> readCsv(const std::string &path) {
  std::vector<std::vector<std::string>> rows;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> fields;
    std::stringstream ss(line);
    std::string f;
    while (std::getline(ss, f, ',')) fields.push_back(f);
    rows.push_back(fields);
  }
  if (rows.empty()) test::fail(__FILE__, __LINE__, "no rows in " + path);
  return rows;
}

double number(const std::vector<std::vector<std::string>> &rows, int r, int c) {
  return std::stod(rows.at(r).at(c));
}

/// u_mf by Wen & Yu, computed here from the textbook formula.
double wenYu(double d, double rhoP) {
  const double rhoG = 1.189, mu = 1.189 * 1e-5, g = 9.81;
  const double ar = g * d * d * d * rhoG * (rhoP - rhoG) / (mu * mu);
  return (std::sqrt(33.7 * 33.7 + 0.0408 * ar) - 33.7) * mu / (rhoG * d);
}

struct Bed {
  std::unique_ptr<Database> db;
  FractionSet fractions = rcfd::test::fractionSet({1.5e-3, 3.0e-3}, {0.5, 0.5});
  FractionState state;
  double rho = 0.0;
  std::string out; // output directory of this test and rank count
  std::shared_ptr<LayerSampler> sampler = std::make_shared<LayerSampler>();
  RunContext run() const { return RunContext{*db, fractions, rho}; }
};

// 2 x 1 x 4 cells of 0.1 m; layer l's two cells hold (l + 1) kg each, split
// small/large as l0: 0/1, l1: 1/2, l2 and l3: all small (as test_layers).
PetscErrorCode makeBed(const std::string &dir, const std::string &name, Bed *bed) {
  PetscFunctionBeginUser;
  BoxSpec s;
  s.nx = 2;
  s.ny = 1;
  s.nz = 4;
  s.length = {0.2, 0.1, 0.4};
  int size;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  const std::string path = dir + "/answers_np" + std::to_string(size) + ".h5";
  test::writeIdentityDatabase(path, rcfd::test::boxMesh(s), std::vector<double>(8, 0.5), DatabaseMetadata{});
  PetscCall(Database::load(PETSC_COMM_WORLD, path, DatabaseLoadOptions{}, &bed->db));
  PetscCall(bed->state.create(bed->db->layout(), 2));
  const double share[4] = {0.0, 0.5, 1.0, 1.0};
  std::vector<double> natural(16);
  for (int c = 0; c < 8; ++c) {
    const int l = c / 2;
    natural[2 * c] = (l + 1) * share[l];
    natural[2 * c + 1] = (l + 1) * (1.0 - share[l]);
  }
  test::setNatural(*bed->db, bed->state, natural);
  bed->rho = bed->db->metadata().solidDensity;
  bed->out = dir + "/" + name + "_np" + std::to_string(size);
  PetscCall(makeDirectories(PETSC_COMM_WORLD, bed->out));
  PetscCall(bed->sampler->setUp(*bed->db));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode layeredBed(const std::string &dir) {
  PetscFunctionBeginUser;
  Bed bed;
  PetscCall(makeBed(dir, "answers", &bed));
  const double rho = bed.rho;
  const RunContext run = bed.run();
  const std::string &out = bed.out;

  const auto &sampler = bed.sampler;
  TimeWindow window{0.01, 0.02};
  ProfilesMonitor profiles(sampler, window);
  HalvesMonitor halves(sampler, window, std::numeric_limits<double>::quiet_NaN());
  ZoneSet zones;
  zones.add(Zone("second", Zone::Shape::Layers, {1, 1}));
  PetscCall(zones.setUp(bed.db->mesh(), bed.db->layout(), bed.db->metadata().gravity));
  GasProperties air;
  BottomLayerMonitor bottom(sampler, findUmfCorrelation("wen-yu"), air, 1.0, &zones, true);
  MixingMonitor mixing;
  BedDynamicsMonitor dynamics(sampler, true);
  SnapshotMonitor snapshot({0.01});
  std::vector<Monitor *> all{&profiles, &halves, &bottom, &mixing, &dynamics, &snapshot};
  for (Monitor *m : all) PetscCall(m->setUp(run, bed.state, out));
  // Lacey's n_c uses the inventory's shares: give the mixing monitor the bed's own (16 : 4 kg).
  const FractionSet inventory = rcfd::test::fractionSet({1.5e-3, 3.0e-3}, {0.8, 0.2});
  PetscCall(mixing.setUp(RunContext{*bed.db, inventory, rho}, bed.state, out));
  // Steps 0..4 every 5 ms: the window [0.01, 0.02] s holds steps 2, 3, 4.
  for (long step = 0; step <= 4; ++step) {
    const MonitorContext ctx{step, step * 0.005, 0, step == 4, bed.state, run, out};
    for (Monitor *m : all) PetscCall(m->sample(ctx));
  }
  for (Monitor *m : all) PetscCall(m->flush());
  PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));

  // Profiles: alpha_i = m_i / (rho V_layer), V_layer = 2e-3 m^3, the state constant.
  const auto p = readCsv(out + "/profiles.csv");
  RCFD_CHECK(p[0].size() == 4 && p[0][0] == "z" && p[0][1] == "alpha_d1.500mm" && p[0][3] == "alpha_total");
  RCFD_CHECK(p.size() == 5);
  const double small[4] = {0, 2, 6, 8}, large[4] = {2, 2, 0, 0};
  for (int l = 0; l < 4 && p.size() == 5; ++l) {
    RCFD_CHECK_CLOSE(number(p, l + 1, 0), 0.05 + 0.1 * l, 1e-12);
    RCFD_CHECK_CLOSE(number(p, l + 1, 1), small[l] / (rho * 2e-3), 1e-8);
    RCFD_CHECK_CLOSE(number(p, l + 1, 2), large[l] / (rho * 2e-3), 1e-8);
    RCFD_CHECK_CLOSE(number(p, l + 1, 3), (small[l] + large[l]) / (rho * 2e-3), 1e-8);
  }
  std::ifstream comment(out + "/profiles.csv");
  std::string first;
  std::getline(comment, first);
  RCFD_CHECK(first.find("mean over 3 samples in [0.01, 0.02] s") != std::string::npos);

  // Halves at the median layer 2: bottom 8/12 small, 4/12 large; top all small; d32 = 2 mm.
  const auto h = readCsv(out + "/halves.csv");
  RCFD_CHECK(h[0].size() == 5 && h[0][1] == "diameter" && h[0][2] == "bottom_mass_fraction" &&
             h[0][3] == "top_mass_fraction" && h[0][4] == "d_over_d32");
  RCFD_CHECK(h.size() == 3 && h[1][0] == "d1.500mm");
  if (h.size() == 3) {
    RCFD_CHECK_CLOSE(number(h, 1, 2), 8.0 / 12.0, 1e-8);
    RCFD_CHECK_CLOSE(number(h, 2, 2), 4.0 / 12.0, 1e-8);
    RCFD_CHECK(number(h, 1, 3) == 1.0 && number(h, 2, 3) == 0.0);
    RCFD_CHECK_CLOSE(number(h, 1, 4), 0.75, 1e-8);
    RCFD_CHECK_CLOSE(number(h, 2, 4), 1.5, 1e-8);
  }

  // Bottom layer: all large (3 mm), zone "second" = layer 1 (d32 2 mm); u_mf(3 mm) > 1 m/s.
  const auto b = readCsv(out + "/bottom.csv");
  RCFD_CHECK(b[0].size() == 6 && b[0][0] == "time_s" && b[0][1] == "d32_bottom_m" && b[0][2] == "umf_m_s" &&
             b[0][3] == "usup_m_s" && b[0][4] == "defluidized" && b[0][5] == "d32_second_m");
  RCFD_CHECK(b.size() == 6);
  if (b.size() == 6) {
    RCFD_CHECK_CLOSE(number(b, 1, 1), 3e-3, 1e-9);
    RCFD_CHECK_CLOSE(number(b, 1, 2), wenYu(3e-3, rho), 1e-9);
    RCFD_CHECK(number(b, 1, 3) == 1.0 && number(b, 1, 4) == 1.0 && number(b, 5, 4) == 1.0);
    RCFD_CHECK_CLOSE(number(b, 1, 5), 2e-3, 1e-9);
  }
  RCFD_CHECK(bottom.warning().fired() && bottom.warning().firstTime() == 0.0);

  // Lacey: cells (mass, small share) (1, 0), (2, 1/2), (3, 1), (4, 1), twice; p = 16/20.
  // s^2 = (1 0.64 + 2 0.09 + 3 0.04 + 4 0.04) / 10 = 0.11, s0^2 = 0.16,
  // sR^2 = s0^2 sum_c M_c (1 / n_c) / sum_c M_c with 1 / n_c = rho v_mean / M_c, so
  // sR^2 = s0^2 8 rho v_mean / 20 kg, v_mean = 1 / sum(w_i / v_i) with w = (0.8, 0.2).
  const double v1 = kPi / 6 * std::pow(1.5e-3, 3), v2 = kPi / 6 * std::pow(3e-3, 3);
  const double random = 0.16 * 8 * rho / (0.8 / v1 + 0.2 / v2) / 20;
  RCFD_CHECK(random > 1e-7); // far above the 1e-9 tolerance below: a wrong n_c shows
  const auto mx = readCsv(out + "/mixing.csv");
  RCFD_CHECK(mx[0].size() == 3 && mx[0][1] == "lacey_d1.500mm" && mx.size() == 6);
  if (mx.size() == 6) {
    RCFD_CHECK_CLOSE(number(mx, 3, 1), (0.16 - 0.11) / (0.16 - random), 1e-9);
    RCFD_CHECK_CLOSE(number(mx, 3, 2), (0.16 - 0.11) / (0.16 - random), 1e-9);
  }

  // Bed dynamics of a bed that does not move: z_CoG = sum m h / sum m = 5 / 20 m, Delta 0.
  const auto d = readCsv(out + "/bed_dynamics.csv");
  RCFD_CHECK(d.size() == 2 && d[0][1] == "mean_z_cog_m" && d[0][2] == "delta_z_cog_m");
  if (d.size() == 2) {
    RCFD_CHECK(number(d, 1, 0) == 5);
    RCFD_CHECK_CLOSE(number(d, 1, 1), 0.25, 1e-9);
    RCFD_CHECK(std::fabs(number(d, 1, 2)) < 1e-12);
  }

  // Snapshot at 0.01 s (step 2): the mesh's one y-layer, 8 cells, bottom row first.
  const auto snap = readCsv(out + "/snapshot_0.0100s.csv");
  RCFD_CHECK(snap.size() == 9 && snap[0][0] == "x_m" && snap[0][1] == "z_m");
  if (snap.size() == 9) {
    RCFD_CHECK_CLOSE(number(snap, 1, 0), 0.05, 1e-12);
    RCFD_CHECK_CLOSE(number(snap, 2, 0), 0.15, 1e-12);
    RCFD_CHECK_CLOSE(number(snap, 1, 3), 1.0 / (rho * 1e-3), 1e-8);     // 1 kg large in a 1e-3 m^3 cell
    RCFD_CHECK_CLOSE(number(snap, 8, 2), 4.0 / (rho * 1e-3), 1e-8);     // top layer: 4 kg small
  }

  // Halves split at a given height: 0.2 m leaves layers 0 and 1 (centres 0.05, 0.15) below.
  HalvesMonitor fixed(sampler, window, 0.2);
  PetscCall(fixed.setUp(run, bed.state, out + "/fixed"));
  PetscCall(makeDirectories(PETSC_COMM_WORLD, out + "/fixed"));
  const MonitorContext ctx{9, 0.015, 0, true, bed.state, run, out};
  PetscCall(fixed.sample(ctx));
  PetscCall(fixed.flush());
  PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
  const auto f = readCsv(out + "/fixed/halves.csv");
  // Below: small 0 + 2, large 2 + 2 -> 2/6, 4/6; above: all small.
  RCFD_CHECK(f.size() == 3);
  if (f.size() == 3) {
    RCFD_CHECK_CLOSE(number(f, 1, 2), 2.0 / 6.0, 1e-8);
    RCFD_CHECK_CLOSE(number(f, 2, 2), 4.0 / 6.0, 1e-8);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The warning fires at the step at which u_mf first reaches u_sup and never
// again, even when the bottom layer fines up and coarsens a second time.
PetscErrorCode warningOnce(const std::string &dir) {
  PetscFunctionBeginUser;
  Bed bed;
  PetscCall(makeBed(dir, "answers_warning", &bed));
  const double rho = bed.rho;
  const RunContext run = bed.run();
  const std::string &out = bed.out;
  // The bottom layer's large share at each step: d32 = 1 / (w / 3 mm + (1 - w) / 1.5 mm).
  const double largeShare[7] = {0.0, 0.3, 0.6, 0.8, 0.2, 0.9, 1.0};
  const auto d32 = [](double w) { return 1.0 / (w / 3e-3 + (1.0 - w) / 1.5e-3); };
  const double usup = wenYu(d32(0.6), rho); // reached exactly at step 2
  const auto &sampler = bed.sampler;
  ZoneSet none;
  BottomLayerMonitor bottom(sampler, findUmfCorrelation("wen-yu"), GasProperties{}, usup, &none, true);
  PetscCall(bottom.setUp(run, bed.state, out));
  int fired = 0;
  for (long step = 0; step < 7; ++step) {
    std::vector<double> natural(16, 0.0);
    natural[0] = natural[2] = 1.0 - largeShare[step]; // the two bottom cells, 1 kg each
    natural[1] = natural[3] = largeShare[step];
    natural[4] = 1.0; // one small-only cell above: the bed is more than its bottom layer
    test::setNatural(*bed.db, bed.state, natural);
    const bool before = bottom.warning().fired();
    PetscCall(bottom.sample(MonitorContext{step, step * 0.01, 0, false, bed.state, run, out}));
    if (bottom.warning().fired() && !before) {
      ++fired;
      RCFD_CHECK(step == 2);
    }
  }
  RCFD_CHECK(fired == 1);
  RCFD_CHECK(bottom.warning().firstTime() == 0.02);
  PetscCall(bottom.flush());
  PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
  const auto b = readCsv(out + "/bottom.csv");
  RCFD_CHECK(b.size() == 8);
  const double flags[7] = {0, 0, 1, 1, 0, 1, 1}; // the flag follows the state; the warning does not repeat
  for (int r = 0; r < 7 && b.size() == 8; ++r) RCFD_CHECK(number(b, r + 1, 4) == flags[r]);
  // A restored monitor does not warn again.
  BottomLayerMonitor again(sampler, findUmfCorrelation("wen-yu"), GasProperties{}, usup, &none, true);
  PetscCall(again.setUp(run, bed.state, out));
  PetscCall(again.restoreState(bottom.saveState()));
  RCFD_CHECK(again.warning().fired() && again.warning().firstTime() == 0.02);
  PetscFunctionReturn(PETSC_SUCCESS);
}

// Particles at the cell centres standing for the state (n particles of class i
// in a cell of mass n rho v_i): rcfd reference's profiles and halves equal the
// monitors' on the state.
PetscErrorCode sameAsReference(const std::string &dir) {
  PetscFunctionBeginUser;
  Bed bed;
  PetscCall(makeBed(dir, "answers_reference", &bed));
  const double rho = bed.rho;
  const RunContext run = bed.run();
  const std::string &out = bed.out;
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  const Mesh &mesh = bed.db->mesh();
  // Per cell: (2c mod 5) small and (c mod 3) large particles.
  ParticleSnapshot snap;
  std::vector<double> natural(16);
  for (int c = 0; c < 8; ++c)
    for (int i = 0; i < 2; ++i) {
      const int n = i == 0 ? (2 * c) % 5 : c % 3;
      const double d = bed.fractions.diameter(i), m = rho * kPi / 6 * d * d * d;
      natural[2 * c + i] = n * m;
      for (int k = 0; k < n; ++k) {
        snap.id.push_back(static_cast<int64_t>(snap.id.size()) + 1);
        snap.type.push_back(i + 1);
        snap.position.push_back(mesh.cellCentre[c]);
        snap.diameter.push_back(d);
        snap.mass.push_back(m);
      }
    }
  test::setNatural(*bed.db, bed.state, natural);
  if (rank == 0) {
    ReferenceOptions opt;
    opt.classes.diameter = {1.5e-3, 3.0e-3};
    opt.profileMesh = mesh.boxSpec();
    opt.volume = ParticleVolume::Centre; // the particles stand for the cells' masses
    ParticleReference reference(opt);
    reference.add(0.0, snap);
    reference.writeProfilesCsv(out + "/reference_profiles.csv");
    reference.writeHalvesCsv(out + "/reference_halves.csv");
  }
  const auto &sampler = bed.sampler;
  ProfilesMonitor profiles(sampler, TimeWindow{0, 0});
  HalvesMonitor halves(sampler, TimeWindow{0, 0}, std::numeric_limits<double>::quiet_NaN());
  for (Monitor *m : std::vector<Monitor *>{&profiles, &halves}) {
    PetscCall(m->setUp(run, bed.state, out));
    PetscCall(m->sample(MonitorContext{0, 0.0, 0, true, bed.state, run, out}));
    PetscCall(m->flush());
  }
  PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
  for (const char *name : {"profiles.csv", "halves.csv"}) {
    const auto mine = readCsv(out + "/" + name), theirs = readCsv(out + "/reference_" + name);
    RCFD_CHECK(mine.size() == theirs.size() && mine.size() > 2);
    for (std::size_t r = 0; r < std::min(mine.size(), theirs.size()); ++r)
      for (std::size_t c = 0; c < theirs[r].size(); ++c) { // the run adds d_over_d32 at the end of halves
        if (r == 0 || (c == 0 && std::string(name) == "halves.csv")) RCFD_CHECK(mine[r][c] == theirs[r][c]);
        else RCFD_CHECK_CLOSE(number(mine, r, c), number(theirs, r, c), 1e-8);
      }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

// Format version 2 stores the conditions a database was recorded at; a
// version 1 file (no conditions) is still read; a bad condition is refused.
PetscErrorCode formatVersions(const std::string &dir) {
  PetscFunctionBeginUser;
  int size, rank;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  BoxSpec s;
  s.nx = s.ny = 1;
  s.nz = 2;
  s.length = {0.1, 0.1, 0.2};
  DatabaseMetadata meta;
  meta.conditions.superficialVelocity = 1.2;
  meta.conditions.gasKinematicViscosity = 1.5e-5;
  const std::string stem = dir + "/answers_version_np" + std::to_string(size);
  test::writeIdentityDatabase(stem + "_2.h5", rcfd::test::boxMesh(s), {0.5, 0.5}, meta);
  test::writeIdentityDatabase(stem + "_1.h5", rcfd::test::boxMesh(s), {0.5, 0.5}, meta, 1, 2); // full CSR, as version 1
  test::writeIdentityDatabase(stem + "_bad.h5", rcfd::test::boxMesh(s), {0.5, 0.5}, meta);
  if (rank == 0) { // as rcfd 1 wrote it: version 1, no conditions
    h5::File one = h5::File::openReadWrite(stem + "_1.h5");
    one.writeAttr("/", "format_version", 1LL);
    H5Adelete_by_name(one.id(), "/metadata", "superficial_velocity", H5P_DEFAULT);
    H5Adelete_by_name(one.id(), "/metadata", "gas_kinematic_viscosity", H5P_DEFAULT);
    h5::File bad = h5::File::openReadWrite(stem + "_bad.h5");
    bad.writeAttr("/metadata", "gas_density", -1.0);
  }
  PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
  std::unique_ptr<Database> two, one, bad;
  PetscCall(Database::load(PETSC_COMM_WORLD, stem + "_2.h5", DatabaseLoadOptions{}, &two));
  const OperatingConditions &c = two->metadata().conditions;
  RCFD_CHECK(c.superficialVelocity == 1.2 && c.gasKinematicViscosity == 1.5e-5 && std::isnan(c.gasDensity));
  PetscCall(Database::load(PETSC_COMM_WORLD, stem + "_1.h5", DatabaseLoadOptions{}, &one));
  RCFD_CHECK(std::isnan(one->metadata().conditions.superficialVelocity));
  RCFD_CHECK(one->numFrames() == 1);
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, nullptr));
  const PetscErrorCode refused = Database::load(PETSC_COMM_WORLD, stem + "_bad.h5", DatabaseLoadOptions{}, &bad);
  PetscCall(PetscPopErrorHandler());
  char *text = nullptr;
  PetscErrorMessage(refused, nullptr, &text);
  RCFD_CHECK(refused != 0 && text && std::string(text).find("/metadata gas_density must be a positive number") !=
                                         std::string::npos);
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  RCFD_CHECK(argc > 1);
  const std::string dir = argc > 1 ? argv[1] : ".";
  RCFD_CHECK(layeredBed(dir) == 0);
  RCFD_CHECK(warningOnce(dir) == 0);
  RCFD_CHECK(sameAsReference(dir) == 0);
  RCFD_CHECK(formatVersions(dir) == 0);
  const int failed = test::globalFailures();
  PetscCall(PetscFinalize());
  return failed == 0 ? 0 : 1;
}
