// The granulation operators (rcfd/granulation.hpp):
//  - growth on a hand-made state: the transfers to the next larger class by
//    projected area, computed by hand, in transfer and number mode; limited
//    by a class's mass (never negative); nothing, and counted, when the spray
//    zone is empty;
//  - feed split by shares and by cell solid, held back while its zone is
//    empty and delivered whole later; discharge at local concentrations,
//    never more than the zone holds (emptied to exactly 0, the rest owed);
//    with -keep_bulk, the zone's cells keep their bulk and the change is
//    spread over the bed by one factor per fraction;
//  - a zone without solid in every frame is refused naming it;
//  - whole runs on small.h5: the per-class mass account closes to round-off
//    every step with growth, feed and discharge together (the ledger checks
//    every step at 1e-12), with a closed and an open top, and the bulk stays
//    with alpha_s; growth off, feed and discharge over the whole bed
//    with a feed composition unlike the holdup: the holdup converges to the
//    feed's composition exactly as e_n = e_0 (M / (M + m dt))^n, i.e. with
//    the residence time M / m as time constant;
//  - the steady-state criterion on a constructed product series.
// Runs at 1 and 2 ranks.  usage: test_granulation DATA_DIR SMALL_DB
#include "check.hpp"
#include "box_meshes.hpp"
#include "fraction_sets.hpp"
#include "rcfd/granulation.hpp"
#include "rcfd/run.hpp"
#include "scoped_options.hpp"
#include "state_access.hpp"
#include "base/csv.hpp"
#include "base/petsc_compat.hpp"
#include "operator/granulation/product_monitor.hpp"

#include <cmath>

using namespace rcfd;
using rcfd::test::gatherNatural;
using rcfd::test::setNatural;

