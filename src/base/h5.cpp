#include "base/h5.hpp"

#include "base/atomic_file.hpp"
#include "base/h5_write_driver.hpp"
#include "base/input_file.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <cstdlib>
#include <cstdio>
#include <type_traits>
#include <numeric>

namespace rcfd::h5 {
namespace {

template <typename T> hid_t nativeType();
template <> hid_t nativeType<double>() { return H5T_NATIVE_DOUBLE; }
template <> hid_t nativeType<int32_t>() { return H5T_NATIVE_INT32; }
template <> hid_t nativeType<int64_t>() { return H5T_NATIVE_INT64; }
template <> hid_t nativeType<uint16_t>() { return H5T_NATIVE_UINT16; }
template <> hid_t nativeType<long long>() { return H5T_NATIVE_LLONG; }

// HDF5 prints its own error stack by default; rcfd reports one sentence instead.
void silenceHdf5() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

constexpr const char *kChecksumsAttribute = "checksums"; // on the root: the file's Checksums
constexpr const char *kFletcher32 = "fletcher32";
// Bytes of one chunk of a checksummed dataset (a whole row of a 2-D one at
// least).  HDF5 reads, checks and caches whole chunks: well below its 1 MB
// cache per dataset, so that the pieces a rank reads of one chunk find it
// there, and large enough that the per-chunk work stays small
// (docs/database-format.md, "Checksums", measured).
constexpr hsize_t kChunkBytes = 64 * 1024;

// Whether the error stack of the HDF5 call that just failed reports bytes
// that do not match their checksum: a chunk's Fletcher-32, or one of HDF5's
// own records (superblock, object header, chunk index, heap) in the 1.10 format.
bool checksumFailed() {
  bool found = false;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_DOWNWARD,
      [](unsigned, const H5E_error2_t *e, void *data) -> herr_t {
        if (e->desc && std::strstr(e->desc, "checksum")) *static_cast<bool *>(data) = true;
        return 0;
      },
      &found);
  return found;
}

// After a failed HDF5 call on `object` of `file`: throws Damaged if a
// checksum did not match (otherwise the caller reports its own reason).
void throwIfDamaged(const std::string &file, const std::string &object) {
  if (!checksumFailed()) return;
  throw Damaged("HDF5 file '" + file + "': " + (object.empty() ? std::string("its superblock") : "'" + object + "'") +
                    " is damaged (" + Damaged::reason + ")",
                object);
}

Id openObject(const File &f, const std::string &object) {
  hid_t id = H5Oopen(f.id(), object.c_str(), H5P_DEFAULT);
  if (id < 0) throwIfDamaged(f.path(), object);
  if (id < 0) throw Error("HDF5 file '" + f.path() + "' has no object '" + object + "'");
  return Id(id, H5Oclose);
}

Id openAttribute(const File &f, const std::string &object, const std::string &attr) {
  Id obj = openObject(f, object);
  if (H5Aexists(obj, attr.c_str()) <= 0) {
    throwIfDamaged(f.path(), object);
    throw Error("HDF5 file '" + f.path() + "' has no attribute '" + attr + "' on '" + object + "'");
  }
  Id a(H5Aopen(obj, attr.c_str(), H5P_DEFAULT), H5Aclose);
  if (!a.valid()) throwIfDamaged(f.path(), object);
  if (!a.valid()) throw Error("HDF5 file '" + f.path() + "': attribute '" + attr + "' on '" + object + "' cannot be read");
  return a;
}

size_t attributeSize(const Id &a) {
  Id space(H5Aget_space(a), H5Sclose);
  hssize_t n = H5Sget_simple_extent_npoints(space);
  return n < 0 ? 0 : static_cast<size_t>(n);
}

template <typename T>
void writeAttrArray(const File &f, const std::string &object, const std::string &attr,
                    const T *data, hsize_t n) {
  Id obj = openObject(f, object);
  if (H5Aexists(obj, attr.c_str()) > 0) H5Adelete(obj, attr.c_str());
  Id space(n == 1 ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &n, nullptr), H5Sclose);
  Id a(H5Acreate2(obj, attr.c_str(), nativeType<T>(), space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  const bool written = a.valid() && H5Awrite(a, nativeType<T>(), data) >= 0;
  f.throwIfWriteFailed();
  if (!written) throw Error("could not write attribute '" + attr + "' to '" + f.path() + "'");
}

template <typename T>
std::vector<T> readAttrArray(const File &f, const std::string &object, const std::string &attr) {
  Id a = openAttribute(f, object, attr);
  std::vector<T> v(attributeSize(a));
  if (!v.empty() && H5Aread(a, nativeType<T>(), v.data()) < 0) {
    throwIfDamaged(f.path(), object);
    throw Error("HDF5 file '" + f.path() + "': attribute '" + attr + "' on '" + object + "' is not numeric");
  }
  return v;
}

// Cover the runs with at most maxPieces contiguous pieces by closing the
// smallest gaps: many small hyperslabs are slow in HDF5 1.10, a few extra
// elements are not.
std::vector<std::pair<hsize_t, hsize_t>>
coalesce(const std::vector<std::pair<hsize_t, hsize_t>> &runs, size_t maxPieces) {
  if (runs.size() <= maxPieces) return runs;
  std::vector<size_t> gaps(runs.size() - 1);
  std::iota(gaps.begin(), gaps.end(), size_t{0});
  auto gap = [&](size_t g) { return runs[g + 1].first - runs[g].second; };
  std::nth_element(gaps.begin(), gaps.begin() + (maxPieces - 1), gaps.end(),
                   [&](size_t a, size_t b) { return gap(a) > gap(b); });
  std::vector<bool> cut(runs.size(), false);
  for (size_t p = 0; p + 1 < maxPieces; ++p) cut[gaps[p]] = true;
  std::vector<std::pair<hsize_t, hsize_t>> pieces;
  hsize_t begin = runs[0].first;
  for (size_t r = 0; r < runs.size(); ++r)
    if (r + 1 == runs.size() || cut[r]) {
      pieces.emplace_back(begin, runs[r].second);
      if (r + 1 < runs.size()) begin = runs[r + 1].first;
    }
  return pieces;
}

} // namespace

File File::openRead(const std::string &path, MPI_Comm comm) {
  silenceHdf5();
  if (const std::string problem = notRegularFile(path); !problem.empty()) throw Error(problem);
  if (H5Fis_hdf5(path.c_str()) <= 0) {
    FILE *probe = std::fopen(path.c_str(), "rb");
    if (!probe) throw Error("cannot open file '" + path + "': it does not exist or is not readable");
    std::fclose(probe);
    throw Error("file '" + path + "' is not an HDF5 file");
  }
  Id fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  if (comm != MPI_COMM_NULL) H5Pset_fapl_mpio(fapl, comm, MPI_INFO_NULL);
  File f;
  f.name = path;
  f.file = Id(H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl), H5Fclose);
  if (!f.file.valid()) throwIfDamaged(path, "");
  if (!f.file.valid()) throw Error("cannot open HDF5 file '" + path + "'");
  f.adoptChecksums();
  return f;
}

