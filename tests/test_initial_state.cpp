// Initial states: mixed and layered by hand, and files that must be refused
// (NaN, inf, negative, no mass at all, wrong size) or warned about (mass in
// cells that frame 0 says are empty), on 1 and 2 ranks.
#include "base/petsc_compat.hpp"
#include "box_meshes.hpp"
#include "check.hpp"
#include "fraction_sets.hpp"
#include "state_access.hpp"

#include "base/h5.hpp"
#include "state/initial_state.hpp"

#include <cmath>
#include <limits>

using namespace rcfd;

namespace {

PetscErrorCode run(const std::string &dir) {
  PetscFunctionBeginUser;
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  // A column of 4 cells of 1e-3 m^3; frame 0 leaves the top cell empty.
  BoxSpec s;
  s.nx = 1;
  s.ny = 1;
  s.nz = 4;
  s.length = {0.1, 0.1, 0.4};
  const std::string path = dir + "/column.h5";
  test::writeIdentityDatabase(path, rcfd::test::boxMesh(s), {0.5, 0.5, 0.25, 0.0}, DatabaseMetadata{});
  std::unique_ptr<Database> db;
  PetscCall(Database::load(PETSC_COMM_WORLD, path, DatabaseLoadOptions{}, &db));
  const FractionSet set = rcfd::test::fractionSet({1e-3, 3e-3}, {0.25, 0.75});
  FractionState state;
  PetscCall(state.create(db->layout(), 2));
  const double rho = 1000.0; // cell masses 0.5, 0.5, 0.25, 0 kg: 1.25 kg

  PetscCall(setInitialState({"mixed", ""}, *db, set, rho, state));
  auto m = test::gatherNatural(*db, state.masses(), 2);
  RCFD_CHECK_CLOSE(m[0], 0.125, 1e-15);
  RCFD_CHECK_CLOSE(m[1], 0.375, 1e-15);
  RCFD_CHECK(m[6] == 0.0 && m[7] == 0.0);
  // Layered: 0.9375 kg of 3 mm at the bottom, then 0.3125 kg of 1 mm.
  PetscCall(setInitialState({"layered", ""}, *db, set, rho, state));
  m = test::gatherNatural(*db, state.masses(), 2);
  RCFD_CHECK(m[0] == 0.0);
  RCFD_CHECK_CLOSE(m[1], 0.5, 1e-15);
  RCFD_CHECK_CLOSE(m[2], 0.0625, 1e-15);
  RCFD_CHECK_CLOSE(m[3], 0.4375, 1e-15);
  RCFD_CHECK_CLOSE(m[4], 0.25, 1e-15);

  // Files: each refused with its sentence, or read.
  auto file = [&](const std::string &name, std::vector<double> masses, hsize_t cols = 2) {
    const std::string p = dir + "/init_" + name + ".h5";
    if (rank == 0) {
      h5::File f = h5::File::create(p);
      f.write("/masses", masses, cols);
      f.close();
    }
    MPI_Barrier(PETSC_COMM_WORLD);
    return p;
  };
  auto refusal = [&](const std::string &p) {
    const PetscErrorCode ierr = setInitialState({"file", p}, *db, set, rho, state);
    char *why = nullptr;
    PetscErrorMessage(ierr, nullptr, &why);
    return ierr && why ? std::string(why) : std::string();
  };
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  RCFD_CHECK(refusal(file("nan", {0.1, 0.1, nan, 0.1, 0.1, 0.1, 0, 0})).find("1 negative or non-finite") !=
             std::string::npos);
  RCFD_CHECK(refusal(file("inf", {0.1, inf, 0.1, 0.1, -1.0, 0.1, 0, 0})).find("2 negative or non-finite") !=
             std::string::npos);
  RCFD_CHECK(refusal(file("zero", std::vector<double>(8, 0.0))).find("holds no mass at all") != std::string::npos);
  RCFD_CHECK(refusal(file("size", std::vector<double>(6, 0.1), 3)).find("should be 4 cells x 2 fractions") !=
             std::string::npos);
  // Mass in the empty top cell: read, with a warning.
  const std::string stray = file("stray", {0.1, 0.2, 0.1, 0.2, 0.1, 0.2, 0.05, 0.0});
  PetscCall(setInitialState({"file", stray}, *db, set, rho, state));
  m = test::gatherNatural(*db, state.masses(), 2);
  RCFD_CHECK(m[6] == 0.05 && m[1] == 0.2);
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

int main(int argc, char **argv) { return test::rankTestMain(argc, argv, "initial_state", run); }
