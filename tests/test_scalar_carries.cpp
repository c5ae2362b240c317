// Scalars carried across jumps by the remap and level carries, and across
// database switches (docs/scalars.md): a carried mass takes its value along.
//  - on the small database along a stitched path (random sequences joined by
//    jumps) through shift, drift and the carry of kind remap, then level: a
//    uniform scalar stays uniform to round-off (1e-12 relative) in every cell
//    and fraction holding mass; every scalar's total is kept (the ledger
//    closes to 1e-12), a decaying one's is exp(-k t) times its start; no
//    amount is negative; with level (a transport) a zone's values stay within
//    their initial bounds;
//  - on two synthetic beds switched by a schedule (there and back, the remap
//    onto the other database's frame at each switch) the same, with the gas
//    exchange on (at the uniform temperature: it changes nothing) set up on
//    each database in turn;
//  - each run on the ranks of the test equals the same run on one rank
//    (PETSC_COMM_SELF) to 1e-12, masses and amounts (sums over the ranks round
//    in another order); a run restarted from its mid-run checkpoint (remap; and
//    between the two switches) ends with the same bits and the same scalars.csv;
//  - a user's carry kind that does not say it carries scalars is refused with
//    one sentence.
// Runs at 1 and 2 ranks.  usage: test_scalar_carries DIR (DIR/small.h5 is the small database)
#include "check.hpp"
#include "registry_helpers.hpp"
#include "scoped_options.hpp"
#include "state_access.hpp"
#include "synthetic_beds.hpp"
#include "scalar_run.hpp"
#include "base/csv.hpp"
#include "base/petsc_compat.hpp"
#include "rcfd/run.hpp"

#include <cmath>
#include <string>
#include <vector>

using namespace rcfd;

namespace {

constexpr double kDecay = 1.7;
const std::string kScalars =
    " -scalars temperature,moisture,tracer -scalar_temperature_initial 300 -scalar_moisture_initial 0.1"
    " -zones hot -zone_hot_layers 0,3 -scalar_moisture_zones hot -scalar_moisture_zone_values 0.4"
    " -scalar_tracer_initial 2 -scalar_tracer_decay 1.7 -pipeline shift,drift,carry -monitor_digits 17"
    " -fractions_diameters 1.459e-3,4.075e-3 -fractions_mass_shares 0.564,0.436";

using Outcome = test::ScalarOutcome;
using test::fileBytes;

/// A carry kind that leaves the state as it is and does not say it carries scalars.
class StillCarry : public CarryKind {
public:
  std::string type() const override { return "still"; }
  PetscErrorCode apply(const CarryContext &, const StepInfo &, FractionState &) override { return PETSC_SUCCESS; }
  PetscErrorCode view(PetscViewer viewer) const override {
    return PetscViewerASCIIPrintf(viewer, "carry: still\n");
  }
};

PetscErrorCode runCase(MPI_Comm comm, const std::string &options, const std::string &dir, Outcome *out) {
  OperatorRegistry registry = OperatorRegistry::withBuiltins();
  registered(registry.carryKinds(), "still", [] { return std::make_unique<StillCarry>(); }, "changes nothing");
  return test::runScalarCaseWith(comm, registry, options, dir, out);
}

/// The same run on one rank (PETSC_COMM_SELF) against the ranks of the test, to 1e-12.
PetscErrorCode checkRanks(const Outcome &all, const std::string &options, const std::string &dir) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  Outcome alone;
  PetscCall(runCase(PETSC_COMM_SELF, options, dir + "/alone" + std::to_string(rank), &alone));
  RCFD_CHECK_CLOSE(test::largestDifference(alone, all), 0.0, 1e-12);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/// Stopped at `half` with a checkpoint and restarted to the end: the same bits and scalars.csv as `all`.
PetscErrorCode checkRestart(const Outcome &all, const std::string &options, const std::string &end,
                            const std::string &half, const std::string &dir, const std::string &allDir) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  Outcome first, second;
  PetscCall(runCase(PETSC_COMM_WORLD, options + " -t_end " + half + " -checkpoint_every " + half, dir, &first));
  PetscCall(runCase(PETSC_COMM_WORLD, options + " -t_end " + end + " -restart " + dir + "/checkpoint.h5", dir, &second));
  RCFD_CHECK(second.masses == all.masses);
  RCFD_CHECK(second.amounts == all.amounts);
  if (rank == 0) {
    const std::string a = fileBytes(allDir + "/scalars.csv"), b = fileBytes(dir + "/scalars.csv");
    RCFD_CHECK(!a.empty() && a == b);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode run(const std::string &dir, const std::string &small) {
  PetscFunctionBeginUser;
  // Stitched: the remap and level carries at the jumps.
  const double t = 0.6;
  for (const std::string kind : {"remap", "level"}) {
    const std::string opts = kScalars + " -db " + small + " -carry_type " + kind + " -path_type random -path_seed 5";
    const std::string out = dir + "/" + kind;
    Outcome all;
    PetscCall(runCase(PETSC_COMM_WORLD, opts + " -t_end 0.6", out, &all));
    RCFD_CHECK(all.jumps >= 5);
    test::checkScalarsCarried(all, t, kDecay, true, kind);
    PetscCall(checkRanks(all, opts + " -t_end 0.6", out));
    if (kind == "remap") PetscCall(checkRestart(all, opts, "0.6", "0.3", out + "/restarted", out));
  }

  // Switched: there and back between two beds of other bubbles, the remap at each switch.
  const std::string a = dir + "/a.h5", b = dir + "/b.h5";
  test::writeBed(a, 20, 1500.0, 1);
  test::writeBed(b, 20, 4000.0, 2);
  const std::string switched = kScalars + " -db " + a + "," + b +
                               " -db_conditions 1.1,1.3 -db_switch_schedule 0:1.1,0.02:1.3,0.045:1.1 -path_type replay"
                               " -scalar_exchange_model gunn -scalar_gas_temperature 300"; // the sources follow the switch
  Outcome all;
  PetscCall(runCase(PETSC_COMM_WORLD, switched + " -t_end 0.07", dir + "/switched", &all));
  const csv::Table switches = csv::Table::read(dir + "/switched/switches.csv");
  int count = 0;
  for (std::size_t r = 0; r < switches.numRows(); ++r)
    count += switches.field(r, switches.find({"event"})) == "switch";
  RCFD_CHECK(count == 2);
  test::checkScalarsCarried(all, 0.07, kDecay, true, "switched");
  PetscCall(checkRanks(all, switched + " -t_end 0.07", dir + "/switched"));
  PetscCall(checkRestart(all, switched, "0.07", "0.03", dir + "/switched/restarted", dir + "/switched"));

  // A carry kind that does not carry scalars is refused.
  {
    ErrorCapture capture;
    Outcome none;
    const PetscErrorCode status =
        runCase(PETSC_COMM_WORLD, kScalars + " -db " + small + " -carry_type still -t_end 0.1", dir + "/refused", &none);
    const std::string sentence = "-scalars: the operator 'carry' of -pipeline does not carry scalars yet";
    RCFD_CHECK(status != 0);
    if (capture.message().find(sentence) == std::string::npos)
      test::fail(__FILE__, __LINE__, "expected '" + sentence + "', got '" + capture.message() + "'");
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

int main(int argc, char **argv) {
  const std::string small = (argc > 1 ? std::string(argv[1]) : std::string(".")) + "/small.h5";
  return test::rankTestMain(argc, argv, "scalar-carries", [&](const std::string &dir) { return run(dir, small); });
}
