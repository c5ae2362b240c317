// The granulation operators cost their zone, not the bed (docs/performance.md,
// "Zone operators at the cost of their zone"): growth, feed and discharge find
// the bed's totals in the reduction of their zone's sums and the mass their
// zone's cells gained from those sums, instead of summing the whole bed twice
// per operator.  This test keeps the operators as they were before (summing
// the bed before and after, the arithmetic of each cell unchanged) as
// reference operators registered under the same names, and runs the same
// stitched granulator (growth, feed, discharge, -keep_bulk; closed and open
// top) with both:
//  - the states agree to round-off at the end (each cell and fraction within
//    1e-12 of the largest cell mass; measured: a few 1e-16), and so do the
//    operators' ledgers (the mass added per fraction, 1e-12 of the bed);
//  - the mass ledger checks every step at 1e-12 in both runs;
//  - a reference whose feed is 1e-9 off (a deliberately broken variant) is
//    told apart: the same comparison finds it above the tolerance.
// Runs at 1 and 2 ranks.  usage: test_granulation_reference DATA_DIR SMALL_DB
#include "check.hpp"
#include "registry_helpers.hpp"
#include "rcfd/granulation.hpp"
#include "rcfd/run.hpp"
#include "scoped_options.hpp"
#include "state_access.hpp"
#include "base/petsc_compat.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

using namespace rcfd;

namespace {

std::string dir, smallDb;
double feedError = 0.0; // the broken variant: the reference's feed rate off by this, relative

// What the three operators shared before: the bed summed before and after
// the zone's change, every cell of the bed scaled.
class ReferenceZone : public ZoneOperator {
protected:
  using ZoneOperator::ZoneOperator;
  std::vector<double> before, cellBulk;

  PetscErrorCode remember(const FractionState &state) {
    const PetscScalar *m;
    PetscFunctionBeginUser;
    PetscCall(state.totals(&before));
    cellBulk.assign(zone->localCells().size(), 0.0);
    PetscCall(VecGetArrayRead(state.masses(), &m));
    for (std::size_t k = 0; k < zone->localCells().size(); ++k)
      for (int i = 0; i < nf; ++i) cellBulk[k] += m[zone->localCells()[k] * nf + i];
    PetscCall(VecRestoreArrayRead(state.masses(), &m));
    PetscFunctionReturn(PETSC_SUCCESS);
  }

  PetscErrorCode restore(FractionState &state, const std::vector<double> &change) {
    PetscScalar *m;
    PetscInt n;
    std::vector<double> now;
    PetscFunctionBeginUser;
    PetscCall(VecGetArray(state.masses(), &m));
    for (std::size_t k = 0; k < zone->localCells().size(); ++k) {
      PetscScalar *cell = m + zone->localCells()[k] * nf;
      double bulk = 0.0;
      for (int i = 0; i < nf; ++i) bulk += cell[i];
      if (bulk > 0.0)
        for (int i = 0; i < nf; ++i) cell[i] *= cellBulk[k] / bulk;
    }
    PetscCall(VecRestoreArray(state.masses(), &m));
    PetscCall(state.totals(&now));
    std::vector<double> factor(nf, 1.0);
    for (int i = 0; i < nf; ++i)
      if (now[i] > 0.0) factor[i] = std::max(0.0, before[i] + change[i]) / now[i];
    PetscCall(VecGetLocalSize(state.masses(), &n));
    PetscCall(VecGetArray(state.masses(), &m));
    for (PetscInt c = 0; c < n; c += nf)
      for (int i = 0; i < nf; ++i) m[c + i] *= factor[i];
    PetscCall(VecRestoreArray(state.masses(), &m));
    PetscFunctionReturn(PETSC_SUCCESS);
  }

