// Compact frames (issue 14): the database holds each rank's moving rows only,
// the propagation reads them in place, and PETSc matrices are built on demand.
//  - The compact kernel gives the same bits as MatMult with the on-demand
//    matrix, fraction by fraction, on every frame of small.h5 at 1 rank: the
//    AIJ product without inodes, which sums a row's entries one after the
//    other as the compact kernel does (the inode product adds them two by
//    two; test_replay compares with MAIJ).  At 2 ranks PETSc's product
//    differs by an ulp in some rows that mix own and other ranks' cells
//    (the old moving-rows kernel did too): within 1e-15 there.
//  - Weights quantised to 2^-16 (largest-remainder rounding per column): every
//    column sums to exactly 1, every fraction's mass is conserved to 1e-12 over
//    all frames and never negative, and the run equals the one-rank run.
//  - A bad quantisation is refused with a sentence: weight_bits out of range,
//    weight_bits on weights that are not quantised, a writer given such frames.
// Runs at 1 and 2 ranks; argv[1] is the test-data directory with small.h5.
#include "base/h5.hpp"
#include "box_meshes.hpp"
#include "base/petsc_compat.hpp"
#include "check.hpp"
#include "database/quantise.hpp"
#include "database_copies.hpp"
#include "operator/moving_rows.hpp"
#include "scoped_options.hpp"
#include "state_access.hpp"
#include "database/database_file_writer.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

using namespace rcfd;

