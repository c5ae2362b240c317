// rcfd coarsen: an exactly coarsened copy of a database (src/database/coarsen.hpp).
#include "cli/commands.hpp"
#include "base/petsc_compat.hpp"
#include "mesh/box_mesh.hpp"
#include "base/checked_options.hpp"

#include "base/atomic_file.hpp"
#include "base/collective.hpp"
#include "base/h5.hpp"
#include "database/coarsen.hpp"
#include "database/quantise.hpp"
#include "database/stored_frame.hpp"
#include "rcfd/database.hpp"
#include "database/database_file_writer.hpp"

#include <cstdio>
#include <cstdlib>
#include <optional>
#include <stdexcept>

namespace rcfd::cli {
namespace {

// An initial composition (/masses [cells x fractions], as rcfd build -init_out
// writes it) summed into the coarse cells, with its attributes.
void coarsenInitialMasses(const std::string &in, const std::string &out, const CoarseBox &coarse, int fineCells) {
  const h5::File f = h5::File::openRead(in, MPI_COMM_NULL);
  const auto dims = f.extents("/masses");
  if (dims.size() != 2 || dims[0] != static_cast<hsize_t>(fineCells))
    throw std::runtime_error("-init_file '" + in + "': /masses should be " + std::to_string(fineCells) +
                             " cells x fractions to match the database");
  const std::size_t nf = dims[1];
  const auto fine = f.read<double>("/masses");
  std::vector<double> masses(static_cast<std::size_t>(coarse.numCells()) * nf, 0.0);
  for (int c = 0; c < fineCells; ++c)
    for (std::size_t i = 0; i < nf; ++i) masses[coarse.coarseOf[c] * nf + i] += fine[c * nf + i];
  AtomicFile file(out);
  h5::File g = h5::File::create(file.temporaryPath(), h5::Checksums::fletcher32);
  g.write("/masses", masses, static_cast<hsize_t>(nf));
  for (const char *a : {"diameters", "mass_shares"})
    if (f.hasAttribute("/masses", a)) g.writeAttr("/masses", a, f.readAttrDoubles("/masses", a));
  g.writeAttr("/masses", "note", std::string("summed into coarse cells by rcfd coarsen from ") + in);
  g.close();
  file.commit();
}

// The precision -weights asks for: "full" (or 0, its first spelling) gives 0,
// B in 1..kMaxWeightBits quantised weights of B bits; nothing for any other text.
std::optional<int> requestedWeightBits(const std::string &given) {
  if (given == "full") return 0;
  char *end = nullptr;
  const long bits = std::strtol(given.c_str(), &end, 10);
  if (given.empty() || *end != '\0' || bits < 0 || bits > kMaxWeightBits) return std::nullopt;
  return static_cast<int>(bits);
}

} // namespace

PetscErrorCode coarsenCommand(MPI_Comm comm, const char *positional) {
  char in[PETSC_MAX_PATH_LEN] = "", out[PETSC_MAX_PATH_LEN] = "", initIn[PETSC_MAX_PATH_LEN] = "",
       initOut[PETSC_MAX_PATH_LEN] = "", weights[16] = "input";
  PetscInt factor[3] = {1, 1, 1}, nfactor = 3, timeFactor = 1;
  PetscBool setIn = PETSC_FALSE, setOut = PETSC_FALSE, setFactor = PETSC_FALSE, quiet = PETSC_FALSE;
  PetscMPIInt size;
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, nullptr, "rcfd coarsen: an exactly coarsened copy of a database", "rcfd");
  PetscCall(PetscOptionsString("-db", "Database file (or give it as the first argument)", "", "", in, sizeof in,
                               &setIn));
  PetscCall(PetscOptionsString("-o", "Coarsened database file", "", "", out, sizeof out, &setOut));
  PetscCall(checkedIntArray(PetscOptionsObject, "-factor",
                            "Fine cells per coarse cell along x,y,z (each divides the cell count)", factor,
                            &nfactor, &setFactor));
  PetscCall(PetscOptionsInt("-time_factor", "Frames per coarse frame: 1, or 2 (each pair composed, dt_rec doubled)",
                            "", timeFactor, &timeFactor, nullptr));
  PetscCall(PetscOptionsString("-init_file", "Also coarsen this initial composition (HDF5 /masses, e.g. from rcfd build -init_out)",
                               "", "", initIn, sizeof initIn, nullptr));
  PetscCall(PetscOptionsString("-init_out", "Where the coarsened initial composition goes", "", "", initOut,
                               sizeof initOut, nullptr));
  PetscCall(PetscOptionsString("-weights",
                               "Shift weights: B (multiples of 2^-B with exact column sums), full, or input (the input's precision)",
                               "", weights, weights, sizeof weights, nullptr));
  PetscCall(PetscOptionsBool("-quiet", "No report", "", quiet, &quiet, nullptr));
  PetscOptionsEnd();
  if (helpRequested()) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(rejectUnusedOptions(comm, "coarsen"));
  const std::string file = positional ? positional : in;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCheck(size == 1, comm, PETSC_ERR_SUP, "rcfd coarsen runs on one rank (it reads the whole database)");
  PetscCheck(!file.empty(), comm, PETSC_ERR_USER_INPUT, "No database given: rcfd coarsen FILE -factor 2,1,2 -o OUT");
  PetscCheck(setOut && out[0], comm, PETSC_ERR_USER_INPUT, "rcfd coarsen needs -o FILE for the coarsened database");
  PetscCheck(!setFactor || nfactor == 3, comm, PETSC_ERR_USER_INPUT, "-factor takes three counts fx,fy,fz");
  PetscCheck(timeFactor == 1 || timeFactor == 2, comm, PETSC_ERR_USER_INPUT,
             "-time_factor %d: expected 1 or 2 (compose twice for 4)", (int)timeFactor);
  const bool keepPrecision = std::string(weights) == "input";
  const std::optional<int> requestedBits = keepPrecision ? std::nullopt : requestedWeightBits(weights);
  PetscCheck(keepPrecision || requestedBits, comm, PETSC_ERR_USER_INPUT,
             "-weights '%s': expected the bits of the quantised weights, 1 to %d, full, or input", weights,
             kMaxWeightBits);
  PetscCheck(!initIn[0] == !initOut[0], comm, PETSC_ERR_USER_INPUT, "-init_file and -init_out go together");
  PetscCheck(file != out, comm, PETSC_ERR_USER_INPUT, "-o names the input database; give another file");
  // The loader checks the file's format and sizes and gives mesh and metadata;
  // the frames are read below as stored, so it need not build the shifts.
  DatabaseLoadOptions headerOnly;
  headerOnly.loadShifts = false;
  std::unique_ptr<Database> db;
  PetscCall(Database::load(comm, file, headerOnly, &db));
  const int cells = db->mesh().numCells();
  PetscCheck(db->mesh().onBoxLattice(), comm, PETSC_ERR_SUP, "Database '%s': rcfd coarsen needs a box mesh",
             file.c_str());
  const int K = db->numFrames() / static_cast<int>(timeFactor);
  PetscCheck(K >= 1, comm, PETSC_ERR_USER_INPUT, "Database '%s' has too few frames for -time_factor %d",
             file.c_str(), (int)timeFactor);
  CoarseBox coarse;
  Mesh coarseMesh; // a vessel's (docs/vessels.md); a box's is boxMesh(coarse.box)
  PetscCall(collectively(comm, [&] {
    const std::array<int, 3> f{(int)factor[0], (int)factor[1], (int)factor[2]};
    if (db->mesh().isMasked()) coarseMesh = coarsenVesselMesh(db->mesh(), f, &coarse);
    else coarse = coarsenBox(db->mesh().boxSpec(), f);
  }, PETSC_ERR_USER_INPUT));
  DatabaseMetadata meta = db->metadata();
  // Unless asked otherwise the output keeps the input's precision: a quantised
  // input's coarse frames are quantised again to its bits (for factor 1 that
  // is exact: weights already quantised to B bits come back unchanged).
  const int weightBits = requestedBits.value_or(meta.weightBits);
  const std::string precision = weightBits > 0       ? " -weights " + std::to_string(weightBits)
                                : meta.weightBits > 0 ? " -weights full"
                                                      : "";
  meta.dtRec *= static_cast<double>(timeFactor);
  meta.source = "rcfd coarsen " + file + " -factor " + std::to_string(factor[0]) + "," + std::to_string(factor[1]) +
                "," + std::to_string(factor[2]) + " -time_factor " + std::to_string(timeFactor) + precision + " (" +
                db->metadata().source + ")";
  meta.weightBits = weightBits;
  std::unique_ptr<DatabaseFileWriter> writer;
  PetscCall(collectively(comm, [&] {
    writer = std::make_unique<DatabaseFileWriter>(out, coarse.cells > 0 ? coarseMesh : boxMesh(coarse.box), meta);
  }));
  const std::vector<double> &volume = db->mesh().cellVolume;
  int64_t nnz = 0;
  PetscCall(collectively(comm, [&] {
    const h5::File f = h5::File::openRead(file, MPI_COMM_NULL);
    for (int k = 0; k < K; ++k) {
      FrameRecord a = readStoredFrame(f, static_cast<int>(timeFactor) * k, cells);
      if (timeFactor == 2) a = composeFrames(a, readStoredFrame(f, 2 * k + 1, cells));
      FrameRecord c = coarsenFrame(a, volume, coarse);
      if (weightBits > 0) quantiseWeights(&c.shift, weightBits);
      nnz += c.shift.nnz();
      writer->append(c);
    }
  }));
  PetscCall(collectively(comm, [&] { writer->finish(); }));
  if (initIn[0])
    PetscCall(collectively(comm, [&] { coarsenInitialMasses(initIn, initOut, coarse, cells); }, PETSC_ERR_USER_INPUT));
  if (!quiet)
    PetscCall(PetscPrintf(comm, "Wrote %s: %d x %d x %d cells, %d frames every %g s, %.3g shift nonzeros per column%s\n",
                          out, coarse.box.nx, coarse.box.ny, coarse.box.nz, K, meta.dtRec,
                          static_cast<double>(nnz) / (static_cast<double>(K) * coarse.numCells()),
                          weightBits > 0 ? (", weights quantised to 2^-" + std::to_string(weightBits)).c_str() : ""));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