  // Mass of each fraction in the zone (global) and its sum.
  PetscErrorCode inZone(const FractionState &state, std::vector<double> *perFraction, double *total) const {
    const PetscScalar *m;
    PetscFunctionBeginUser;
    perFraction->assign(nf, 0.0);
    PetscCall(VecGetArrayRead(state.masses(), &m));
    for (PetscInt c : zone->localCells())
      for (int i = 0; i < nf; ++i) (*perFraction)[i] += m[c * nf + i];
    PetscCall(VecRestoreArrayRead(state.masses(), &m));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, perFraction->data(), nf, MPI_DOUBLE, MPI_SUM, comm));
    *total = std::accumulate(perFraction->begin(), perFraction->end(), 0.0);
    PetscFunctionReturn(PETSC_SUCCESS);
  }

  PetscErrorCode readRate(MPI_Comm c, const char *title, double *rate) {
    PetscFunctionBeginUser;
    PetscOptionsBegin(c, prefix.c_str(), title, "rcfd");
    PetscCall(readZone(PetscOptionsObject, c));
    PetscCall(readKeepBulk(PetscOptionsObject));
    PetscCall(PetscOptionsReal("-rate", "", "", *rate, rate, nullptr));
    PetscOptionsEnd();
    PetscFunctionReturn(PETSC_SUCCESS);
  }
};

// Growth, transfer mode, closed or open top (-growth_top), keeping the bulk.
class ReferenceGrowth : public ReferenceZone {
public:
  ReferenceGrowth() : ReferenceZone("spray") {}
  std::string type() const override { return "growth"; }
  PetscErrorCode setFromOptions(MPI_Comm c) override {
    char top[32] = "closed";
    PetscFunctionBeginUser;
    PetscCall(readRate(c, "reference growth", &rate));
    PetscCall(PetscOptionsGetString(nullptr, "growth_", "-top", top, sizeof top, nullptr));
    openTop = std::string(top) == "open";
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscErrorCode setUp(const RunContext &ctx) override {
    PetscFunctionBeginUser;
    PetscCall(setUpZone(ctx));
    for (int i = 0; i < nf; ++i) diameter.push_back(ctx.fractions.diameter(i));
    std::vector<int> order(nf);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return diameter[a] < diameter[b]; });
    next.assign(nf, -1);
    for (int k = 0; k + 1 < nf; ++k) next[order[k]] = order[k + 1];
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscErrorCode apply(const StepInfo &step, FractionState &state) override {
    PetscScalar *m;
    PetscFunctionBeginUser;
    PetscCall(VecGetArray(state.masses(), &m));
    double area = 0.0;
    for (PetscInt c : zone->localCells())
      for (int i = 0; i < nf; ++i) area += m[c * nf + i] / diameter[i];
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &area, 1, MPI_DOUBLE, MPI_SUM, comm));
    PetscCall(VecRestoreArray(state.masses(), &m));
    if (!(area > 0.0)) PetscFunctionReturn(PETSC_SUCCESS);
    const double k = 0.01 * rate * step.dt / area;
    if (openTop && keepBulk) PetscCall(remember(state));
    const auto grows = [&](int i) { return next[i] >= 0 || openTop; };
    std::vector<double> sums(nf, 0.0), out(nf);
    PetscCall(VecGetArray(state.masses(), &m));
    for (PetscInt c : zone->localCells()) {
      PetscScalar *cell = m + c * nf;
      for (int i = 0; i < nf; ++i) out[i] = std::min(grows(i) ? k * cell[i] / diameter[i] : 0.0, cell[i]);
      for (int i = 0; i < nf; ++i) {
        if (!grows(i)) continue;
        cell[i] -= out[i];
        sums[i] += out[i];
        if (next[i] >= 0) cell[next[i]] += out[i];
      }
    }
    PetscCall(VecRestoreArray(state.masses(), &m));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums.data(), nf, MPI_DOUBLE, MPI_SUM, comm));
    std::vector<double> change(nf, 0.0);
    for (int i = 0; i < nf; ++i) {
      if (!grows(i)) continue;
      change[i] -= sums[i];
      if (next[i] >= 0) change[next[i]] += sums[i];
    }
    for (int i = 0; i < nf; ++i) added[i] += change[i];
    if (openTop && keepBulk) PetscCall(restore(state, change));
    PetscFunctionReturn(PETSC_SUCCESS);
  }

private:
  double rate = 0.0;
  bool openTop = false;
  std::vector<double> diameter;
  std::vector<int> next;
};