namespace {

std::string dir, smallDb;
constexpr double kDt = 0.005;

bool contains(const std::string &text, const std::string &part) { return text.find(part) != std::string::npos; }

int col(const csv::Table &t, const std::string &name) {
  const int c = t.find({name});
  if (c < 0) std::fprintf(stderr, "%s has no column %s\n", t.path().c_str(), name.c_str());
  return c;
}

// 2 x 1 x 2 cells of 0.1 m: natural cells 0 (x0,z0), 1 (x1,z0), 2 (x0,z1), 3 (x1,z1);
// cell 3 never holds solid in the database.
struct Bed {
  std::unique_ptr<Database> db;
  FractionSet fractions = rcfd::test::fractionSet({2e-3, 1e-3, 4e-3}, {0.5, 0.3, 0.2}); // not sorted: next larger of 1 mm is 2 mm
  FractionState state;
  RunContext run() const { return RunContext{*db, fractions, 1440.0}; }
};

Bed makeBed() {
  BoxSpec s;
  s.nx = 2;
  s.ny = 1;
  s.nz = 2;
  s.length = {0.2, 0.1, 0.2};
  int size;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  const std::string path = dir + "/granulation_np" + std::to_string(size) + ".h5";
  test::writeIdentityDatabase(path, rcfd::test::boxMesh(s), {0.5, 0.5, 0.5, 0.0}, DatabaseMetadata{});
  Bed bed;
  PetscCallAbort(PETSC_COMM_WORLD, Database::load(PETSC_COMM_WORLD, path, DatabaseLoadOptions{}, &bed.db));
  PetscCallAbort(PETSC_COMM_WORLD, bed.state.create(bed.db->layout(), 3));
  return bed;
}

const std::string kZones = "-zones spray,inlet,outlet,bottom,dead -zone_spray_layers 1,1 -zone_bottom_layers 0,0 "
                           "-zone_inlet_box 0,0.1,0,0.1,0,0.1 -zone_outlet_box 0.1,0.2,0,0.1,0,0.1 "
                           "-zone_dead_box 0.1,0.2,0,0.1,0.1,0.2";

template <typename Op> void setUp(Op &op, const std::string &prefix, const Bed &bed, const std::string &options) {
  ScopedOptions o(kZones + " " + options);
  op.setOptionsPrefix(prefix);
  PetscCallAbort(PETSC_COMM_WORLD, op.setFromOptions(PETSC_COMM_WORLD));
  PetscCallAbort(PETSC_COMM_WORLD, op.setUp(bed.run()));
}

template <typename Op> void step(Op &op, Bed &bed) {
  StepInfo info;
  info.dt = kDt;
  PetscCallAbort(PETSC_COMM_WORLD, op.apply(info, bed.state));
}

void checkMasses(const Bed &bed, const std::vector<double> &expected, double tol, const char *what) {
  const std::vector<double> got = gatherNatural(*bed.db, bed.state.masses(), 3);
  for (std::size_t k = 0; k < expected.size(); ++k)
    if (!rcfd::test::close(got[k], expected[k], tol)) {
      std::fprintf(stderr, "%s: cell %zu class %zu: %.17g, expected %.17g\n", what, k / 3, k % 3, got[k], expected[k]);
      RCFD_CHECK(false);
    }
}

// Spray zone = cells 2 and 3.  Projected area ~ m_i / d_i: cell 2
// 0.3/2e-3 + 0.2/1e-3 + 0.1/4e-3 = 375, cell 3 25 + 400 = 425, A = 800 (per m).
// c m_g dt = 0.01 * 2 * 0.005 = 1e-4 kg, k = 1e-4 / 800 = 1.25e-7:
//   cell 2: 2 mm -> 4 mm: k 150 = 1.875e-5, 1 mm -> 2 mm: k 200 = 2.5e-5
//   cell 3: 2 mm -> 4 mm: k 25 = 3.125e-6,  1 mm -> 2 mm: k 400 = 5e-5
void growthByHand() {
  const std::vector<double> start{1, 1, 1, 1, 1, 1, 0.3, 0.2, 0.1, 0.05, 0.4, 0.0};
  for (const bool number : {false, true}) {
    Bed bed = makeBed();
    setNatural(*bed.db, bed.state, start);
    GrowthOperator growth;
    setUp(growth, "growth_", bed, std::string("-growth_rate 2 -growth_transfer_fraction 0.01 -growth_mass ") +
                                      (number ? "number" : "transfer"));
    step(growth, bed);
    const double gain = number ? 8.0 : 1.0; // (4/2)^3 and (2/1)^3
    checkMasses(bed,
                {1, 1, 1, 1, 1, 1, 0.3 - 1.875e-5 + 2.5e-5 * gain, 0.2 - 2.5e-5, 0.1 + 1.875e-5 * gain,
                 0.05 - 3.125e-6 + 5e-5 * gain, 0.4 - 5e-5, 3.125e-6 * gain},
                1e-14, number ? "growth, number kept" : "growth, mass kept");
    const std::vector<double> &added = *growth.addedMass();
    RCFD_CHECK(rcfd::test::close(added[0], -2.1875e-5 + 7.5e-5 * gain, 1e-15));
    RCFD_CHECK(rcfd::test::close(added[1], -7.5e-5, 1e-15));
    RCFD_CHECK(rcfd::test::close(added[2], 2.1875e-5 * gain, 1e-15));
    RCFD_CHECK(rcfd::test::close(growth.impliedCoating(), number ? 0.0 : 7 * (2.1875e-5 + 7.5e-5), 1e-15));
    RCFD_CHECK(growth.limited() == 0.0 && growth.missed() == 0.0);
  }
  // A rate that wants more than the classes hold: everything of the two smaller
  // classes moves, nothing goes negative, the rest is counted as limited.
  // k = 0.01 * 1e8 * 0.005 / 800 = 6.25; wanted k 775 = 4843.75 kg, moved 0.95 kg.
  Bed bed = makeBed();
  setNatural(*bed.db, bed.state, start);
  GrowthOperator growth;
  setUp(growth, "growth_", bed, "-growth_rate 1e8");
  step(growth, bed);
  checkMasses(bed, {1, 1, 1, 1, 1, 1, 0.2, 0.0, 0.4, 0.4, 0.0, 0.05}, 1e-15, "growth, limited");
  RCFD_CHECK(rcfd::test::close(growth.limited(), 4843.75 - 0.95, 1e-14));
  // An empty spray zone grows nothing; the mass it would have moved is counted.
  setNatural(*bed.db, bed.state, {1, 1, 1, 1, 1, 1, 0, 0, 0, 0, 0, 0});
  step(growth, bed);
  checkMasses(bed, {1, 1, 1, 1, 1, 1, 0, 0, 0, 0, 0, 0}, 0.0, "growth, empty zone");
  RCFD_CHECK(rcfd::test::close(growth.missed(), 0.01 * 1e8 * kDt, 1e-15));
}

// An open top: the largest class (4 mm) grows as well, k m / d, and that
// mass leaves the bed as oversize: cell 2 k 0.1 / 4e-3 = 3.125e-6 kg, cell 3
// none (it holds no 4 mm).  Without keeping the bulk the spray cells lose
// it; with it (the default) cells 2 and 3 keep their 0.6 and 0.45 kg and
// every fraction's total is what the ledger expects.
void openTopByHand() {
  const std::vector<double> start{1, 1, 1, 1, 1, 1, 0.3, 0.2, 0.1, 0.05, 0.4, 0.0};
  for (const bool keep : {false, true}) {
    Bed bed = makeBed();
    setNatural(*bed.db, bed.state, start);
    std::vector<double> before;
    PetscCallAbort(PETSC_COMM_WORLD, bed.state.totals(&before));
    GrowthOperator growth;
    setUp(growth, "growth_", bed,
          std::string("-growth_rate 2 -growth_transfer_fraction 0.01 -growth_top open -growth_keep_bulk ") +
              (keep ? "1" : "0"));
    step(growth, bed);
    const std::vector<double> &added = *growth.addedMass();
    RCFD_CHECK(rcfd::test::close(growth.oversize(), 3.125e-6, 1e-15));
    RCFD_CHECK(rcfd::test::close(added[0], -2.1875e-5 + 7.5e-5, 1e-15));
    RCFD_CHECK(rcfd::test::close(added[1], -7.5e-5, 1e-15));
    RCFD_CHECK(rcfd::test::close(added[2], 2.1875e-5 - 3.125e-6, 1e-15));
    RCFD_CHECK(rcfd::test::close(added[0] + added[1] + added[2], -growth.oversize(), 1e-15));
    // Without keeping the bulk: the transfers by hand; with it, those cells scaled
    // back to their bulk and then every fraction by s_i = (before_i + added_i) / now_i.
    std::vector<double> m{1, 1, 1, 1, 1, 1, 0.3 - 1.875e-5 + 2.5e-5, 0.2 - 2.5e-5, 0.1 + 1.875e-5 - 3.125e-6,
                          0.05 - 3.125e-6 + 5e-5, 0.4 - 5e-5, 3.125e-6};
    if (keep) {
      for (int c : {2, 3}) {
        const double bulk = m[3 * c] + m[3 * c + 1] + m[3 * c + 2], was = c == 2 ? 0.6 : 0.45;
        for (int i = 0; i < 3; ++i) m[3 * c + i] *= was / bulk;
      }
      for (int i = 0; i < 3; ++i) {
        const double now = m[i] + m[3 + i] + m[6 + i] + m[9 + i];
        for (int c = 0; c < 4; ++c) m[3 * c + i] *= (before[i] + added[i]) / now;
      }
    }
    checkMasses(bed, m, 1e-14, keep ? "growth, open top, bulk kept" : "growth, open top");
    std::vector<double> after;
    PetscCallAbort(PETSC_COMM_WORLD, bed.state.totals(&after));
    for (int i = 0; i < 3; ++i) RCFD_CHECK(rcfd::test::close(after[i], before[i] + added[i], 1e-15));
  }
  ErrorCapture errors;
  ScopedOptions o(kZones + " -growth_top ajar");
  GrowthOperator growth;
  growth.setOptionsPrefix("growth_");
  RCFD_CHECK(growth.setFromOptions(PETSC_COMM_WORLD) != 0);
  RCFD_CHECK(contains(errors.message(), "-growth_top ajar is not known"));
}

// Feed: 4 kg/s * 0.005 s = 0.02 kg per step, shares 0.2/0.3/0.5, into the
// bottom layer (cells 0 with 1 kg and 1 with 3 kg: a quarter and three quarters).
void feedByHand() {
  Bed bed = makeBed();
  setNatural(*bed.db, bed.state, {0.5, 0.25, 0.25, 1, 1, 1, 1, 1, 1, 0, 0, 0});
  FeedOperator feed;
  setUp(feed, "feed_", bed, "-feed_zone bottom -feed_rate 4 -feed_mass_shares 0.2,0.3,0.5 -feed_keep_bulk 0");
  step(feed, bed);
  checkMasses(bed,
              {0.5 + 0.25 * 0.004, 0.25 + 0.25 * 0.006, 0.25 + 0.25 * 0.01, 1 + 0.75 * 0.004, 1 + 0.75 * 0.006,
               1 + 0.75 * 0.01, 1, 1, 1, 0, 0, 0},
              1e-15, "feed");
  RCFD_CHECK(rcfd::test::close((*feed.addedMass())[2], 0.01, 1e-15));
  // An empty zone: the feed is held back, then delivered whole where there is solid.
  setNatural(*bed.db, bed.state, {0, 0, 0, 0, 0, 0, 1, 1, 1, 0, 0, 0});
  step(feed, bed);
  checkMasses(bed, {0, 0, 0, 0, 0, 0, 1, 1, 1, 0, 0, 0}, 0.0, "feed held back");
  RCFD_CHECK(rcfd::test::close(feed.heldBack()[1], 0.006, 1e-15));
  setNatural(*bed.db, bed.state, {0, 0, 0, 0, 0, 1, 1, 1, 1, 0, 0, 0});
  step(feed, bed);
  checkMasses(bed, {0, 0, 0, 0.008, 0.012, 1.02, 1, 1, 1, 0, 0, 0}, 1e-15, "feed delivered late");
  RCFD_CHECK(feed.heldBack()[0] == 0.0 && rcfd::test::close((*feed.addedMass())[2], 0.03, 1e-15));

  // Discharge from cell 1 (0.1, 0.2, 0.7 kg): 20 kg/s takes 0.1 kg, a tenth of each class.
  setNatural(*bed.db, bed.state, {1, 1, 1, 0.1, 0.2, 0.7, 1, 1, 1, 0, 0, 0});
  DischargeOperator discharge;
  setUp(discharge, "discharge_", bed, "-discharge_zone outlet -discharge_rate 20 -discharge_keep_bulk 0");
  step(discharge, bed);
  checkMasses(bed, {1, 1, 1, 0.09, 0.18, 0.63, 1, 1, 1, 0, 0, 0}, 1e-15, "discharge");
  RCFD_CHECK(rcfd::test::close(discharge.discharged()[2], 0.07, 1e-15) && discharge.limitedSteps() == 0);
  // More than the zone holds: all of it (exactly 0 left), the rest owed, never negative.
  discharge.setRate(300); // 1.5 kg per step against 0.9 kg
  step(discharge, bed);
  checkMasses(bed, {1, 1, 1, 0, 0, 0, 1, 1, 1, 0, 0, 0}, 0.0, "discharge limited");
  RCFD_CHECK(discharge.limitedSteps() == 1 && rcfd::test::close(discharge.owed(), 0.6, 1e-14));
  RCFD_CHECK(rcfd::test::close(discharge.discharged()[0] + discharge.discharged()[1] + discharge.discharged()[2], 1.0, 1e-14));
  step(discharge, bed); // an empty zone: the owed mass grows, nothing changes
  checkMasses(bed, {1, 1, 1, 0, 0, 0, 1, 1, 1, 0, 0, 0}, 0.0, "discharge from an empty zone");
  RCFD_CHECK(rcfd::test::close(discharge.owed(), 2.1, 1e-14));
}

// With -keep_bulk (the default) the zone's cells keep their bulk and the
// change is spread by one factor per fraction: a discharge of 0.1 kg from
// cell 1 (0.1, 0.2, 0.7 kg) takes 0.01, 0.02, 0.07 kg, cell 1 is scaled back
// to its 1 kg, so every cell ends at s_i m_i with s_i = 1 - P_i / T_i over the
// totals T = (1.1, 1.2, 1.7); a feed of 0.02 kg (0.2/0.3/0.5) into the bottom
// layer (cells 0 and 1) changes their composition, keeps their bulk, and
// brings every fraction's total to T_i + F_i.
void keepBulkByHand() {
  const std::vector<double> start{0.5, 0.5, 0.0, 0.1, 0.2, 0.7, 0.5, 0.5, 1.0, 0, 0, 0};
  const auto scaled = [&](const std::vector<double> &s) {
    std::vector<double> m = start;
    for (std::size_t k = 0; k < m.size(); ++k) m[k] *= s[k % 3];
    return m;
  };
  Bed bed = makeBed();
  setNatural(*bed.db, bed.state, start);
  DischargeOperator discharge;
  setUp(discharge, "discharge_", bed, "-discharge_zone outlet -discharge_rate 20");
  step(discharge, bed);
  checkMasses(bed, scaled({1 - 0.01 / 1.1, 1 - 0.02 / 1.2, 1 - 0.07 / 1.7}), 1e-15, "discharge keeping the bulk");
  // The feed changes the composition of cells 0 and 1 (1 kg each: half the feed,
  // 0.002/0.003/0.005 kg, each), which are scaled back to 1 kg by 1/1.01; then
  // s_i = (T_i + F_i) / (total now) over the whole bed.
  setNatural(*bed.db, bed.state, start);
  FeedOperator feed;
  setUp(feed, "feed_", bed, "-feed_zone bottom -feed_rate 4 -feed_mass_shares 0.2,0.3,0.5");
  step(feed, bed);
  std::vector<double> m = start;
  const double fed[3] = {0.002, 0.003, 0.005}, total[3] = {1.1, 1.2, 1.7}, feedTotal[3] = {0.004, 0.006, 0.01};
  for (int c : {0, 1})
    for (int i = 0; i < 3; ++i) m[3 * c + i] = (m[3 * c + i] + fed[i]) / 1.01;
  for (int i = 0; i < 3; ++i) {
    const double now = m[i] + m[3 + i] + m[6 + i] + m[9 + i];
    for (int c = 0; c < 4; ++c) m[3 * c + i] *= (total[i] + feedTotal[i]) / now;
  }
  checkMasses(bed, m, 1e-14, "feed keeping the bulk");
}

void zonesRefused() {
  Bed bed = makeBed();
  {
    ErrorCapture errors;
    ScopedOptions o(kZones + " -feed_zone dead");
    FeedOperator feed;
    feed.setOptionsPrefix("feed_");
    PetscCallAbort(PETSC_COMM_WORLD, feed.setFromOptions(PETSC_COMM_WORLD));
    RCFD_CHECK(feed.setUp(bed.run()) != 0);
    RCFD_CHECK(contains(errors.message(), "Zone 'dead' of the feed operator") &&
               contains(errors.message(), "holds no solid in any of the database's 1 frames"));
  }
  ErrorCapture errors;
  ScopedOptions o(kZones + " -discharge_zone nowhere");
  DischargeOperator discharge;
  discharge.setOptionsPrefix("discharge_");
  PetscCallAbort(PETSC_COMM_WORLD, discharge.setFromOptions(PETSC_COMM_WORLD));
  RCFD_CHECK(discharge.setUp(bed.run()) != 0);
  RCFD_CHECK(contains(errors.message(), "-discharge_zone nowhere names no zone of the case"));
}

std::unique_ptr<Run> solve(const std::string &options, OperatorRegistry &registry) {
  ScopedOptions o("-db " + smallDb + " -fields 0 -quiet -plot 0 " + options);
  auto run = std::make_unique<Run>(PETSC_COMM_WORLD, registry);
  PetscCallAbort(PETSC_COMM_WORLD, run->setFromOptions());
  PetscCallAbort(PETSC_COMM_WORLD, run->setUp());
  PetscCallAbort(PETSC_COMM_WORLD, run->solve());
  return run;
}

const std::string kChamber =
    "-fractions_diameters 1.459e-3,2.0e-3,2.8e-3,4.075e-3 -fractions_mass_shares 0.25,0.25,0.25,0.25 "
    "-zones spray,feed,discharge -zone_spray_box 0.06,0.14,0,0.05,0.15,0.25 -zone_feed_box 0,0.04,0,0.05,0,0.07 "
    "-zone_discharge_box 0.16,0.2,0,0.05,0,0.07 -feed_mass_shares 0.7,0.1,0.1,0.1 ";

// Growth, feed and discharge together for 400 steps (with jumps): the ledger
// checks every fraction every step at 1e-12, and every row of mass_account.csv
// closes: holdup - initial - sum of the operators' columns = round-off.
// With an open top (-growth_top open) as well: the growth columns then sum to
// minus the oversize that left.
void accountCloses(OperatorRegistry &registry, const std::string &top) {
  const std::string out = dir + "/account_" + top;
  auto run = solve(kChamber + "-pipeline shift,drift,carry,growth,feed,discharge -path_type random -path_seed 3 "
                              "-growth_rate 5 -feed_rate 0.5 -discharge_rate 0.5 -t_end 2 -mass_check_every 1 "
                              "-mass_leak_tolerance 1e-12 -growth_top " + top + " -output_dir " + out,
                   registry);
  const csv::Table t = csv::Table::read(out + "/mass_account.csv");
  double bed = 0.0, worst = 0.0, residual = 0.0, discharged = 0.0, grown = 0.0;
  for (int i = 0; i < 4; ++i) bed += t.number(0, col(t, "holdup_" + run->fractions().label(i)));
  for (std::size_t r = 0; r < t.numRows(); ++r)
    for (int i = 0; i < 4; ++i) {
      const std::string l = run->fractions().label(i);
      const double closing = t.number(r, col(t, "holdup_" + l)) - t.number(0, col(t, "holdup_" + l)) -
                             t.number(r, col(t, "growth_" + l)) - t.number(r, col(t, "feed_" + l)) -
                             t.number(r, col(t, "discharge_" + l));
      worst = std::fmax(worst, std::fabs(closing));
      residual = std::fmax(residual, std::fabs(t.number(r, col(t, "residual_" + l))));
    }
  double growthSum = 0.0;
  for (int i = 0; i < 4; ++i) {
    discharged -= t.number(t.numRows() - 1, col(t, "discharge_" + run->fractions().label(i)));
    grown += std::fabs(t.number(t.numRows() - 1, col(t, "growth_" + run->fractions().label(i))));
    growthSum += t.number(t.numRows() - 1, col(t, "growth_" + run->fractions().label(i)));
  }
  const GrowthOperator *growth = nullptr;
  for (const auto &op : run->pipeline().operators())
    if (!growth) growth = dynamic_cast<const GrowthOperator *>(op.get());
  RCFD_CHECK(growth && (top == "open" ? growth->oversize() > 1e-4 : growth->oversize() == 0.0));
  if (growth && !rcfd::test::close(growthSum, -growth->oversize(), 1e-9 * bed))
    std::fprintf(stderr, "%s top: growth columns sum to %.10g kg, oversize %.10g kg\n", top.c_str(), growthSum,
                 growth->oversize());
  RCFD_CHECK(growth && std::fabs(growthSum + growth->oversize()) <= 1e-9 * bed);
  if (worst > 1e-9 * bed || residual > 1e-14 * bed)
    std::fprintf(stderr, "mass account: columns close to %.3g kg, residual %.3g kg, of %.3g kg\n", worst, residual, bed);
  RCFD_CHECK(worst <= 1e-9 * bed);      // from the columns, printed with 10 significant digits
  RCFD_CHECK(residual <= 1e-14 * bed); // computed before printing: round-off
  RCFD_CHECK(t.numRows() == 401 && rcfd::test::close(discharged, 1.0, 0.05) && grown > 0.01);
  double low;
  PetscCallAbort(PETSC_COMM_WORLD, run->state().minimum(&low));
  RCFD_CHECK(low >= 0.0);
  // The bulk stays with alpha_s (cog.csv's bulk mismatch): feed, discharge and an open top keep
  // their cells' bulk; 1.3e-3 and 5.8e-3 here against 5e-5 without the operators and 3.1e-2 when
  // feed and discharge do not keep it (-feed_keep_bulk 0 -discharge_keep_bulk 0).
  const csv::Table cog = csv::Table::read(out + "/cog.csv");
  double mismatch = 0.0;
  for (std::size_t r = 0; r < cog.numRows(); ++r) mismatch = std::fmax(mismatch, cog.number(r, col(cog, "bulk_mismatch")));
  if (mismatch > (top == "open" ? 1e-2 : 2.5e-3)) std::fprintf(stderr, "%s top: bulk mismatch %.3g\n", top.c_str(), mismatch);
  RCFD_CHECK(mismatch <= (top == "open" ? 1e-2 : 2.5e-3));
}

// Growth off; feed and discharge zones are the whole bed, so the discharge
// takes from every class in proportion to its holdup: after feed and
// discharge H_i' = (H_i + D w_i) M / (M + D), the deviation from the feed's
// composition e_i = H_i - M w_i shrinks by q = M / (M + D) per step exactly,
// e_n = e_0 q^n ~ e_0 exp(-t / tau), tau = M / m the residence time.
void steadyComposition(OperatorRegistry &registry) {
  const std::string whole = "-zones all -zone_all_layers 0,19 -feed_zone all -discharge_zone all ";
  auto run = solve("-fractions_diameters 1.459e-3,4.075e-3 -fractions_mass_shares 0.564,0.436 " + whole +
                       "-pipeline shift,drift,carry,feed,discharge -feed_rate 1 -discharge_rate 1 "
                       "-feed_mass_shares 0.1,0.9 -t_end 3 -discharge_sample_interval 0.05 -output_dir " + dir + "/steady",
                   registry);
  std::vector<double> holdup;
  PetscCallAbort(PETSC_COMM_WORLD, run->state().totals(&holdup));
  const double M = holdup[0] + holdup[1], D = 1.0 * kDt, q = M / (M + D);
  const double e0 = 0.564 * M - 0.1 * M, n = static_cast<double>(run->numSteps());
  const double expected = 0.1 * M + e0 * std::pow(q, n);
  if (!rcfd::test::close(holdup[0], expected, 1e-9))
    std::fprintf(stderr, "holdup of the fine class %.12g kg, expected %.12g kg\n", holdup[0], expected);
  RCFD_CHECK(rcfd::test::close(holdup[0], expected, 1e-9));
  // The exponential's time constant is the residence time tau = M / m: q^n = exp(-n ln(1 + x)),
  // x = D / M = dt / tau, against exp(-n x): they differ by n x^2 / 2 = (t / tau) (dt / tau) / 2.
  const double tau = M / 1.0, x = kDt / tau;
  RCFD_CHECK(std::fabs(std::pow(q, n) / std::exp(-n * x) - 1.0) < 0.6 * n * x * x);
  // The product is the holdup here; product.csv's holdup share follows the same curve.
  const csv::Table t = csv::Table::read(dir + "/steady/product.csv");
  const std::size_t r = t.numRows() / 2;
  const double time = t.number(r, col(t, "time_s"));
  const double share = t.number(r, col(t, "holdup_" + run->fractions().label(0)));
  RCFD_CHECK(rcfd::test::close(share, 0.1 + 0.464 * std::pow(q, std::round(time / kDt)), 1e-8));
}

// Two classes, tau = 1 s (holdup 1 kg, 1 kg/s), rows every 0.25 s; the product
// is 50 % fine until t = 2 s and 30 % from then on.  change(t) is 0 at t = 2
// (both windows before the switch), positive from 2.25 to 3.75 s and 0 from
// t = 4 s on: steady from 4 s, not from the early, interrupted 2 s.
// The series keeps only the rows later rows need (2 tau and one more: at
// most 10 here), and every change is the whole history's: 2 |P(t) - P(t - 1)|
// with P(t) = fine(t) - fine(t - 1).
void steadyCriterion() {
  ProductSeries s;
  s.nf = 2;
  s.rate = 1.0;
  s.tolerance = 0.02;
  const auto fine = [](double t) { return 0.5 * std::fmin(t, 2.0) + 0.3 * std::fmax(t - 2.0, 0.0); };
  std::vector<double> change;
  std::size_t kept = 0;
  for (int k = 0; k <= 24; ++k) {
    const double t = 0.25 * k;
    change.push_back(s.add({t, fine(t), t - fine(t), 0.5, 0.5}));
    kept = std::max(kept, s.size());
    if (k == 15) RCFD_CHECK(std::isnan(s.steadyTime()));
  }
  RCFD_CHECK(std::isnan(change[7]) && change[8] == 0.0);
  RCFD_CHECK(rcfd::test::close(change[15], 2 * 0.05, 1e-12)); // t = 3.75: windows 0.3 and 0.35
  for (int k = 8; k <= 24; ++k) {
    const double t = 0.25 * k, p = fine(t) - fine(t - 1), q = fine(t - 1) - fine(t - 2);
    RCFD_CHECK(std::fabs(change[k] - 2 * std::fabs(p - q)) < 1e-12);
  }
  if (kept > 10) std::fprintf(stderr, "the product series kept %zu rows, expected at most 10\n", kept);
  RCFD_CHECK(kept <= 10);
  RCFD_CHECK(rcfd::test::close(s.product(s.size() - 1)[0], 0.3, 1e-12));
  RCFD_CHECK(s.steadyTime() == 4.0);
  const double off = 0.5 * 2 + 0.3 * 4.25 + 0.2;
  s.add({6.25, off, 6.25 - off, 0.5, 0.5});
  RCFD_CHECK(std::isnan(s.steadyTime())); // a last row off the steady product: not steady
}

} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  if (argc < 3) {
    std::fprintf(stderr, "usage: test_granulation DATA_DIR SMALL_DB\n");
    return 1;
  }
  dir = rcfd::test::rankCountDirectory(argc, argv, "granulation");
  smallDb = argv[2];
  if (dir.empty()) return 1;
  growthByHand();
  openTopByHand();
  feedByHand();
  keepBulkByHand();
  zonesRefused();
  OperatorRegistry registry = OperatorRegistry::withBuiltins();
  accountCloses(registry, "closed");
  accountCloses(registry, "open");
  steadyComposition(registry);
  steadyCriterion();
  const int total = rcfd::test::globalFailures();
  PetscCall(PetscFinalize());
  return total == 0 ? 0 : 1;
}