File File::create(const std::string &path, Checksums checksums) {
  silenceHdf5();
  // Test hook (docs/testing.md): write as an rcfd before checksums did, to
  // make the older files that tests and benchmarks compare against.
  if (const char *older = std::getenv("RCFD_WRITE_WITHOUT_CHECKSUMS"); older && std::string(older) == "1")
    checksums = Checksums::none;
  File f;
  f.name = path;
  f.writeError = std::make_unique<int>(0);
  Id fapl(checkedWriteAccess(f.writeError.get()), H5Pclose);
  // HDF5 1.10's format checksums every record of its own (1.8's left the
  // chunk index unprotected); readable by HDF5 1.10 and later.
  if (checksums == Checksums::fletcher32) H5Pset_libver_bounds(fapl, H5F_LIBVER_V110, H5F_LIBVER_V110);
  f.file = Id(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl), H5Fclose);
  if (!f.file.valid()) throw Error("cannot create HDF5 file '" + path + "'");
  f.protection = checksums;
  if (checksums == Checksums::fletcher32) f.writeAttr("/", kChecksumsAttribute, std::string(kFletcher32));
  return f;
}

File File::create(const AtomicFile &target, Checksums checksums) {
  try {
    File f = create(target.temporaryPath(), checksums);
    f.name = target.path();
    return f;
  } catch (const Error &) { // name the file the user asked for
    throw Error("cannot create HDF5 file '" + target.path() + "' (as '" + target.temporaryPath() + "')");
  }
}