// Feed with the inventory's shares.
class ReferenceFeed : public ReferenceZone {
public:
  ReferenceFeed() : ReferenceZone("feed") {}
  std::string type() const override { return "feed"; }
  PetscErrorCode setFromOptions(MPI_Comm c) override { return readRate(c, "reference feed", &rate); }
  PetscErrorCode setUp(const RunContext &ctx) override {
    PetscFunctionBeginUser;
    PetscCall(setUpZone(ctx));
    for (int i = 0; i < nf; ++i) shares.push_back(ctx.fractions.massShare(i));
    held.assign(nf, 0.0);
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscErrorCode apply(const StepInfo &step, FractionState &state) override {
    std::vector<double> zoneMass;
    double solid = 0.0;
    PetscScalar *m;
    PetscFunctionBeginUser;
    for (int i = 0; i < nf; ++i) held[i] += rate * (1.0 + feedError) * step.dt * shares[i];
    PetscCall(inZone(state, &zoneMass, &solid));
    if (!(solid > 0.0)) PetscFunctionReturn(PETSC_SUCCESS);
    if (keepBulk) PetscCall(remember(state));
    PetscCall(VecGetArray(state.masses(), &m));
    for (PetscInt c : zone->localCells()) {
      double cellSolid = 0.0;
      for (int i = 0; i < nf; ++i) cellSolid += m[c * nf + i];
      for (int i = 0; i < nf; ++i) m[c * nf + i] += held[i] * (cellSolid / solid);
    }
    PetscCall(VecRestoreArray(state.masses(), &m));
    if (keepBulk) PetscCall(restore(state, held));
    for (int i = 0; i < nf; ++i) added[i] += held[i], held[i] = 0.0;
    PetscFunctionReturn(PETSC_SUCCESS);
  }

private:
  double rate = 0.0;
  std::vector<double> shares, held;
};

class ReferenceDischarge : public ReferenceZone {
public:
  ReferenceDischarge() : ReferenceZone("discharge") {}
  std::string type() const override { return "discharge"; }
  PetscErrorCode setFromOptions(MPI_Comm c) override { return readRate(c, "reference discharge", &rate); }
  PetscErrorCode setUp(const RunContext &ctx) override { return setUpZone(ctx); }
  PetscErrorCode apply(const StepInfo &step, FractionState &state) override {
    std::vector<double> zoneMass;
    double solid = 0.0;
    PetscScalar *m;
    PetscFunctionBeginUser;
    const double wanted = rate * step.dt + owed;
    PetscCall(inZone(state, &zoneMass, &solid));
    if (!(solid > 0.0)) {
      owed = wanted;
      PetscFunctionReturn(PETSC_SUCCESS);
    }
    const bool all = wanted >= solid;
    const double share = all ? 1.0 : wanted / solid;
    owed = all ? wanted - solid : 0.0;
    std::vector<double> out(nf, 0.0);
    if (keepBulk) PetscCall(remember(state));
    PetscCall(VecGetArray(state.masses(), &m));
    for (PetscInt c : zone->localCells())
      for (int i = 0; i < nf; ++i) {
        PetscScalar &mass = m[c * nf + i];
        const double taken = all ? mass : mass * share;
        out[i] += taken;
        mass = all ? 0.0 : mass - taken;
      }
    PetscCall(VecRestoreArray(state.masses(), &m));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, out.data(), nf, MPI_DOUBLE, MPI_SUM, comm));
    std::vector<double> change(nf);
    for (int i = 0; i < nf; ++i) change[i] = -out[i];
    if (keepBulk) PetscCall(restore(state, change));
    for (int i = 0; i < nf; ++i) added[i] -= out[i];
    PetscFunctionReturn(PETSC_SUCCESS);
  }

private:
  double rate = 0.0, owed = 0.0;
};

struct Outcome {
  std::vector<double> masses, added; // natural order; per fraction, the operators' ledgers summed
};