namespace {

constexpr int kFractions = 3;
int rank = 0;

// Masses of nf fractions in PETSc order, from values that depend on the
// natural cell only (the same state at any number of ranks).
PetscErrorCode makeMasses(const Database &db, OwnedVec *x) {
  const Layout &L = db.layout();
  PetscFunctionBeginUser;
  PetscCall(VecCreateMPI(L.comm(), L.numLocal() * kFractions, L.numCells() * kFractions, x->put()));
  PetscCall(VecSetBlockSize(*x, kFractions));
  PetscScalar *m;
  PetscCall(VecGetArrayWrite(*x, &m));
  for (PetscInt r = 0; r < L.numLocal(); ++r)
    for (int i = 0; i < kFractions; ++i)
      m[r * kFractions + i] = 1e-3 * (1 + (L.ownedNatural()[r] * 7919 + i * 104729) % 1000);
  PetscCall(VecRestoreArrayWrite(*x, &m));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// Largest |a - b| over the entries of two vectors of one layout.
double largestDifference(Vec a, Vec b) {
  OwnedVec d;
  PetscReal diff = 0.0;
  VecDuplicate(a, d.put());
  VecWAXPY(d, -1.0, a, b);
  VecNorm(d, NORM_INFINITY, &diff);
  return diff;
}

PetscErrorCode sameBitsAsMatMult(const std::string &path) {
  std::unique_ptr<Database> db;
  PetscFunctionBeginUser;
  PetscCall(Database::load(PETSC_COMM_WORLD, path, DatabaseLoadOptions{}, &db));
  MovingRows moving;
  PetscCall(moving.setUp(*db, kFractions));
  OwnedVec x, before, single, product, fromCompact;
  PetscCall(makeMasses(*db, &x));
  PetscCall(VecDuplicate(x, before.put()));
  PetscCall(VecCreateMPI(PETSC_COMM_WORLD, db->layout().numLocal(), db->layout().numCells(), single.put()));
  PetscCall(VecDuplicate(single, product.put()));
  PetscCall(VecDuplicate(single, fromCompact.put()));
  double worst = 0.0;
  size_t entries = 0;
  for (int k = 0; k < db->numFrames(); ++k) {
    OwnedMat T;
    {
      ScopedOptions plainSums("-mat_no_inode");
      PetscCall(db->shiftMatrix(k, &T));
    }
    PetscCall(VecCopy(x, before));
    PetscCall(moving.apply(k, x));
    for (int i = 0; i < kFractions; ++i) {
      PetscCall(VecStrideGather(before, i, single, INSERT_VALUES));
      PetscCall(MatMult(T, single, product));
      PetscCall(VecStrideGather(x, i, fromCompact, INSERT_VALUES));
      worst = std::max(worst, largestDifference(product, fromCompact));
    }
    entries += db->frame(k).numEntries();
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "compact kernel vs MatMult over %d frames: largest difference %g\n",
                        db->numFrames(), worst));
  PetscMPIInt size;
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  RCFD_CHECK(size == 1 ? worst == 0.0 : worst <= 1e-15);
  RCFD_CHECK(entries > 0);
  PetscFunctionReturn(PETSC_SUCCESS);
}

// All frames applied in turn to the masses of makeMasses, in natural order.
PetscErrorCode replayAll(MPI_Comm comm, const std::string &path, std::vector<double> *natural,
                         std::vector<double> *totals, double *smallest) {
  std::unique_ptr<Database> db;
  PetscFunctionBeginUser;
  PetscCall(Database::load(comm, path, DatabaseLoadOptions{}, &db));
  MovingRows moving;
  PetscCall(moving.setUp(*db, kFractions));
  OwnedVec x;
  PetscCall(makeMasses(*db, &x));
  totals->assign(2 * kFractions, 0.0); // before, after
  for (int i = 0; i < kFractions; ++i) PetscCall(VecStrideNorm(x, i, NORM_1, &(*totals)[i]));
  *smallest = 0.0;
  for (int k = 0; k < db->numFrames(); ++k) {
    PetscCall(moving.apply(k, x));
    PetscReal least;
    PetscCall(VecMin(x, nullptr, &least));
    *smallest = std::min(*smallest, least);
  }
  for (int i = 0; i < kFractions; ++i) {
    PetscReal sum;
    PetscCall(VecStrideSum(x, i, &sum));
    (*totals)[kFractions + i] = sum;
  }
  PetscCall(db->layout().gatherToAll(kFractions, x, natural));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode quantisedConservesExactly(const std::string &small, const std::string &quantised) {
  std::unique_ptr<Database> db;
  PetscFunctionBeginUser;
  PetscCall(test::rewriteDatabase(small, quantised, 16));
  PetscCall(Database::load(PETSC_COMM_WORLD, quantised, DatabaseLoadOptions{}, &db));
  RCFD_CHECK(db->metadata().weightBits == 16);
  // Every column sums to exactly 1 (MatMultTranspose sums as the loader does).
  OwnedVec ones, sums;
  size_t quantumEntries = 0;
  int inexact = 0;
  for (int k = 0; k < db->numFrames(); ++k) {
    OwnedMat T;
    PetscCall(db->shiftMatrix(k, &T));
    if (!ones) {
      PetscCall(MatCreateVecs(T, ones.put(), sums.put()));
      PetscCall(VecSet(ones, 1.0));
    }
    PetscCall(MatMultTranspose(T, ones, sums));
    const PetscScalar *s;
    PetscCall(VecGetArrayRead(sums, &s));
    for (PetscInt r = 0; r < db->layout().numLocal(); ++r) inexact += s[r] != 1.0;
    PetscCall(VecRestoreArrayRead(sums, &s));
    quantumEntries += db->frame(k).quantum.size();
    RCFD_CHECK(db->frame(k).val.empty());
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &inexact, 1, MPI_INT, MPI_SUM, PETSC_COMM_WORLD));
  RCFD_CHECK(inexact == 0);
  RCFD_CHECK(quantumEntries > 0);
  db.reset();

  std::vector<double> natural, totals;
  double smallest;
  PetscCall(replayAll(PETSC_COMM_WORLD, quantised, &natural, &totals, &smallest));
  double drift = 0.0;
  for (int i = 0; i < kFractions; ++i)
    drift = std::max(drift, std::fabs(totals[kFractions + i] - totals[i]) / totals[i]);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "quantised weights: largest relative change of a fraction's mass %.3g, smallest mass %g\n",
                        drift, smallest));
  RCFD_CHECK(drift <= 1e-12);
  RCFD_CHECK(smallest >= 0.0);
  // The same replay on one rank.
  if (rank == 0) {
    std::vector<double> serial, serialTotals;
    double serialSmallest;
    PetscCall(replayAll(PETSC_COMM_SELF, quantised, &serial, &serialTotals, &serialSmallest));
    double largest = 0.0, diff = 0.0;
    for (size_t c = 0; c < serial.size(); ++c)
      largest = std::max(largest, std::fabs(serial[c])), diff = std::max(diff, std::fabs(serial[c] - natural[c]));
    PetscCall(PetscPrintf(PETSC_COMM_SELF, "quantised weights: all ranks vs one rank, largest difference %.3g of %.3g\n",
                          diff, largest));
    RCFD_CHECK(serial.size() == natural.size());
    RCFD_CHECK(diff <= 1e-13 * largest);
  }
  PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// Largest-remainder rounding on a hand-made column: thirds over 2^2 units.