File File::createParallel(const std::string &path, MPI_Comm comm) {
  silenceHdf5();
  Id fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  H5Pset_fapl_mpio(fapl, comm, MPI_INFO_NULL);
  File f;
  f.name = path;
  f.file = Id(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl), H5Fclose);
  if (!f.file.valid()) throw Error("cannot create HDF5 file '" + path + "'");
  return f;
}

File File::openReadWrite(const std::string &path) {
  silenceHdf5();
  File f;
  f.name = path;
  f.writeError = std::make_unique<int>(0); // a failed write is reported, not a crash at exit
  Id fapl(checkedWriteAccess(f.writeError.get()), H5Pclose);
  f.file = Id(H5Fopen(path.c_str(), H5F_ACC_RDWR, fapl), H5Fclose);
  if (!f.file.valid()) throwIfDamaged(path, "");
  if (!f.file.valid()) throw Error("cannot open HDF5 file '" + path + "' for writing");
  f.adoptChecksums();
  if (f.protection == Checksums::fletcher32) // what is added gets the same protection
    H5Fset_libver_bounds(f.file, H5F_LIBVER_V110, H5F_LIBVER_V110);
  return f;
}

void File::adoptChecksums() {
  protection = Checksums::none;
  if (!hasAttribute("/", kChecksumsAttribute)) return;
  const std::string kind = readAttrString("/", kChecksumsAttribute);
  if (kind != kFletcher32)
    throw Error("HDF5 file '" + name + "' says its checksums are '" + kind + "'; this rcfd knows '" + kFletcher32 +
                "' (root attribute " + kChecksumsAttribute + ")");
  H5F_info2_t info;
  if (H5Fget_info2(file, &info) < 0 || info.super.version < 2) // superblocks before version 2 have no checksum
    throw Error("HDF5 file '" + name + "' says it has checksums but its superblock (version " +
                std::to_string(info.super.version) + ") has none; it was not written by rcfd");
  protection = Checksums::fletcher32;
}

void File::requireChecksum(hid_t dataset, const std::string &object) const {
  if (protection == Checksums::none) return;
  Id dcpl(H5Dget_create_plist(dataset), H5Pclose);
  unsigned flags = 0, config = 0;
  size_t values = 0;
  if (!dcpl.valid() ||
      H5Pget_filter_by_id2(dcpl, H5Z_FILTER_FLETCHER32, &flags, &values, nullptr, 0, nullptr, &config) < 0)
    throw Damaged("HDF5 file '" + name + "': dataset '" + object +
                      "' has no checksum although the file says every dataset has one (root attribute " +
                      kChecksumsAttribute + "); it was changed after it was written",
                  object);
}

void File::close() {
  if (!file.valid()) return;
  const herr_t closed = file.close();
  throwIfWriteFailed();
  if (closed < 0)
    throw Error("could not finish writing HDF5 file '" + name + "' (closing it failed)");
}

void File::throwIfWriteFailed() const {
  if (writeError && *writeError)
    throw Error("could not write HDF5 file '" + name + "': " + std::strerror(*writeError));
}

bool File::exists(const std::string &object) const {
  // Walk the path so that a missing parent group is not an HDF5 error.
  // A lookup that fails on a damaged record (a link heap's checksum) is no "missing".
  auto linked = [&](const std::string &path) {
    const htri_t found = H5Lexists(file, path.c_str(), H5P_DEFAULT);
    if (found < 0) throwIfDamaged(name, path);
    return found > 0;
  };
  size_t pos = 0;
  while ((pos = object.find('/', pos + 1)) != std::string::npos)
    if (!linked(object.substr(0, pos))) return false;
  return object == "/" || linked(object);
}

void File::requireGroup(const std::string &group) const {
  if (!exists(group))
    throw Error("HDF5 file '" + name + "' has no group '" + group + "'");
}

