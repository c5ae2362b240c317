// Database loading (include/rcfd/database.hpp): the header on every rank,
// the partition balanced on the frames' filled cells, and the frames read in
// batches, each rank its own rows, rescaled and compacted; and databases
// made from frames in memory.
#include "rcfd/database.hpp"
#include "base/checked_options.hpp"
#include "base/petsc_compat.hpp"

#include "base/collective.hpp"
#include "base/h5.hpp"
#include "database/compact_frames.hpp"
#include "database/database_header.hpp"
#include "database/local_frame.hpp"
#include "database/stored_frame.hpp"

#include <algorithm>

namespace rcfd {

PetscErrorCode Database::optionsFromCommandLine(DatabaseLoadOptions *o) {
  PetscInt window[2] = {o->firstFrame, o->lastFrame};
  PetscInt nwindow = 2;
  PetscFunctionBeginUser;
  PetscOptionsBegin(PETSC_COMM_WORLD, nullptr, "Database loading", "rcfd");
  PetscCall(checkedReal(PetscOptionsObject, "-db_column_tolerance",
                        "Largest |column sum - 1| of a shift matrix accepted on load",
                        &o->columnTolerance, kPositive));
  PetscCall(checkedIntArray(PetscOptionsObject, "-db_frames",
                            "First and last frame to load (last -1: to the end)", window, &nwindow, nullptr));
  // Read by Layout::create while loading; registered here so that -help lists
  // it and the check for unknown options, which runs before loading, knows it.
  PetscBool viewPartition = PETSC_FALSE;
  PetscCall(PetscOptionsBool("-partition_view", "Print each rank's rows and share of the work", "",
                             viewPartition, &viewPartition, nullptr));
  PetscOptionsEnd();
  o->firstFrame = window[0];
  o->lastFrame = window[1];
  PetscFunctionReturn(PETSC_SUCCESS);
}

namespace {

// Number of frames in which each cell holds solid: the work a cell costs
// the shift and the swaps.  In a bubbling bed about half of the domain is
// freeboard that never holds any, and the splash zone only sometimes; the
// partition balances this count (balancing the cells gave one of two ranks
// the whole bed, balancing the ever-filled cells left one with 50 % more
// moving rows).  The ranks read the frames' alpha_s in turns; a
// frame whose alpha_s is missing or of the wrong size is skipped here and
// refused by the reader afterwards.
PetscErrorCode framesFilled(MPI_Comm comm, const h5::File &file, int first, int last, int n,
                            std::vector<int> *filled) {
  PetscMPIInt rank, size;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  filled->assign(n, 0);
  PetscCall(collectively(comm, [&] {
    for (int k = first + rank; k <= last; k += size) {
      const std::string name = frameGroup(k) + "/alpha_s";
      if (!file.exists(frameGroup(k)) || !file.exists(name)) continue;
      const auto dims = file.extents(name);
      if (dims.size() != 1 || dims[0] != static_cast<hsize_t>(n)) continue;
      std::vector<double> alpha;
      try {
        alpha = file.read<double>(name);
      } catch (const h5::Damaged &d) {
        throwDamagedFrame(d, file, k);
      }
      for (int c = 0; c < n; ++c)
        if (alpha[c] > 0.0) ++(*filled)[c];
    }
  }));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, filled->data(), n, MPI_INT, MPI_SUM, comm));
  // Every cell also costs the whole-field passes (monitors, mass checks):
  // about a tenth of a cell that is always filled.
  for (int &w : *filled) w += (last - first + 1) / 10 + 1;
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

namespace {

// The header of a database file on every rank, and its number of frames; the
// file stays open for the frames.
PetscErrorCode openHeader(MPI_Comm comm, const std::string &path, h5::File *file, DatabaseHeader *h,
                          long long *K) {
  PetscFunctionBeginUser;
  // The header is read on every rank from the same file, so any failure is
  // the same everywhere; collectively() still guards against a rank that
  // could not open the file.
  PetscCall(collectively(comm, [&] {
    *file = h5::File::openRead(path, comm);
    h->checksummed = file->checksums() == h5::Checksums::fletcher32;
    h->formatVersion = checkFormat(*file);
    h->metadata = readMetadata(*file);
    h->identity = readIdentity(*file);
    h->mesh = readMesh(*file);
    file->requireGroup("/frames");
    *K = file->readAttrInt("/frames", "num_frames");
    if (*K < 1) throw h5::Error("database '" + path + "' has no frames");
    for (long long k = 0; k < *K; ++k)
      if (!file->exists(frameGroup(static_cast<int>(k))))
        throw h5::Error("database '" + path + "' says it has " + std::to_string(*K) +
                        " frames but group " + frameGroup(static_cast<int>(k)) + " is missing");
  }));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The frame window [first, last] of the options, checked against the file's K frames.
PetscErrorCode frameWindow(MPI_Comm comm, const std::string &path, const DatabaseLoadOptions &options,
                           long long K, int *first, int *last) {
  PetscFunctionBeginUser;
  *first = options.firstFrame;
  *last = options.lastFrame < 0 ? (int)K - 1 : options.lastFrame;
  PetscCheck(*first >= 0 && *first <= *last && *last < K, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "-db_frames %d:%d is outside the %lld frames of database '%s'", *first, *last, K,
             path.c_str());
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

PetscErrorCode Database::readHeader(MPI_Comm comm, const std::string &path,
                                    const DatabaseLoadOptions &options, DatabaseHeader *header) {
  h5::File file;
  long long K = 0;
  int first = 0, last = 0;
  PetscFunctionBeginUser;
  PetscCall(openHeader(comm, path, &file, header, &K));
  PetscCall(frameWindow(comm, path, options, K, &first, &last));
  header->numFrames = last - first + 1;
  PetscCall(framesFilled(comm, file, first, last, header->mesh.numCells(), &header->work));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Database::load(MPI_Comm comm, const std::string &path,
                              const DatabaseLoadOptions &options, std::unique_ptr<Database> *out) {
  PetscFunctionBeginUser;
  auto db = std::make_unique<Database>();
  db->path_ = path;
  h5::File file;
  long long K = 0;
  int first = 0, last = 0;
  DatabaseHeader header;
  PetscCall(openHeader(comm, path, &file, &header, &K));
  db->meta = header.metadata;
  db->identity_ = header.identity;
  db->formatVersion_ = header.formatVersion;
  db->checksummed_ = header.checksummed;
  db->mesh_ = std::move(header.mesh);
  if (!header.checksummed)
    PetscCall(PetscPrintf(comm,
                          "Note: database '%s' has no checksums (an older rcfd wrote it), so damage to it cannot be "
                          "detected; rcfd coarsen %s -factor 1,1,1 -o NEW writes a copy that has them\n",
                          path.c_str(), path.c_str()));
  PetscCall(frameWindow(comm, path, options, K, &first, &last));
  if (options.layout) { // a database set's one partition: no work to count
    PetscCheck(options.layout->numCells() == db->mesh_.numCells(), comm, PETSC_ERR_ARG_INCOMP,
               "Database '%s' has %d cells but the layout it is to be loaded onto has %d",
               path.c_str(), db->mesh_.numCells(), (int)options.layout->numCells());
    db->layout_ = *options.layout;
  } else { // on one rank the numbering is the natural one: no work to balance
    PetscMPIInt size;
    PetscCallMPI(MPI_Comm_size(comm, &size));
    std::vector<int> filled;
    if (size > 1) PetscCall(framesFilled(comm, file, first, last, db->mesh_.numCells(), &filled));
    PetscCall(Layout::create(comm, db->mesh_, &db->layout_, size > 1 ? &filled : nullptr));
  }
  const Layout &L = db->layout_;
  for (PetscInt c : L.ownedNatural()) db->volumes.push_back(db->mesh_.cellVolume[c]);

  // The frames in batches: each rank reads its rows of a batch on its own,
  // then the ranks meet once to agree that every rank read them, once to sum
  // their columns and once to agree that they were compacted (a rank that
  // fails still comes to every meeting, so no rank waits for ever).
  ColumnCheck check;
  check.tolerance = options.columnTolerance;
  check.weightBits = db->meta.weightBits;
  check.batch = batchFor(L);
  OwnedVec alphaLike; // a vector of the layout: its copies need no communication
  PetscCall(VecCreateMPI(comm, L.numLocal(), L.numCells(), alphaLike.put()));
  for (int batchFirst = first; batchFirst <= last; batchFirst += check.batch) {
    const int batchLast = std::min(last, batchFirst + check.batch - 1);
    std::vector<LocalFrame> frames;
    std::vector<std::string> where;
    PetscCall(collectively(comm, [&] {
      for (int k = batchFirst; k <= batchLast; ++k) {
        frames.push_back(readLocalFrame(file, header.formatVersion, db->meta.weightBits, k, L, options.loadShifts));
        where.push_back("database '" + path + "', frame " + std::to_string(k));
      }
    }));
    for (LocalFrame &fr : frames) {
      OwnedVec a;
      PetscCall(VecDuplicate(alphaLike, a.put()));
      PetscScalar *pa;
      PetscCall(VecGetArrayWrite(a, &pa));
      std::copy(fr.alpha.begin(), fr.alpha.end(), pa);
      PetscCall(VecRestoreArrayWrite(a, &pa));
      db->alpha.push_back(std::move(a));
    }
    if (!options.loadShifts) continue;
    std::vector<LocalShiftRows> shifts;
    for (LocalFrame &fr : frames) shifts.push_back(std::move(fr.shift));
    frames.clear();
    PetscCall(rescaleColumns(L, &shifts, where, &check));
    PetscCall(collectively(comm, [&] {
      for (size_t j = 0; j < shifts.size(); ++j)
        db->frames_.push_back(
            compactFrame(shifts[j], L.rowStart(), L.numLocal(), check.weightBits, where[j], &db->ghostRows_));
    }));
  }
  PetscCall(PetscInfo(nullptr, "%s: %d frames, column-sum scatter built %d times over %zu ghost columns\n",
                      path.c_str(), last - first + 1, check.scattersBuilt, check.ghosts.size()));
  db->maxColumnError = check.largestError;
  db->numberGhostRows();
  *out = std::move(db);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Database::fromFrames(const Database &like, const std::string &identity, std::vector<OwnedVec> alpha,
                                  std::vector<OwnedMat> shifts, std::unique_ptr<Database> *out,
                                  std::vector<int> wrapsAfter) {
  PetscFunctionBeginUser;
  auto db = std::make_unique<Database>();
  std::sort(wrapsAfter.begin(), wrapsAfter.end());
  db->wrapsAfter_ = std::move(wrapsAfter);
  db->path_ = like.path_;
  db->identity_ = identity;
  db->mesh_ = like.mesh_;
  db->layout_ = like.layout_;
  db->meta = like.meta;
  db->meta.weightBits = 0; // the frames are made here, in full precision
  db->volumes = like.volumes;
  db->alpha = std::move(alpha);
  const Layout &L = db->layout_;
  for (const OwnedMat &T : shifts) {
    LocalShiftRows rows; // this rank's rows, columns sorted as MatGetRow gives them
    rows.rowPtr.push_back(0);
    for (PetscInt r = L.rowStart(); r < L.rowEnd(); ++r) {
      PetscInt n;
      const PetscInt *c;
      const PetscScalar *v;
      PetscCall(MatGetRow(T, r, &n, &c, &v));
      rows.col.insert(rows.col.end(), c, c + n);
      rows.val.insert(rows.val.end(), v, v + n);
      PetscCall(MatRestoreRow(T, r, &n, &c, &v));
      rows.rowPtr.push_back(static_cast<PetscInt>(rows.col.size()));
    }
    PetscCall(collectively(L.comm(), [&] {
      db->frames_.push_back(compactFrame(rows, L.rowStart(), L.numLocal(), 0, identity, &db->ghostRows_));
    }));
  }
  db->numberGhostRows();
  *out = std::move(db);
  PetscFunctionReturn(PETSC_SUCCESS);
}

void Database::numberGhostRows() {
  // Other ranks' cells get their place in the list of all frames' ghosts.
  std::sort(ghostRows_.begin(), ghostRows_.end());
  ghostRows_.erase(std::unique(ghostRows_.begin(), ghostRows_.end()), ghostRows_.end());
  ghostRows_.shrink_to_fit();
  for (CompactFrame &f : frames_) numberGhosts(&f, layout_.numLocal(), ghostRows_);
}

} // namespace rcfd
