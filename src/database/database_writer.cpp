// DatabaseFileWriter (database_file_writer.hpp): a database file written
// frame by frame through an atomic file, with its content hash; and
// DatabaseWriter (include/rcfd/database.hpp), its PETSc-style face.
#include "database/database_file_writer.hpp"
#include "base/petsc_compat.hpp"

#include "base/atomic_file.hpp"
#include "base/h5.hpp"
#include "database/content_hash.hpp"
#include "database/database_header.hpp"
#include "database/stored_frame.hpp"

#include <cmath>
#include <ctime>
#include <stdexcept>

namespace rcfd {
namespace {

std::string nowUtc() {
  char text[32];
  const std::time_t t = std::time(nullptr);
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return text;
}

// A database that records weight_bits promises what the loader then relies
// on: weights that are multiples of 2^-bits in (0, 1], columns summing to 1
// exactly.  Its writer refuses a frame that breaks the promise.
void checkQuantised(const CsrMatrix &T, int bits, int k) {
  const double scale = std::ldexp(1.0, bits);
  std::vector<double> sum(T.n, 0.0);
  for (size_t e = 0; e < T.val.size(); ++e) {
    const double numerator = T.val[e] * scale;
    if (!(numerator >= 1.0 && numerator <= scale && numerator == std::floor(numerator)))
      throw std::invalid_argument("frame " + std::to_string(k) + ": shift weight " + std::to_string(T.val[e]) +
                                  " is not a multiple of 2^-" + std::to_string(bits) + " in (0, 1]");
    sum[T.col[e]] += T.val[e];
  }
  for (int c = 0; c < T.n; ++c)
    if (sum[c] != 1.0)
      throw std::invalid_argument("frame " + std::to_string(k) + ": shift column " + std::to_string(c) +
                                  " of quantised weights sums to " + std::to_string(sum[c]) + ", not exactly 1");
}

} // namespace

struct DatabaseFileWriter::Impl {
  explicit Impl(const std::string &path) : out(path) {}
  AtomicFile out; // declared first: the file is closed before an unfinished temporary is removed
  h5::File file;
  int cells = 0;
  int weightBits = 0; // > 0: every frame must be quantised so (checked by append)
  long long version = kDatabaseFormatVersion;
  ContentHash hash; // of every frame's arrays, stored as content_hash by finish()
};

DatabaseFileWriter::DatabaseFileWriter(const std::string &path, const Mesh &mesh, const DatabaseMetadata &meta,
                                       long long formatVersion)
    : impl(std::make_unique<Impl>(path)) {
  if (formatVersion != 2 && formatVersion != kDatabaseFormatVersion)
    throw std::invalid_argument("a database is written in format version 2 or " +
                                std::to_string(kDatabaseFormatVersion) + ", not " + std::to_string(formatVersion));
  impl->version = formatVersion;
  if (!(meta.dtRec > 0)) throw std::invalid_argument("dt_rec must be positive");
  if (!(meta.solidDensity > 0)) throw std::invalid_argument("the solid density must be positive");
  impl->cells = mesh.numCells();
  impl->hash.add(std::vector<double>{static_cast<double>(impl->cells), meta.dtRec, meta.solidDensity, meta.gravity[0],
                                     meta.gravity[1], meta.gravity[2]});
  if (mesh.isMasked()) impl->hash.add(mesh.vessel()); // a box's hash stays what it was
  impl->file = h5::File::create(impl->out, h5::Checksums::fletcher32);
  const h5::File &f = impl->file;
  f.writeAttr("/", "format", std::string(kFormatName));
  f.writeAttr("/", "format_version", formatVersion);
  f.writeAttr("/", "created", nowUtc());
  writeMesh(f, mesh);
  f.createGroup("/metadata");
  f.writeAttr("/metadata", "dt_rec", meta.dtRec);
  f.writeAttr("/metadata", "solid_density", meta.solidDensity);
  f.writeAttr("/metadata", "gravity", std::vector<double>(meta.gravity.begin(), meta.gravity.end()));
  f.writeAttr("/metadata", "source", meta.source);
  f.writeAttr("/metadata", "units", meta.units);
  writeConditions(f, meta.conditions);
  if (meta.weightBits != 0) {
    if (meta.weightBits < 1 || meta.weightBits > kMaxWeightBits)
      throw std::invalid_argument("weight bits must be 1 to " + std::to_string(kMaxWeightBits) + ", got " +
                                  std::to_string(meta.weightBits));
    f.writeAttr("/metadata", "weight_bits", static_cast<long long>(meta.weightBits));
  }
  impl->weightBits = meta.weightBits;
  f.createGroup("/frames");
}

DatabaseFileWriter::~DatabaseFileWriter() = default; // an unfinished database leaves no file behind

void DatabaseFileWriter::append(const FrameRecord &frame) {
  const int n = impl->cells;
  if (frame.alphaS.size() != static_cast<size_t>(n) || frame.shift.n != n ||
      frame.shift.rowPtr.size() != static_cast<size_t>(n) + 1)
    throw std::invalid_argument("frame " + std::to_string(frames) +
                                " does not match the mesh's " + std::to_string(n) + " cells");
  if (impl->weightBits > 0) checkQuantised(frame.shift, impl->weightBits, frames);
  writeStoredFrame(impl->file, frameGroup(frames), frame, impl->version, impl->weightBits);
  // The identity is of the full CSR in every version, so that the same
  // frames have the same identity however they are stored.
  impl->hash.add(frame.alphaS);
  impl->hash.add(frame.shift.rowPtr);
  impl->hash.add(frame.shift.col);
  impl->hash.add(frame.shift.val);
  ++frames;
}

void DatabaseFileWriter::writeMatrix(const std::string &name, const std::vector<double> &rowMajor,
                                     int cols, const std::string &note) {
  impl->file.createGroup("/extra");
  impl->file.write("/extra/" + name, rowMajor, static_cast<hsize_t>(cols));
  impl->file.writeAttr("/extra/" + name, "note", note);
}

void DatabaseFileWriter::setNote(const std::string &key, const std::string &text) {
  for (const char *reserved : {"dt_rec", "solid_density", "gravity", "source", "units", "superficial_velocity",
                               "gas_density", "gas_kinematic_viscosity", "weight_bits"})
    if (key == reserved)
      throw std::invalid_argument("DatabaseWriter::setNote: '" + key +
                                  "' is a metadata attribute of the format");
  impl->file.writeAttr("/metadata", key, text);
}

void DatabaseFileWriter::finish() {
  if (frames < 1) throw std::invalid_argument("a database needs at least one frame");
  impl->file.writeAttr("/frames", "num_frames", static_cast<long long>(frames));
  impl->file.writeAttr("/", "content_hash", impl->hash.hex());
  impl->file.close();
  impl->out.commit();
}

// ---------------------------------------------------------------------------
// DatabaseWriter: the same, with PETSc error codes

namespace {
// Runs body(); its exception becomes an error with its sentence: bad input
// (std::invalid_argument) PETSC_ERR_ARG_WRONG, anything else PETSC_ERR_FILE_WRITE.
template <typename Body> PetscErrorCode refusing(Body &&body) {
  std::string why;
  PetscErrorCode code = PETSC_SUCCESS;
  try {
    body();
  } catch (const std::invalid_argument &e) {
    why = e.what();
    code = PETSC_ERR_ARG_WRONG;
  } catch (const std::exception &e) {
    why = e.what();
    code = PETSC_ERR_FILE_WRITE;
  }
  PetscFunctionBeginUser;
  PetscCheck(code == PETSC_SUCCESS, PETSC_COMM_SELF, code, "%s", why.c_str());
  PetscFunctionReturn(PETSC_SUCCESS);
}
} // namespace

DatabaseWriter::DatabaseWriter() = default;
DatabaseWriter::~DatabaseWriter() = default;

PetscErrorCode DatabaseWriter::create(const std::string &path, const Mesh &mesh, const DatabaseMetadata &meta,
                                      long long formatVersion) {
  PetscFunctionBeginUser;
  file.reset(); // a database started before and not finished leaves no file
  PetscCall(refusing([&] { file = std::make_unique<DatabaseFileWriter>(path, mesh, meta, formatVersion); }));
  PetscFunctionReturn(PETSC_SUCCESS);
}

#define RCFD_WRITER_STARTED()                                                                          \
  PetscCheck(file, PETSC_COMM_SELF, PETSC_ERR_ORDER, "DatabaseWriter: create() the database first")

PetscErrorCode DatabaseWriter::append(const FrameRecord &frame) {
  PetscFunctionBeginUser;
  RCFD_WRITER_STARTED();
  PetscCall(refusing([&] { file->append(frame); }));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode DatabaseWriter::writeMatrix(const std::string &name, const std::vector<double> &rowMajor, int cols,
                                           const std::string &note) {
  PetscFunctionBeginUser;
  RCFD_WRITER_STARTED();
  PetscCall(refusing([&] { file->writeMatrix(name, rowMajor, cols, note); }));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode DatabaseWriter::setNote(const std::string &key, const std::string &text) {
  PetscFunctionBeginUser;
  RCFD_WRITER_STARTED();
  PetscCall(refusing([&] { file->setNote(key, text); }));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode DatabaseWriter::finish() {
  PetscFunctionBeginUser;
  RCFD_WRITER_STARTED();
  PetscCall(refusing([&] { file->finish(); }));
  PetscFunctionReturn(PETSC_SUCCESS);
}

#undef RCFD_WRITER_STARTED

int DatabaseWriter::numFrames() const { return file ? file->numFrames() : 0; }

} // namespace rcfd
