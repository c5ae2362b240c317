// Batched replays (src/analysis/batched_replay.hpp, what rcfd calibrate runs
// by default) give every candidate the numbers of its own one-by-one run
// (Run::solve) bit for bit: every centre-of-gravity sample (time, z of each
// class and of the bed, delta z, each class's total, the smallest cell mass,
// the bulk mismatch) and the final mass of every fraction in every cell.
// Candidates differ in size law, k_d, local d32, hindrance and agitation
// scaling (a batch shares the agitation field of each measure); all in one
// batch writing cog.csv, and split over three batches keeping the samples
// in memory only; on the replay
// and on a stitched path with jumps (carry in the pipeline).  Each
// candidate's columns keep their totals to 1e-12 and no mass is negative.
// Runs at 1 and 2 ranks.
// usage: test_batched_calibration OUTPUT_DIR -db SMALL.h5 [run options]
#include "analysis/batched_replay.hpp"
#include "check.hpp"
#include "scoped_options.hpp"
#include "base/petsc_compat.hpp"

#include <cmath>
#include <string>
#include <vector>

using namespace rcfd;

namespace {

bool same(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

bool same(const std::vector<double> &a, const std::vector<double> &b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (!same(a[k], b[k])) return false;
  return true;
}

// Samples equal in every number, bit for bit.
int differingSamples(const std::vector<BedSample> &a, const std::vector<BedSample> &b) {
  if (a.size() != b.size()) return static_cast<int>(std::max(a.size(), b.size()));
  int n = 0;
  for (std::size_t k = 0; k < a.size(); ++k)
    n += !(same(a[k].time, b[k].time) && same(a[k].mass, b[k].mass) && same(a[k].zCog, b[k].zCog) &&
           same(a[k].zCogBed, b[k].zCogBed) && same(a[k].deltaZ, b[k].deltaZ) &&
           same(a[k].minMass, b[k].minMass) && same(a[k].bulkMismatch, b[k].bulkMismatch));
  return n;
}

struct OneByOne {
  std::vector<BedSample> history;
  std::vector<double> masses; // this rank's, at the end
};

PetscErrorCode runAlone(const OperatorRegistry &registry, std::shared_ptr<Database> db, const std::string &options,
                        const std::string &dir, OneByOne *out) {
  PetscFunctionBeginUser;
  Run run(PETSC_COMM_WORLD, registry);
  BatchedReplay replay(PETSC_COMM_WORLD, registry);
  replay.useDatabase(db);
  PetscCall(replay.solveAlone({dir, options, nullptr}, run)); // Run::solve
  out->history = run.history();
  const PetscScalar *m;
  PetscInt n;
  PetscCall(VecGetLocalSize(run.state().masses(), &n));
  PetscCall(VecGetArrayRead(run.state().masses(), &m));
  out->masses.assign(m, m + n);
  PetscCall(VecRestoreArrayRead(run.state().masses(), &m));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The candidates one by one, then batched in one state and in batches of
// `columns` columns; every candidate must match its own run.
PetscErrorCode compare(const OperatorRegistry &registry, std::shared_ptr<Database> db,
                       const std::vector<std::string> &options, const std::string &dir, int columns,
                       int expectedBatches) {
  PetscFunctionBeginUser;
  std::vector<OneByOne> alone(options.size());
  for (std::size_t k = 0; k < options.size(); ++k)
    PetscCall(runAlone(registry, db, options[k], dir + "/alone-" + std::to_string(k), &alone[k]));
  for (int split : {0, columns}) { // split: without cog.csv (the samples in memory only)
    std::vector<BatchedReplay::Candidate> candidates;
    for (std::size_t k = 0; k < options.size(); ++k)
      candidates.push_back({split ? std::string() : dir + "/batch-" + std::to_string(k), options[k], nullptr});
    BatchedReplay batched(PETSC_COMM_WORLD, registry);
    batched.useDatabase(db);
    if (split) batched.setColumnsPerBatch(split);
    PetscCall(batched.solve(candidates));
    RCFD_CHECK(batched.batches() == (split ? expectedBatches : 1));
    for (std::size_t k = 0; k < options.size(); ++k) {
      const auto &h = batched.history(static_cast<int>(k));
      const int differing = differingSamples(h, alone[k].history);
      if (differing) std::fprintf(stderr, "candidate '%s': %d of %zu samples differ from its own run\n",
                                  options[k].c_str(), differing, h.size());
      RCFD_CHECK(differing == 0);
      RCFD_CHECK(h.size() == 61); // the initial state and 60 steps
      RCFD_CHECK(batched.finalMasses(static_cast<int>(k)) == alone[k].masses);
      // Mass per column: each class's total as at the start, no negative mass.
      for (const BedSample &s : h) {
        RCFD_CHECK(s.minMass >= 0.0);
        for (std::size_t i = 0; i < s.mass.size(); ++i) RCFD_CHECK_CLOSE(s.mass[i] / h.front().mass[i], 1.0, 1e-12);
      }
      // The candidates differ: the batch does not mix their columns.
      if (k > 0) RCFD_CHECK(h.back().deltaZ != batched.history(0).back().deltaZ);
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  {
    PetscCheck(argc > 1, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT,
               "usage: test_batched_calibration OUTPUT_DIR -db DATABASE [run options]");
    PetscMPIInt size;
    PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
    const std::string dir = std::string(argv[1]) + "-np" + std::to_string(size); // np 1 and 2 may run at once
    const OperatorRegistry registry = OperatorRegistry::withBuiltins();
    std::shared_ptr<Database> db;
    {
      Run first(PETSC_COMM_WORLD, registry);
      PetscCall(first.setFromOptions());
      first.setQuiet(true);
      first.setOutputDirectory(dir + "/first");
      PetscCall(first.setUp());
      db = first.sharedDatabase();
      std::string why;
      RCFD_CHECK(BatchedReplay::batchable(first, &why));
    }
    const std::vector<std::string> laws = {
        "-drift_model B -drift_kd 2e5",
        "-drift_model A -drift_kd 4e4 -drift_local_d32",
        "-drift_size_law drag -drift_kd 0.05 -drift_hindered",
        "-drift_size_law power -drift_size_law_exponent 2.5 -drift_kd 0.03 -drift_local_d32",
        "-drift_model B -drift_kd 5e4 -drift_agitation leaving -drift_agitation_exponent 2",
        "-drift_model A -drift_kd 3e4 -drift_agitation dispersion -drift_agitation_exponent 1.5",
    };
    // Two fractions: 4 columns are two candidates per batch, three batches.
    PetscCall(compare(registry, db, laws, dir + "/replay", 4, 3));
    {
      ScopedOptions stitched("-path_type random -path_seed 7");
      PetscCall(compare(registry, db, {laws[0], laws[1], laws[4]}, dir + "/stitched", 4, 2));
    }
    { // A candidate option nobody reads is refused with its name.
      ErrorCapture capture;
      BatchedReplay batched(PETSC_COMM_WORLD, registry);
      batched.useDatabase(db);
      const PetscErrorCode status = batched.solve({{dir + "/typo", "-drift_kdd 3", nullptr}});
      RCFD_CHECK(status != PETSC_SUCCESS);
      RCFD_CHECK(capture.message().find("-drift_kdd") != std::string::npos);
    }
    { // Nor is -db: the candidates share one database.
      ErrorCapture capture;
      BatchedReplay batched(PETSC_COMM_WORLD, registry);
      batched.useDatabase(db);
      RCFD_CHECK(batched.solve({{"", "-db other.h5 -drift_kd 3", nullptr}}) != PETSC_SUCCESS);
      RCFD_CHECK(capture.message().find("share one loaded database") != std::string::npos);
    }
    { // A pipeline that does not start with the shift cannot be batched.
      ScopedOptions drifted("-pipeline drift,shift");
      Run run(PETSC_COMM_WORLD, registry);
      run.useDatabase(db);
      PetscCall(run.setFromOptions());
      run.setOutputDirectory(dir + "/drift-first");
      PetscCall(run.setUp());
      std::string why;
      RCFD_CHECK(!BatchedReplay::batchable(run, &why));
      RCFD_CHECK(why.find("first") != std::string::npos);
    }
  }
  const int result = RCFD_TEST_RESULT();
  PetscCall(PetscFinalize());
  return result;
}