void quantiseByHand() {
  CsrMatrix T;
  T.n = 3;
  T.rowPtr = {0, 1, 2, 3};
  T.col = {0, 0, 0};
  T.val = {1.0 / 3, 1.0 / 3, 1.0 / 3}; // column 0; columns 1 and 2 hold nothing
  bool refused = false;
  try {
    quantiseWeights(&T, 2);
  } catch (const std::invalid_argument &) {
    refused = true; // columns 1 and 2 are empty
  }
  RCFD_CHECK(refused);
  T.rowPtr = {0, 2, 3, 5}; // column 0 spread over rows 0, 1, 2; columns 1 and 2 stay
  T.col = {0, 1, 0, 0, 2};
  T.val = {0.3, 1.0, 0.3, 0.4, 1.0};
  quantiseWeights(&T, 3); // column 0: 0.3, 0.3, 0.4 of 8 units = 2.4, 2.4, 3.2 -> 2 + 1, 2, 3
  RCFD_CHECK(T.val.size() == 5);
  RCFD_CHECK(T.val[0] == 3.0 / 8 && T.val[2] == 2.0 / 8 && T.val[3] == 3.0 / 8);
  RCFD_CHECK(T.val[1] == 1.0 && T.val[4] == 1.0);
}

PetscErrorCode expectRefusal(const std::string &path, const std::string &expected) {
  PetscFunctionBeginUser;
  const std::string text = test::loadRefusal(path);
  if (text.find(expected) == std::string::npos)
    rcfd::test::fail(__FILE__, __LINE__, path + ": expected an error containing '" + expected + "', got '" + text + "'");
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode badQuantisationRefused(const std::string &dir, const std::string &small, const std::string &quantised) {
  PetscFunctionBeginUser;
  const std::string outOfRange = dir + "/bits_out_of_range.h5", notQuantised = dir + "/not_quantised.h5";
  // Weights that break the promise can only be stored as doubles: version 2.
  PetscCall(test::rewriteDatabase(small, notQuantised, 0, 2));
  if (rank == 0) {
    namespace fs = std::filesystem;
    fs::copy_file(quantised, outOfRange, fs::copy_options::overwrite_existing);
    h5::File::openReadWrite(outOfRange).writeAttr("/metadata", "weight_bits", 17LL);
    h5::File::openReadWrite(notQuantised).writeAttr("/metadata", "weight_bits", 16LL);
    // The writer keeps the promise weight_bits makes.
    bool refused = false;
    try {
      DatabaseMetadata meta;
      meta.weightBits = 16;
      DatabaseFileWriter w(dir + "/unwritten.h5", rcfd::test::boxMesh(BoxSpec{2, 1, 1, {0, 0, 0}, {1, 1, 1}}), meta);
      FrameRecord f;
      f.alphaS = {0.5, 0.5};
      f.shift.n = 2;
      f.shift.rowPtr = {0, 2, 3};
      f.shift.col = {0, 1, 1};
      f.shift.val = {0.3, 0.1, 0.9}; // neither multiples of 2^-16 nor columns of exactly 1
      w.append(f);
    } catch (const std::invalid_argument &e) {
      refused = std::string(e.what()).find("not a multiple of 2^-16") != std::string::npos;
    }
    RCFD_CHECK(refused);
  }
  PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
  PetscCall(expectRefusal(outOfRange, "/metadata weight_bits is 17, expected the number of bits of its quantised weights, 1 to 16"));
  PetscCall(expectRefusal(notQuantised, "the database says its weights are quantised to multiples of 2^-16 (/metadata weight_bits)"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

int main(int argc, char **argv) {
  return rcfd::test::rankTestMain(argc, argv, "compact_frames", [&](const std::string &dir) -> PetscErrorCode {
    PetscFunctionBeginUser;
    MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
    const std::string small = std::string(argv[1]) + "/small.h5", quantised = dir + "/small_q16.h5";
    PetscCall(sameBitsAsMatMult(small));
    quantiseByHand();
    PetscCall(quantisedConservesExactly(small, quantised));
    PetscCall(badQuantisationRefused(dir, small, quantised));
    PetscFunctionReturn(PETSC_SUCCESS);
  });
}
