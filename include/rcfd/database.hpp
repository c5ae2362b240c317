// The recurrence database: a mesh, metadata and K frames, each the bulk solid
// volume fraction alpha_s per cell and the shift matrix T_k.  See
// docs/database-format.md for the file layout.
#pragma once

#include "rcfd/frames.hpp"
#include "rcfd/handle.hpp"
#include "rcfd/layout.hpp"
#include "rcfd/mesh.hpp"

#include <algorithm>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace rcfd {

/// Version written (3: the shifts' moving rows only); versions 1 (without
/// operating conditions) and 2 (full CSR shifts) are still read.
inline constexpr long long kDatabaseFormatVersion = 3;

/// The operating conditions of a fluidized bed: what a database was recorded
/// at (format version 2, attributes on /metadata) or what a case runs at.
/// NaN means "not given".  mu = rho_g nu.
struct OperatingConditions {
  double superficialVelocity = std::numeric_limits<double>::quiet_NaN();   ///< u_sup [m/s]
  double gasDensity = std::numeric_limits<double>::quiet_NaN();            ///< rho_g [kg/m^3]
  double gasKinematicViscosity = std::numeric_limits<double>::quiet_NaN(); ///< nu [m^2/s]

  /// Collective.  Reads -superficial_velocity [m/s], -gas_density [kg/m^3] and
  /// -gas_kinematic_viscosity [m^2/s]; those not given stay NaN.  Refuses a
  /// value that is not positive and finite, naming the option.
  /// src/database/operating_conditions.cpp
  static PetscErrorCode fromOptions(MPI_Comm comm, OperatingConditions *conditions);
};

struct DatabaseMetadata {
  double dtRec = 5e-3;          // time between frames [s]
  double solidDensity = 1440.0; // particle material density [kg/m^3]
  Vec3 gravity{0.0, 0.0, -9.81}; // [m/s^2]
  std::string source;           // how the database was made, for humans
  std::string units = "SI";
  OperatingConditions conditions; // format version 2; NaN: not recorded
  /// > 0: every shift weight is a multiple of 2^-weightBits and every column
  /// sums to exactly 1 (/metadata weight_bits, docs/database-format.md,
  /// "Quantised weights"); the loader holds such weights in 2 bytes.  0: full
  /// precision.  At most kMaxWeightBits.
  int weightBits = 0;
};

/// Finest quantisation a database may record: numerators - 1 fit 16 bits.
inline constexpr int kMaxWeightBits = 16;

class DatabaseFileWriter; // the implementation (src/database)

/// Writes a database file from one process, frame by frame (not collective:
/// one rank writes, the others wait before they load it).  The file is
/// written under a temporary name and renamed by finish(), so a file with
/// the final name is always complete; a writer destroyed unfinished leaves
/// no file.  Bad input is refused with PETSC_ERR_ARG_WRONG, a file that
/// cannot be written with PETSC_ERR_FILE_WRITE, each in one sentence.
class DatabaseWriter {
public:
  DatabaseWriter();
  ~DatabaseWriter();
  DatabaseWriter(const DatabaseWriter &) = delete;
  DatabaseWriter &operator=(const DatabaseWriter &) = delete;

  /// Starts the file `path` of this mesh and metadata.  `formatVersion` 2
  /// writes the full CSR of older readers; the current version is the default.
  PetscErrorCode create(const std::string &path, const Mesh &mesh, const DatabaseMetadata &meta,
                        long long formatVersion = kDatabaseFormatVersion);
  PetscErrorCode append(const FrameRecord &frame);
  /// Store an extra 2-D dataset (e.g. the recurrence matrix) before finish().
  PetscErrorCode writeMatrix(const std::string &name, const std::vector<double> &rowMajor, int cols,
                             const std::string &note);
  /// Store a text attribute `key` on /metadata before finish() (e.g. a
  /// builder's report as "build_report"); `key` must not be a format attribute.
  PetscErrorCode setNote(const std::string &key, const std::string &text);
  /// Stores the frame count and the content hash and gives the file its name.
  PetscErrorCode finish();
  int numFrames() const;

private:
  std::unique_ptr<DatabaseFileWriter> file;
};

struct DatabaseLoadOptions {
  double columnTolerance = 1e-9; // |column sum - 1| allowed before refusing a shift
  int firstFrame = 0, lastFrame = -1; // frame window to load (-1: to the end)
  bool loadShifts = true;
  /// Load onto this layout instead of partitioning the mesh (a database set's
  /// one partition, include/rcfd/database_set.hpp); it must be of the same mesh.
  const Layout *layout = nullptr;
};

/// What a database file says before its frames are read (Database::readHeader).
struct DatabaseHeader {
  std::string identity;
  long long formatVersion = 0; ///< of the file (docs/database-format.md, "Versions")
  /// Whether the file carries checksums (docs/database-format.md, "Checksums"):
  /// then every byte the load reads is checked; an older file's cannot be.
  bool checksummed = false;
  Mesh mesh;
  DatabaseMetadata metadata;
  int numFrames = 0;     ///< in the window of DatabaseLoadOptions
  std::vector<int> work; ///< per cell (natural order): what Database::load partitions by
};

