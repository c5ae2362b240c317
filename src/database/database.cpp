#include "rcfd/database.hpp"
#include "base/checked_options.hpp"
#include "base/petsc_compat.hpp"

#include "base/atomic_file.hpp"
#include "base/collective.hpp"
#include "base/h5.hpp"
#include "database/compact_frames.hpp"
#include "database/stored_frame.hpp"

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <numeric>
#include <stdexcept>

namespace rcfd {
namespace {

constexpr const char *kFormatName = "rcfd-database";

/// FNV-1a, 64 bits, over the bytes of what is added: cheap (one pass over
/// data the writer has in memory anyway) and the same on every machine of
/// the same byte order; it names contents, it does not protect them.
class ContentHash {
public:
  void add(const void *data, std::size_t bytes) {
    const auto *p = static_cast<const unsigned char *>(data);
    for (std::size_t i = 0; i < bytes; ++i) state = (state ^ p[i]) * 1099511628211ULL;
  }
  template <typename T> void add(const std::vector<T> &values) { add(values.data(), values.size() * sizeof(T)); }
  void add(const std::string &text) { add(text.data(), text.size()); }
  std::string hex() const {
    char text[20];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(state));
    return text;
  }

private:
  std::uint64_t state = 14695981039346656037ULL;
};

std::string nowUtc() {
  char text[32];
  const std::time_t t = std::time(nullptr);
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return text;
}

void writeMesh(const h5::File &f, const Mesh &mesh) {
  f.createGroup("/mesh");
  if (mesh.isBox()) {
    const BoxSpec &b = mesh.boxSpec();
    f.writeAttr("/mesh", "kind", std::string("box"));
    f.writeAttr("/mesh", "box_cells", std::vector<long long>{b.nx, b.ny, b.nz});
    f.writeAttr("/mesh", "box_origin", std::vector<double>(b.origin.begin(), b.origin.end()));
    f.writeAttr("/mesh", "box_length", std::vector<double>(b.length.begin(), b.length.end()));
  } else {
    f.writeAttr("/mesh", "kind", std::string("unstructured"));
  }
  auto flat = [](const std::vector<Vec3> &v) {
    std::vector<double> out;
    out.reserve(3 * v.size());
    for (const auto &p : v) out.insert(out.end(), p.begin(), p.end());
    return out;
  };
  auto ints = [](const std::vector<int> &v) { return std::vector<int32_t>(v.begin(), v.end()); };
  f.write("/mesh/cell_centres", flat(mesh.cellCentre), 3);
  f.write("/mesh/cell_volumes", mesh.cellVolume);
  f.write("/mesh/face_owner", ints(mesh.faceOwner));
  f.write("/mesh/face_neighbour", ints(mesh.faceNeighbour));
  f.write("/mesh/face_area", flat(mesh.faceArea), 3);
  f.write("/mesh/boundary_owner", ints(mesh.boundaryOwner));
  f.write("/mesh/boundary_patch", ints(mesh.boundaryPatch));
  f.write("/mesh/boundary_area", flat(mesh.boundaryArea), 3);
}

Mesh readMesh(const h5::File &f) {
  f.requireGroup("/mesh");
  const std::string kind = f.readAttrString("/mesh", "kind");
  if (kind != "box")
    throw h5::Error("database '" + f.path() + "' has a mesh of kind '" + kind +
                    "'; this version of rcfd reads box meshes only");
  const auto n = f.readAttrInts("/mesh", "box_cells");
  const auto origin = f.readAttrDoubles("/mesh", "box_origin");
  const auto length = f.readAttrDoubles("/mesh", "box_length");
  if (n.size() != 3 || origin.size() != 3 || length.size() != 3 || n[0] < 1 || n[1] < 1 ||
      n[2] < 1 || !(length[0] > 0 && length[1] > 0 && length[2] > 0))
    throw h5::Error("database '" + f.path() +
                    "': /mesh attributes box_cells, box_origin and box_length must hold three "
                    "positive values each");
  BoxSpec spec;
  spec.nx = static_cast<int>(n[0]);
  spec.ny = static_cast<int>(n[1]);
  spec.nz = static_cast<int>(n[2]);
  std::copy(origin.begin(), origin.end(), spec.origin.begin());
  std::copy(length.begin(), length.end(), spec.length.begin());
  Mesh mesh = Mesh::box(spec);
  // The stored arrays must describe the same mesh as the box attributes.
  const auto volumes = f.read<double>("/mesh/cell_volumes");
  if (volumes.size() != static_cast<size_t>(mesh.numCells()))
    throw h5::Error("database '" + f.path() + "': /mesh/cell_volumes has " +
                    std::to_string(volumes.size()) + " cells but the box is " +
                    std::to_string(spec.nx) + " x " + std::to_string(spec.ny) + " x " +
                    std::to_string(spec.nz) + " = " + std::to_string(mesh.numCells()) + " cells");
  return mesh;
}

// Operating conditions (format version 2): optional attributes on /metadata.
constexpr const char *kConditionNames[3] = {"superficial_velocity", "gas_density", "gas_kinematic_viscosity"};

void readConditions(const h5::File &f, OperatingConditions *c) {
  double *value[3] = {&c->superficialVelocity, &c->gasDensity, &c->gasKinematicViscosity};
  for (int i = 0; i < 3; ++i) {
    if (!f.hasAttribute("/metadata", kConditionNames[i])) continue;
    *value[i] = f.readAttrDouble("/metadata", kConditionNames[i]);
    if (!(*value[i] > 0) || !std::isfinite(*value[i]))
      throw h5::Error("database '" + f.path() + "': /metadata " + kConditionNames[i] +
                      " must be a positive number");
  }
}

void writeConditions(const h5::File &f, const OperatingConditions &c) {
  const double value[3] = {c.superficialVelocity, c.gasDensity, c.gasKinematicViscosity};
  for (int i = 0; i < 3; ++i)
    if (std::isfinite(value[i])) f.writeAttr("/metadata", kConditionNames[i], value[i]);
}

// The file's format version, one this rcfd reads.
long long checkFormat(const h5::File &f) {
  if (!f.hasAttribute("/", "format") || f.readAttrString("/", "format") != kFormatName)
    throw h5::Error("'" + f.path() + "' is not an rcfd database (its root has no attribute format = \"" +
                    kFormatName + "\")");
  const long long version = f.readAttrInt("/", "format_version");
  if (version < 1 || version > kDatabaseFormatVersion)
    throw h5::Error("database '" + f.path() + "' has format version " + std::to_string(version) +
                    ", this rcfd reads versions 1 to " + std::to_string(kDatabaseFormatVersion));
  return version;
}

// The identity a run's checkpoint records (docs/database-format.md, "Identity").
std::string readIdentity(const h5::File &f) {
  if (f.hasAttribute("/", "content_hash")) return "content " + f.readAttrString("/", "content_hash");
  ContentHash made; // an older file: when and how it was made, and its size
  if (f.hasAttribute("/", "created")) made.add(f.readAttrString("/", "created"));
  if (f.hasAttribute("/metadata", "source")) made.add(f.readAttrString("/metadata", "source"));
  if (f.hasAttribute("/frames", "num_frames")) made.add(std::to_string(f.readAttrInt("/frames", "num_frames")));
  return "made " + made.hex();
}

DatabaseMetadata readMetadata(const h5::File &f) {
  f.requireGroup("/metadata");
  DatabaseMetadata m;
  m.dtRec = f.readAttrDouble("/metadata", "dt_rec");
  m.solidDensity = f.readAttrDouble("/metadata", "solid_density");
  const auto g = f.readAttrDoubles("/metadata", "gravity");
  if (g.size() != 3) throw h5::Error("database '" + f.path() + "': /metadata gravity must have 3 components");
  std::copy(g.begin(), g.end(), m.gravity.begin());
  if (f.hasAttribute("/metadata", "source")) m.source = f.readAttrString("/metadata", "source");
  if (f.hasAttribute("/metadata", "units")) m.units = f.readAttrString("/metadata", "units");
  readConditions(f, &m.conditions); // version 2; absent in version 1
  if (f.hasAttribute("/metadata", "weight_bits")) {
    const long long bits = f.readAttrInt("/metadata", "weight_bits");
    if (bits < 1 || bits > kMaxWeightBits)
      throw h5::Error("database '" + f.path() + "': /metadata weight_bits is " + std::to_string(bits) +
                      ", expected the number of bits of its quantised weights, 1 to " +
                      std::to_string(kMaxWeightBits));
    m.weightBits = static_cast<int>(bits);
  }
  if (!(m.dtRec > 0) || !std::isfinite(m.dtRec))
    throw h5::Error("database '" + f.path() + "': dt_rec must be a positive number of seconds");
  if (!(m.solidDensity > 0))
    throw h5::Error("database '" + f.path() + "': solid_density must be positive");
  if (!(std::hypot(g[0], g[1], g[2]) > 0))
    throw h5::Error("database '" + f.path() + "': gravity must not be the zero vector");
  if (m.units != "SI")
    throw h5::Error("database '" + f.path() + "' is in units '" + m.units + "'; rcfd expects SI");
  return m;
}

// Appends natural row `row` of a stored shift to `rows` in PETSc numbering,
// columns sorted; refuses an entry outside the mesh or a weight that is not a
// non-negative number.
void appendRow(const Layout &layout, const std::string &where, hsize_t row, const int32_t *col, const double *val,
               int64_t count, LocalShiftRows *rows) {
  const hsize_t n = layout.numCells();
  const size_t rowBegin = rows->col.size();
  for (int64_t t = 0; t < count; ++t) {
    if (col[t] < 0 || static_cast<hsize_t>(col[t]) >= n)
      throw h5::Error(where + ": shift entry in row " + std::to_string(row) + " names cell " +
                      std::to_string(col[t]) + ", outside the mesh's " + std::to_string(n) + " cells");
    if (!std::isfinite(val[t]) || val[t] < 0.0)
      throw h5::Error(where + ": shift entry (" + std::to_string(row) + ", " + std::to_string(col[t]) + ") is " +
                      std::to_string(val[t]) + ", expected a non-negative share");
    rows->col.push_back(layout.petscRow(col[t]));
    rows->val.push_back(val[t]);
  }
  // PETSc wants sorted columns; renumbering may have reordered them.
  // Rows hold a handful of entries: insertion sort, in place.
  for (size_t a = rowBegin + 1; a < rows->col.size(); ++a)
    for (size_t b = a; b > rowBegin && rows->col[b - 1] > rows->col[b]; --b) {
      std::swap(rows->col[b - 1], rows->col[b]);
      std::swap(rows->val[b - 1], rows->val[b]);
    }
  rows->rowPtr.push_back(static_cast<PetscInt>(rows->col.size()));
}

// Versions 1 and 2: the full CSR's rows of the rank's cells.
void readLocalRowsFull(const h5::File &f, const std::string &g, const std::string &where, const Layout &layout,
                       const std::vector<std::pair<hsize_t, hsize_t>> &cellRuns, LocalShiftRows *rows) {
  const hsize_t n = layout.numCells();
  std::vector<std::pair<hsize_t, hsize_t>> ptrRuns;
  for (auto [b, e] : cellRuns) ptrRuns.emplace_back(b, e + 1);
  const auto ptrDims = f.extents(g + "/shift_row_ptr");
  if (ptrDims.size() != 1 || ptrDims[0] != n + 1)
    throw h5::Error(where + ": shift_row_ptr has " + std::to_string(ptrDims.empty() ? 0 : ptrDims[0]) +
                    " entries, expected " + std::to_string(n + 1) + " (cells + 1)");
  const hsize_t nnz = f.extents(g + "/shift_col").at(0);
  if (f.extents(g + "/shift_val").at(0) != nnz)
    throw h5::Error(where + ": shift_col and shift_val differ in length");
  const auto ptr = f.readRuns<int64_t>(g + "/shift_row_ptr", ptrRuns);
  std::vector<std::pair<hsize_t, hsize_t>> nzRuns;
  size_t p = 0;
  for (auto [b, e] : cellRuns) {
    const int64_t first = ptr[p], last = ptr[p + (e - b)];
    for (hsize_t r = 0; r < e - b; ++r)
      if (ptr[p + r + 1] < ptr[p + r])
        throw h5::Error(where + ": shift_row_ptr decreases at row " + std::to_string(b + r));
    if (first < 0 || last > static_cast<int64_t>(nnz))
      throw h5::Error(where + ": shift_row_ptr points outside shift_col (" + std::to_string(nnz) +
                      " entries)");
    if (last > first) nzRuns.emplace_back(first, last);
    p += e - b + 1;
  }
  const auto col = f.readRuns<int32_t>(g + "/shift_col", nzRuns);
  const auto val = f.readRuns<double>(g + "/shift_val", nzRuns);
  rows->rowPtr.assign(1, 0);
  rows->col.reserve(col.size());
  rows->val.reserve(val.size());
  size_t q = 0;
  p = 0;
  for (auto [b, e] : cellRuns) {
    for (hsize_t r = 0; r < e - b; ++r) {
      const int64_t count = ptr[p + r + 1] - ptr[p + r];
      appendRow(layout, where, b + r, col.data() + q, val.data() + q, count, rows);
      q += static_cast<size_t>(count);
    }
    p += e - b + 1;
  }
}

// Version 3: the rank's moving rows, found by binary search in moving_row
// (read whole); its other cells' rows are identity rows, implied and never
// built (rescaleColumns counts them in their place, compactFrame leaves them
// out), so the frame is the one version 2 gives, to the bit.
void readLocalRowsMoving(const h5::File &f, const std::string &g, const std::string &where, const Layout &layout,
                         const std::vector<std::pair<hsize_t, hsize_t>> &cellRuns, int weightBits,
                         LocalShiftRows *rows) {
  const MovingRowIndex index = readMovingRowIndex(f, g, where, static_cast<int>(layout.numCells()), weightBits);
  const auto &moving = index.movingRow;
  // The positions [lo, hi) in moving_row of each run of own cells, merged where they touch.
  std::vector<std::pair<hsize_t, hsize_t>> rowRuns;
  for (auto [b, e] : cellRuns) {
    const auto lo = static_cast<hsize_t>(std::lower_bound(moving.begin(), moving.end(), b) - moving.begin());
    const auto hi = static_cast<hsize_t>(std::lower_bound(moving.begin(), moving.end(), e) - moving.begin());
    if (lo == hi) continue;
    if (!rowRuns.empty() && rowRuns.back().second == lo) rowRuns.back().second = hi;
    else rowRuns.emplace_back(lo, hi);
  }
  std::vector<std::pair<hsize_t, hsize_t>> entryRuns;
  const auto ptr = readMovingRowPtr(f, g, where, index, rowRuns, &entryRuns);
  const auto col = f.readRuns<int32_t>(g + "/shift_col", entryRuns);
  const auto val = readStoredWeights(f, g, entryRuns, weightBits);
  // The moving rows read, ascending, and their entry counts.
  std::vector<int32_t> row;
  std::vector<int64_t> count;
  size_t p = 0;
  for (auto [lo, hi] : rowRuns) {
    for (hsize_t i = lo; i < hi; ++i, ++p) {
      row.push_back(moving[i]);
      count.push_back(ptr[p + 1] - ptr[p]);
    }
    ++p; // the run's end pointer
  }
  // Only the moving rows are stored; the others stay identity rows, implied.
  rows->impliedIdentity = true;
  rows->rowPtr.assign(1, 0);
  rows->col.reserve(col.size());
  rows->val.reserve(val.size());
  rows->row.reserve(row.size());
  size_t q = 0;
  for (size_t m = 0; m < row.size(); ++m) {
    const PetscInt local = layout.petscRow(row[m]) - layout.rowStart();
    rows->row.push_back(local);
    appendRow(layout, where, static_cast<hsize_t>(row[m]), col.data() + q, val.data() + q, count[m], rows);
    q += static_cast<size_t>(count[m]);
  }
}

// This rank's rows of one frame: alpha_s in PETSc order, and the shift as
// local CSR with PETSc column numbers.  Throws on any inconsistency.
struct LocalFrame {
  std::vector<double> alpha;
  LocalShiftRows shift;
};

LocalFrame readLocalFrame(const h5::File &f, long long version, int weightBits, int k, const Layout &layout,
                          bool withShift) try {
  const std::string g = frameGroup(k);
  const std::string where = "database '" + f.path() + "', frame " + std::to_string(k);
  f.requireGroup(g);
  const hsize_t n = layout.numCells();
  std::vector<std::pair<hsize_t, hsize_t>> cellRuns;
  for (auto [b, e] : layout.ownedNaturalRuns()) cellRuns.emplace_back(b, e);
  LocalFrame fr;
  const auto alphaDims = f.extents(g + "/alpha_s");
  if (alphaDims.size() != 1 || alphaDims[0] != n)
    throw h5::Error(where + ": alpha_s has " + std::to_string(alphaDims.empty() ? 0 : alphaDims[0]) +
                    " values but the mesh has " + std::to_string(n) + " cells");
  fr.alpha = f.readRuns<double>(g + "/alpha_s", cellRuns);
  for (size_t r = 0; r < fr.alpha.size(); ++r)
    if (!std::isfinite(fr.alpha[r]) || fr.alpha[r] < 0.0 || fr.alpha[r] > 1.0)
      throw h5::Error(where + ": alpha_s of cell " + std::to_string(layout.ownedNatural()[r]) +
                      " is " + std::to_string(fr.alpha[r]) + ", expected a number in [0, 1]");
  if (!withShift) return fr;
  if (version >= 3) readLocalRowsMoving(f, g, where, layout, cellRuns, weightBits, &fr.shift);
  else readLocalRowsFull(f, g, where, layout, cellRuns, &fr.shift);
  return fr;
} catch (const h5::Damaged &d) {
  throwDamagedFrame(d, f, k);
}

} // namespace