Outcome solve(OperatorRegistry &registry, const std::string &top, const std::string &out) {
  ScopedOptions o("-db " + smallDb + " -fields 0 -quiet -plot 0 -output_dir " + out +
                  " -fractions_diameters 1.459e-3,2.0e-3,2.8e-3,4.075e-3 -fractions_mass_shares 0.25,0.25,0.25,0.25 "
                  "-zones spray,feed,discharge -zone_spray_box 0.06,0.14,0,0.05,0.15,0.25 "
                  "-zone_feed_box 0,0.04,0,0.05,0,0.07 -zone_discharge_box 0.16,0.2,0,0.05,0,0.07 "
                  "-pipeline shift,drift,carry,growth,feed,discharge -path_type random -path_seed 5 "
                  "-growth_rate 5 -feed_rate 0.5 -discharge_rate 0.5 -t_end 2 -mass_check_every 1 "
                  "-mass_leak_tolerance 1e-12 -growth_top " + top);
  Run run(PETSC_COMM_WORLD, registry);
  PetscCallAbort(PETSC_COMM_WORLD, run.setFromOptions());
  PetscCallAbort(PETSC_COMM_WORLD, run.setUp());
  PetscCallAbort(PETSC_COMM_WORLD, run.solve()); // the ledger refuses a change above 1e-12 in any step
  Outcome r;
  r.masses = test::gatherNatural(run.database(), run.state().masses(), run.state().numFractions());
  run.pipeline().addedMass(&r.added);
  return r;
}

// The largest difference, relative to the largest cell mass (masses) or to the bed (ledgers).
double difference(const Outcome &a, const Outcome &b, double *ledger) {
  double scale = 0.0, worst = 0.0, bed = 0.0;
  for (double v : a.masses) scale = std::max(scale, std::fabs(v)), bed += v;
  for (std::size_t k = 0; k < a.masses.size(); ++k) worst = std::max(worst, std::fabs(a.masses[k] - b.masses[k]));
  *ledger = 0.0;
  for (std::size_t i = 0; i < a.added.size(); ++i) *ledger = std::max(*ledger, std::fabs(a.added[i] - b.added[i]) / bed);
  return worst / scale;
}

void sameAsBefore(const std::string &top) {
  OperatorRegistry now = OperatorRegistry::withBuiltins(), before = OperatorRegistry::withBuiltins();
  replaced(before, "growth", [] { return std::make_unique<ReferenceGrowth>(); }, "growth as before");
  replaced(before, "feed", [] { return std::make_unique<ReferenceFeed>(); }, "feed as before");
  replaced(before, "discharge", [] { return std::make_unique<ReferenceDischarge>(); }, "discharge as before");
  const Outcome fast = solve(now, top, dir + "/now_" + top);
  feedError = 0.0;
  const Outcome reference = solve(before, top, dir + "/before_" + top);
  double ledger;
  const double cells = difference(fast, reference, &ledger);
  PetscPrintf(PETSC_COMM_WORLD, "%s top: cells differ by %.2e of the largest, ledgers by %.2e of the bed\n",
              top.c_str(), cells, ledger);
  RCFD_CHECK(cells <= 1e-12 && ledger <= 1e-12);
  RCFD_CHECK(fast.added.size() == 4 && std::fabs(fast.added[0]) > 1e-3); // the operators did change the bed
  // The broken variant: a reference feed 1e-9 off is told apart.
  feedError = 1e-9;
  const Outcome broken = solve(before, top, dir + "/broken_" + top);
  feedError = 0.0;
  const double brokenCells = difference(fast, broken, &ledger);
  PetscPrintf(PETSC_COMM_WORLD, "%s top, feed 1e-9 off: cells differ by %.2e, ledgers by %.2e\n", top.c_str(),
              brokenCells, ledger);
  RCFD_CHECK(brokenCells > 1e-12 && ledger > 1e-12);
}

} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  if (argc < 3) {
    std::fprintf(stderr, "usage: test_granulation_reference DATA_DIR SMALL_DB\n");
    return 1;
  }
  dir = rcfd::test::rankCountDirectory(argc, argv, "granulation_reference");
  smallDb = argv[2];
  if (dir.empty()) return 1;
  sameAsBefore("closed");
  sameAsBefore("open");
  const int total = rcfd::test::globalFailures();
  PetscCall(PetscFinalize());
  return total == 0 ? 0 : 1;
}