/// A database held in memory, distributed over the ranks of its layout.
class Database {
public:
  /// Collective.  Reads the mesh on every rank, partitions it, and reads each
  /// rank's rows of every frame.  Refuses, with a sentence naming the file and
  /// the fault, files that are not rcfd databases, have another format
  /// version, miss a group, have sizes that do not match the mesh, negative
  /// or non-finite entries, or shift columns that do not sum to 1.  Columns
  /// within tolerance are rescaled so that they sum to 1 to round-off.
  static PetscErrorCode load(MPI_Comm comm, const std::string &path,
                             const DatabaseLoadOptions &options, std::unique_ptr<Database> *db);
  /// Collective.  The header of a database file and the work per cell of the
  /// frames in the window, without loading the frames; refuses what load() refuses
  /// of the header.
  static PetscErrorCode readHeader(MPI_Comm comm, const std::string &path,
                                   const DatabaseLoadOptions &options, DatabaseHeader *header);
  /// A database made in memory on the mesh, layout and metadata of `like`,
  /// with its own frames (e.g. two databases blended, rcfd/database_set.hpp):
  /// alpha_s and the shifts, one per frame, on like's layout; collective.
  /// The shifts are held as compact frames (full precision) like a loaded
  /// database's, the matrices are not kept.  `wrapsAfter`: frames k whose
  /// next, k + 1, is not what follows k in time (a blend's frame where one of
  /// its databases wraps); see nextFollows().
  static PetscErrorCode fromFrames(const Database &like, const std::string &identity, std::vector<OwnedVec> alpha,
                                   std::vector<OwnedMat> shifts, std::unique_ptr<Database> *out,
                                   std::vector<int> wrapsAfter = {});
  Database();
  ~Database();
  Database(const Database &) = delete;
  Database &operator=(const Database &) = delete;
  /// Read the options -db_column_tolerance, -db_frames first:last.
  static PetscErrorCode optionsFromCommandLine(DatabaseLoadOptions *options);

  const std::string &path() const { return path_; }
  /// What identifies the database's contents (docs/database-format.md,
  /// "Identity"): "content <hash>" from the content_hash its writer stored, or
  /// for an older file "made <hash>" of when and how it was made.
  const std::string &identity() const { return identity_; }
  /// Format version of the file it was loaded from (0: made in memory).
  long long formatVersion() const { return formatVersion_; }
  /// Whether the file it was loaded from carries checksums, so that what was
  /// loaded was checked (docs/database-format.md, "Checksums").
  bool checksummed() const { return checksummed_; }
  const Mesh &mesh() const { return mesh_; }
  const Layout &layout() const { return layout_; }
  const DatabaseMetadata &metadata() const { return meta; }
  int numFrames() const { return static_cast<int>(alpha.size()); }
  /// Bulk solid volume fraction of frame k (PETSc ordering, not to be modified).
  Vec alphaS(int k) const { return alpha[k]; }
  /// Whether frame k + 1 is the frame that follows frame k in time, so that
  /// frame k's shift moves alpha_k onto alpha_{k+1}: false after the last
  /// frame, and after a frame of a blend where one of its databases wraps
  /// (rcfd/database_set.hpp).  A run steps from a frame without a follower as
  /// a jump (the carry remaps the state onto the next frame's bulk).
  bool nextFollows(int k) const {
    return k + 1 < numFrames() && !std::binary_search(wrapsAfter_.begin(), wrapsAfter_.end(), k);
  }
  bool hasShifts() const { return !frames_.empty(); }
  /// Collective.  The shift matrix of frame k, which moves solid mass from t_k
  /// to t_k + dt_rec, built from the compact frame on each call (an MPIAIJ
  /// matrix of all rows, identity rows included; for the MAIJ kernel, exports
  /// and checks).  The run's kernel reads frame(k) instead.
  PetscErrorCode shiftMatrix(int k, OwnedMat *T) const;
  /// This rank's moving rows of frame k's shift (include/rcfd/frames.hpp).
  const CompactFrame &frame(int k) const { return frames_[k]; }
  /// PETSc rows of the other ranks' cells that any frame's moving rows read,
  /// ascending: the column nlocal + g of a compact frame is ghostRows()[g].
  const std::vector<PetscInt> &ghostRows() const { return ghostRows_; }
  /// Bytes of this rank's compact frames (all frames).
  size_t frameBytes() const;
  /// Local cell volumes in PETSc order.
  const std::vector<double> &localVolumes() const { return volumes; }
  /// Relative mass mismatch ||T_k V a_k - V a_{k+1}||_1 / ||V a_k||_1 of each
  /// consecutive pair (collective).
  PetscErrorCode consistency(std::vector<double> *residual) const;
  /// Stored 2-D dataset written by DatabaseWriter::writeMatrix, read on every
  /// rank; empty when absent.
  PetscErrorCode readMatrix(const std::string &name, std::vector<double> *rowMajor,
                            int *cols) const;
  PetscErrorCode view(PetscViewer viewer) const;

private:
  std::string path_, identity_;
  long long formatVersion_ = 0;
  bool checksummed_ = false;
  Mesh mesh_;
  Layout layout_;
  DatabaseMetadata meta;
  std::vector<OwnedVec> alpha;
  std::vector<CompactFrame> frames_; // the shifts, as this rank's moving rows
  std::vector<PetscInt> ghostRows_;
  std::vector<int> wrapsAfter_; // ascending: frames followed by another than their next (nextFollows)
  void numberGhostRows(); // sorts ghostRows_ and renumbers the frames' ghost columns
  std::vector<double> volumes;
  double maxColumnError = 0.0;
};

} // namespace rcfd