// ---------------------------------------------------------------- writer

namespace {

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

struct DatabaseWriter::Impl {
  explicit Impl(const std::string &path) : out(path) {}
  AtomicFile out; // declared first: the file is closed before an unfinished temporary is removed
  h5::File file;
  int cells = 0;
  int weightBits = 0; // > 0: every frame must be quantised so (checked by append)
  long long version = kDatabaseFormatVersion;
  ContentHash hash; // of every frame's arrays, stored as content_hash by finish()
};

DatabaseWriter::DatabaseWriter(const std::string &path, const Mesh &mesh, const DatabaseMetadata &meta,
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

DatabaseWriter::~DatabaseWriter() = default; // an unfinished database leaves no file behind

void DatabaseWriter::append(const FrameRecord &frame) {
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

void DatabaseWriter::writeMatrix(const std::string &name, const std::vector<double> &rowMajor,
                                 int cols, const std::string &note) {
  impl->file.createGroup("/extra");
  impl->file.write("/extra/" + name, rowMajor, static_cast<hsize_t>(cols));
  impl->file.writeAttr("/extra/" + name, "note", note);
}

void DatabaseWriter::setNote(const std::string &key, const std::string &text) {
  for (const char *reserved : {"dt_rec", "solid_density", "gravity", "source", "units", "superficial_velocity",
                               "gas_density", "gas_kinematic_viscosity", "weight_bits"})
    if (key == reserved)
      throw std::invalid_argument("DatabaseWriter::setNote: '" + key +
                                  "' is a metadata attribute of the format");
  impl->file.writeAttr("/metadata", key, text);
}

void DatabaseWriter::finish() {
  if (frames < 1) throw std::invalid_argument("a database needs at least one frame");
  impl->file.writeAttr("/frames", "num_frames", static_cast<long long>(frames));
  impl->file.writeAttr("/", "content_hash", impl->hash.hex());
  impl->file.close();
  impl->out.commit();
}

// ---------------------------------------------------------------- loader

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

Database::Database() = default;
Database::~Database() = default;

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

PetscErrorCode Database::shiftMatrix(int k, OwnedMat *T) const {
  PetscFunctionBeginUser;
  PetscCheck(hasShifts(), layout_.comm(), PETSC_ERR_ARG_WRONGSTATE,
             "Database '%s' was loaded without its shifts", path_.c_str());
  PetscCheck(k >= 0 && k < numFrames(), layout_.comm(), PETSC_ERR_ARG_OUTOFRANGE,
             "Frame %d of database '%s', which has %d", k, path_.c_str(), numFrames());
  PetscCall(shiftMatrixOf(frames_[k], layout_, ghostRows_, meta.weightBits, T));
  PetscFunctionReturn(PETSC_SUCCESS);
}

size_t Database::frameBytes() const {
  size_t bytes = ghostRows_.size() * sizeof(PetscInt);
  for (const CompactFrame &f : frames_) bytes += f.bytes();
  return bytes;
}

PetscErrorCode Database::consistency(std::vector<double> *residual) const {
  PetscFunctionBeginUser;
  residual->clear();
  if (!hasShifts() || numFrames() < 2) PetscFunctionReturn(PETSC_SUCCESS);
  OwnedVec vol, ma, mb, moved;
  PetscCall(VecDuplicate(alpha[0], vol.put()));
  PetscCall(VecDuplicate(alpha[0], ma.put()));
  PetscCall(VecDuplicate(alpha[0], mb.put()));
  PetscCall(VecDuplicate(alpha[0], moved.put()));
  PetscScalar *pv;
  PetscCall(VecGetArrayWrite(vol, &pv));
  std::copy(volumes.begin(), volumes.end(), pv);
  PetscCall(VecRestoreArrayWrite(vol, &pv));
  for (int k = 0; k + 1 < numFrames(); ++k) {
    PetscReal diff, total;
    PetscCall(VecPointwiseMult(ma, vol, alpha[k]));
    PetscCall(VecPointwiseMult(mb, vol, alpha[k + 1]));
    OwnedMat T;
    PetscCall(shiftMatrix(k, &T));
    PetscCall(MatMult(T, ma, moved));
    PetscCall(VecNorm(ma, NORM_1, &total));
    PetscCall(VecAXPY(moved, -1.0, mb));
    PetscCall(VecNorm(moved, NORM_1, &diff));
    residual->push_back(total > 0 ? diff / total : 0.0);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Database::readMatrix(const std::string &name, std::vector<double> *rowMajor,
                                    int *cols) const {
  PetscFunctionBeginUser;
  rowMajor->clear();
  *cols = 0;
  PetscCall(collectively(layout_.comm(), [&] {
    h5::File f = h5::File::openRead(path_, MPI_COMM_NULL);
    const std::string ds = "/extra/" + name;
    if (!f.exists(ds)) return;
    const auto dims = f.extents(ds);
    if (dims.size() != 2) throw h5::Error("database '" + path_ + "': " + ds + " is not a matrix");
    *rowMajor = f.read<double>(ds);
    *cols = static_cast<int>(dims[1]);
  }));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Database::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  const Mesh &m = mesh_;
  PetscCall(PetscViewerASCIIPrintf(viewer, "Database %s\n", path_.c_str()));
  PetscCall(PetscViewerASCIIPushTab(viewer));
  if (m.isBox()) {
    const BoxSpec &b = m.boxSpec();
    PetscCall(PetscViewerASCIIPrintf(
        viewer, "mesh: box %d x %d x %d cells = %d, %.4g x %.4g x %.4g m from (%.4g, %.4g, %.4g)\n",
        b.nx, b.ny, b.nz, m.numCells(), b.length[0], b.length[1], b.length[2], b.origin[0],
        b.origin[1], b.origin[2]));
  }
  PetscCall(PetscViewerASCIIPrintf(viewer, "faces: %d internal, %d boundary\n", m.numFaces(),
                                   m.numBoundaryFaces()));
  PetscCall(PetscViewerASCIIPrintf(viewer, "frames: %d every %.6g s (%.6g s recorded)\n",
                                   numFrames(), meta.dtRec, numFrames() * meta.dtRec));
  PetscCall(PetscViewerASCIIPrintf(viewer, "solid density: %g kg/m^3, gravity (%g, %g, %g) m/s^2\n",
                                   meta.solidDensity, meta.gravity[0], meta.gravity[1],
                                   meta.gravity[2]));
  PetscCall(PetscViewerASCIIPrintf(viewer, "source: %s\n", meta.source.c_str()));
  const OperatingConditions &c = meta.conditions;
  if (std::isfinite(c.superficialVelocity) || std::isfinite(c.gasDensity) || std::isfinite(c.gasKinematicViscosity))
    PetscCall(PetscViewerASCIIPrintf(viewer, "recorded at: u_sup %g m/s, gas density %g kg/m^3, gas kinematic viscosity %g m^2/s (nan: not recorded)\n",
                                     c.superficialVelocity, c.gasDensity, c.gasKinematicViscosity));
  if (hasShifts()) {
    // nonzeros (a row not held is an identity row of one entry), moving entries, narrow ones, bytes
    double counts[4] = {0.0, 0.0, 0.0, static_cast<double>(frameBytes())};
    for (const CompactFrame &f : frames_) {
      counts[0] += static_cast<double>(f.numEntries() + layout_.numLocal() - f.numRows());
      counts[1] += static_cast<double>(f.numEntries());
      counts[2] += static_cast<double>(f.offset.size());
    }
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, counts, 4, MPI_DOUBLE, MPI_SUM, layout_.comm()));
    const double nnz = counts[0], moving = counts[1];
    std::vector<double> res;
    PetscCall(consistency(&res));
    const double worst = res.empty() ? 0.0 : *std::max_element(res.begin(), res.end());
    double colErr = maxColumnError;
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &colErr, 1, MPI_DOUBLE, MPI_MAX, layout_.comm()));
    PetscCall(PetscViewerASCIIPrintf(viewer, "shift nonzeros: %.3g per column on average\n",
                                     nnz / numFrames() / m.numCells()));
    char weights[64] = "full-precision weights";
    if (meta.weightBits > 0) std::snprintf(weights, sizeof weights, "weights quantised to 2^-%d", meta.weightBits);
    PetscCall(PetscViewerASCIIPrintf(
        viewer, "compact frames: %.1f MB on all ranks, %.3g moving entries per cell and frame, %.0f %% of them with 16-bit column offsets, %s\n",
        counts[3] / 1e6, moving / numFrames() / m.numCells(), moving > 0 ? 100.0 * counts[2] / moving : 100.0,
        weights));
    PetscCall(PetscViewerASCIIPrintf(viewer, "largest |column sum - 1| before rescaling: %.3g\n",
                                     colErr));
    PetscCall(PetscViewerASCIIPrintf(
        viewer, "mass consistency |T_k a_k - a_k+1|_1 / |a_k|_1: largest %.3g over %zu pairs\n",
        worst, res.size()));
  }
  PetscCall(PetscViewerASCIIPopTab(viewer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