Id File::openDataset(const std::string &dataset) const {
  if (!exists(dataset)) throw Error("HDF5 file '" + name + "' has no dataset '" + dataset + "'");
  Id d(H5Dopen2(file, dataset.c_str(), H5P_DEFAULT), H5Dclose);
  if (!d.valid()) throwIfDamaged(name, dataset);
  if (!d.valid()) throw Error("HDF5 file '" + name + "': '" + dataset + "' is not a dataset");
  return d;
}

void File::createGroup(const std::string &group) const {
  if (exists(group)) return;
  Id g(H5Gcreate2(file, group.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
  throwIfWriteFailed();
  if (!g.valid()) throw Error("cannot create group '" + group + "' in '" + name + "'");
}

std::vector<hsize_t> File::extents(const std::string &dataset) const {
  Id d = openDataset(dataset);
  Id space(H5Dget_space(d), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space);
  std::vector<hsize_t> dims(rank > 0 ? rank : 0);
  if (rank > 0) H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  return dims;
}

bool File::hasAttribute(const std::string &object, const std::string &attr) const {
  if (!exists(object)) return false;
  Id obj = openObject(*this, object);
  const htri_t found = H5Aexists(obj, attr.c_str());
  if (found < 0) throwIfDamaged(name, object);
  return found > 0;
}

double File::readAttrDouble(const std::string &object, const std::string &attr) const {
  auto v = readAttrArray<double>(*this, object, attr);
  if (v.size() != 1)
    throw Error("HDF5 file '" + name + "': attribute '" + attr + "' on '" + object +
                "' should hold one number");
  return v[0];
}

long long File::readAttrInt(const std::string &object, const std::string &attr) const {
  auto v = readAttrArray<long long>(*this, object, attr);
  if (v.size() != 1)
    throw Error("HDF5 file '" + name + "': attribute '" + attr + "' on '" + object +
                "' should hold one integer");
  return v[0];
}

std::vector<double> File::readAttrDoubles(const std::string &object, const std::string &attr) const {
  return readAttrArray<double>(*this, object, attr);
}

std::vector<long long> File::readAttrInts(const std::string &object,
                                          const std::string &attr) const {
  return readAttrArray<long long>(*this, object, attr);
}

std::string File::readAttrString(const std::string &object, const std::string &attr) const {
  Id a = openAttribute(*this, object, attr);
  Id type(H5Aget_type(a), H5Tclose);
  if (H5Tget_class(type) != H5T_STRING)
    throw Error("HDF5 file '" + name + "': attribute '" + attr + "' on '" + object +
                "' should be a string");
  if (H5Tis_variable_str(type) > 0) {
    char *s = nullptr;
    Id mem(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(mem, H5T_VARIABLE);
    if (H5Aread(a, mem, &s) < 0) throwIfDamaged(name, object);
    std::string out = s ? s : "";
    H5free_memory(s);
    return out;
  }
  std::string out(H5Tget_size(type), '\0');
  if (H5Aread(a, type, out.data()) < 0) throwIfDamaged(name, object);
  out.erase(std::find(out.begin(), out.end(), '\0'), out.end());
  return out;
}

void File::writeAttr(const std::string &object, const std::string &attr, double v) const {
  writeAttrArray(*this, object, attr, &v, 1);
}
void File::writeAttr(const std::string &object, const std::string &attr, long long v) const {
  writeAttrArray(*this, object, attr, &v, 1);
}
void File::writeAttr(const std::string &object, const std::string &attr,
                     const std::vector<double> &v) const {
  writeAttrArray(*this, object, attr, v.data(), v.size());
}
void File::writeAttr(const std::string &object, const std::string &attr,
                     const std::vector<long long> &v) const {
  writeAttrArray(*this, object, attr, v.data(), v.size());
}
void File::writeAttr(const std::string &object, const std::string &attr,
                     const std::string &v) const {
  Id obj = openObject(*this, object);
  if (H5Aexists(obj, attr.c_str()) > 0) H5Adelete(obj, attr.c_str());
  Id type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type, std::max<size_t>(1, v.size()));
  H5Tset_strpad(type, H5T_STR_NULLPAD);
  Id space(H5Screate(H5S_SCALAR), H5Sclose);
  Id a(H5Acreate2(obj, attr.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  std::string padded = v.empty() ? std::string(1, '\0') : v;
  const bool written = a.valid() && H5Awrite(a, type, padded.data()) >= 0;
  throwIfWriteFailed();
  if (!written)
    throw Error("could not write attribute '" + attr + "' to '" + name + "'");
}

template <typename T>
void File::write(const std::string &dataset, const std::vector<T> &data, hsize_t cols) const {
  hsize_t dims[2] = {cols ? data.size() / cols : data.size(), cols};
  Id space(H5Screate_simple(cols ? 2 : 1, dims, nullptr), H5Sclose);
  Id dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  if (protection == Checksums::fletcher32 && dims[0] > 0) { // an empty dataset has nothing to protect
    // As many chunks as kChunkBytes asks for, all of the same size: the last
    // one is stored whole, so rounding up only the row count wastes < 1 row per chunk.
    const hsize_t rowBytes = sizeof(T) * std::max<hsize_t>(cols, 1);
    const hsize_t chunks = (dims[0] * rowBytes + kChunkBytes - 1) / kChunkBytes;
    const hsize_t chunk[2] = {(dims[0] + chunks - 1) / chunks, cols};
    H5Pset_chunk(dcpl, cols ? 2 : 1, chunk);
    H5Pset_fletcher32(dcpl);
  }
  Id d(H5Dcreate2(file, dataset.c_str(), nativeType<T>(), space, H5P_DEFAULT, dcpl, H5P_DEFAULT), H5Dclose);
  const bool written =
      d.valid() && (data.empty() || H5Dwrite(d, nativeType<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()) >= 0);
  throwIfWriteFailed(); // the system's reason, when there is one, rather than HDF5's
  if (!written)
    throw Error("could not write dataset '" + dataset + "' to '" + name + "'");
}

template <typename T>
std::vector<T> File::read(const std::string &dataset, size_t expected) const {
  Id d = openDataset(dataset);
  Id space(H5Dget_space(d), H5Sclose);
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  if (expected && static_cast<size_t>(n) != expected)
    throw Error("HDF5 file '" + name + "': dataset '" + dataset + "' has " + std::to_string(n) +
                " values, expected " + std::to_string(expected));
  std::vector<T> v(n);
  if (n > 0) requireChecksum(d, dataset);
  if (n > 0 && H5Dread(d, nativeType<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0) {
    throwIfDamaged(name, dataset);
    throw Error("HDF5 file '" + name + "': dataset '" + dataset + "' could not be read as " +
                (std::is_floating_point_v<T> ? "numbers" : "integers"));
  }
  return v;
}

template <typename T>
std::vector<T> File::readRuns(const std::string &dataset,
                              const std::vector<std::pair<hsize_t, hsize_t>> &runs) const {
  Id d = openDataset(dataset);
  Id space(H5Dget_space(d), H5Sclose);
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  if (H5Sget_simple_extent_ndims(space) != 1)
    throw Error("HDF5 file '" + name + "': dataset '" + dataset + "' should be one-dimensional");
  std::vector<T> out;
  if (runs.empty()) return out;
  if (runs.back().second > static_cast<hsize_t>(n))
    throw Error("HDF5 file '" + name + "': dataset '" + dataset + "' has " + std::to_string(n) +
                " values, fewer than its row pointers require");
  const auto pieces = coalesce(runs, 64);
  hsize_t total = 0;
  H5Sselect_none(space);
  for (const auto &[b, e] : pieces) {
    const hsize_t count = e - b;
    H5Sselect_hyperslab(space, H5S_SELECT_OR, &b, nullptr, &count, nullptr);
    total += count;
  }
  std::vector<T> buffer(total);
  Id mem(H5Screate_simple(1, &total, nullptr), H5Sclose);
  requireChecksum(d, dataset);
  if (H5Dread(d, nativeType<T>(), mem, space, H5P_DEFAULT, buffer.data()) < 0) {
    throwIfDamaged(name, dataset);
    throw Error("HDF5 file '" + name + "': dataset '" + dataset + "' could not be read");
  }
  // Pick the requested runs out of the coalesced pieces.
  size_t p = 0;
  hsize_t pieceOffset = 0;
  for (const auto &[b, e] : runs) {
    while (pieces[p].second < e) pieceOffset += pieces[p].second - pieces[p].first, ++p;
    const auto *src = buffer.data() + pieceOffset + (b - pieces[p].first);
    out.insert(out.end(), src, src + (e - b));
  }
  return out;
}

std::pair<long long, double> File::verifyAll() const {
  std::vector<std::string> objects{"/"};
  const herr_t walked = H5Lvisit(
      file, H5_INDEX_NAME, H5_ITER_INC,
      [](hid_t, const char *link, const H5L_info_t *, void *data) -> herr_t {
        static_cast<std::vector<std::string> *>(data)->push_back(std::string("/") + link);
        return 0;
      },
      &objects);
  if (walked < 0) {
    throwIfDamaged(name, "/");
    throw Error("HDF5 file '" + name + "': its objects could not be listed");
  }
  long long datasets = 0;
  double bytes = 0.0;
  // Reads `n` values of `type` from a dataset or attribute, raw; false if HDF5 could not.
  auto readRaw = [](hid_t type, hssize_t n, const auto &read) {
    std::vector<unsigned char> raw(static_cast<size_t>(n) * H5Tget_size(type));
    return H5Tis_variable_str(type) > 0 || read(raw.data()) >= 0;
  };
  for (const std::string &object : objects) {
    Id o = openObject(*this, object); // its header, attributes in it included, is checked here
    H5O_info_t info;
    if (H5Oget_info2(o, &info, H5O_INFO_NUM_ATTRS) < 0) throwIfDamaged(name, object);
    for (hsize_t i = 0; i < info.num_attrs; ++i) { // attributes kept outside the header (many or large)
      Id a(H5Aopen_by_idx(o, ".", H5_INDEX_NAME, H5_ITER_NATIVE, i, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
      Id type(a.valid() ? H5Aget_type(a) : -1, H5Tclose);
      if (!type.valid() || !readRaw(type, static_cast<hssize_t>(attributeSize(a)), [&](void *to) { return H5Aread(a, type, to); })) {
        throwIfDamaged(name, object);
        throw Error("HDF5 file '" + name + "': an attribute of '" + object + "' could not be read");
      }
    }
    if (H5Iget_type(o) != H5I_DATASET) continue;
    Id type(H5Dget_type(o), H5Tclose);
    Id space(H5Dget_space(o), H5Sclose);
    const hssize_t n = H5Sget_simple_extent_npoints(space);
    ++datasets;
    if (n <= 0) continue;
    requireChecksum(o, object);
    if (!readRaw(type, n, [&](void *to) { return H5Dread(o, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, to); })) {
      throwIfDamaged(name, object);
      throw Error("HDF5 file '" + name + "': dataset '" + object + "' could not be read");
    }
    bytes += static_cast<double>(n) * static_cast<double>(H5Tget_size(type));
  }
  return {datasets, bytes};
}

template void File::write(const std::string &, const std::vector<double> &, hsize_t) const;
template void File::write(const std::string &, const std::vector<int32_t> &, hsize_t) const;
template void File::write(const std::string &, const std::vector<int64_t> &, hsize_t) const;
template void File::write(const std::string &, const std::vector<uint16_t> &, hsize_t) const;
template std::vector<double> File::read(const std::string &, size_t) const;
template std::vector<int32_t> File::read(const std::string &, size_t) const;
template std::vector<int64_t> File::read(const std::string &, size_t) const;
template std::vector<double> File::readRuns(const std::string &,
                                            const std::vector<std::pair<hsize_t, hsize_t>> &) const;
template std::vector<int32_t>
File::readRuns(const std::string &, const std::vector<std::pair<hsize_t, hsize_t>> &) const;
template std::vector<int64_t>
File::readRuns(const std::string &, const std::vector<std::pair<hsize_t, hsize_t>> &) const;
template std::vector<uint16_t> File::read(const std::string &, size_t) const;
template std::vector<uint16_t>
File::readRuns(const std::string &, const std::vector<std::pair<hsize_t, hsize_t>> &) const;

} // namespace rcfd::h5
