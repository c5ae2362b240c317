// Thin RAII layer over the HDF5 C API, private to the library.  Functions
// throw rcfd::H5Error with a sentence naming the file and the object; the
// PETSc boundary turns that into an error code.
#pragma once

#include <hdf5.h>

#include <array>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace rcfd {
class AtomicFile;
}

namespace rcfd::h5 {

struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A read refused because the bytes stored no longer match their checksum:
/// the file was changed after it was written (a flipped bit on disk, a bad
/// copy, an edit outside HDF5).  `object` is what failed ("/frames/000012/
/// shift_col", or the file itself when HDF5's superblock fails).
struct Damaged : Error {
  Damaged(const std::string &what, std::string object) : Error(what), object(std::move(object)) {}
  std::string object;
  /// The end of every such sentence: what happened and what to do.
  static constexpr const char *reason =
      "its bytes do not match their checksum: the file changed after it was written; restore it or make it again";
};

/// What a file does to detect changed bits (docs/database-format.md, "Checksums").
enum class Checksums {
  none,      ///< HDF5's defaults: nothing detects a changed bit
  fletcher32 ///< every dataset chunked with HDF5's Fletcher-32 filter (a checksum per chunk) and all
             ///< of HDF5's own records (superblock, object headers with their attributes, chunk
             ///< indexes, link heaps) in HDF5 1.10's file format, which checksums each; the root
             ///< attribute `checksums` = "fletcher32" says so
};

/// Owner of one hid_t with the matching close function.
class Id {
public:
  Id() = default;
  Id(hid_t id, herr_t (*close)(hid_t)) : id(id), closer(close) {}
  Id(const Id &) = delete;
  Id &operator=(const Id &) = delete;
  Id(Id &&o) noexcept : id(o.id), closer(o.closer) { o.id = -1; }
  Id &operator=(Id &&o) noexcept {
    if (this != &o) {
      reset();
      id = o.id;
      closer = o.closer;
      o.id = -1;
    }
    return *this;
  }
  ~Id() { reset(); }
  void reset() { close(); }
  /// Close now; the status of the close function (negative: failed).
  herr_t close() {
    const herr_t status = id >= 0 && closer ? closer(id) : 0;
    id = -1;
    return status;
  }
  operator hid_t() const { return id; } // NOLINT
  bool valid() const { return id >= 0; }

private:
  hid_t id = -1;
  herr_t (*closer)(hid_t) = nullptr;
};

/// An open HDF5 file and the name it was opened under, for messages.
///
/// Files opened for writing use rcfd's
/// write driver (h5_write_driver.hpp): a failed write, e.g. on a full disk,
/// is reported by the next write call or close() as a sentence naming the
/// file and the system's reason, and HDF5 itself never fails to close it.
class File {
public:
  File() = default;
  File(File &&) = default;
  File &operator=(File &&other) noexcept {
    if (this != &other) {
      file.close(); // while its writeError still exists
      writeError = std::move(other.writeError);
      file = std::move(other.file);
      name = std::move(other.name);
      protection = other.protection;
    }
    return *this;
  }

  /// Open for reading; with comm != MPI_COMM_NULL through MPI-IO (collective).
  static File openRead(const std::string &path, MPI_Comm comm);
  /// Create (truncate) for writing by one process.
  static File create(const std::string &path, Checksums checksums = Checksums::none);
  /// Create target's temporary for writing by one process; messages name target.path().
  static File create(const AtomicFile &target, Checksums checksums = Checksums::none);
  /// Create (truncate) for writing by all processes of comm through MPI-IO.
  static File createParallel(const std::string &path, MPI_Comm comm);
  /// Open an existing file for read-write by one process; what it adds to a
  /// file with checksums gets them too.
  static File openReadWrite(const std::string &path);

  /// Close the file, flushing it, and throw naming it if HDF5 could not
  /// finish it (a file being written must be closed this way before it is
  /// committed; the destructor cannot report a failure).
  void close();

  hid_t id() const { return file; }
  const std::string &path() const { return name; }
  /// Whether the file protects its contents (the root attribute `checksums`);
  /// every dataset read from such a file is checked to carry the checksum filter.
  Checksums checksums() const { return protection; }
  /// Reads every dataset of the file whole, so that each chunk's checksum is
  /// compared (HDF5's records on the way are compared as they are read), and
  /// checks that each non-empty dataset has one.  Throws Damaged naming the
  /// first object that fails; returns the number of datasets and their bytes.
  /// Meaningful for files with checksums().
  std::pair<long long, double> verifyAll() const;

  bool exists(const std::string &object) const;
  void requireGroup(const std::string &group) const; // throws naming what is missing
  Id openDataset(const std::string &dataset) const;
  void createGroup(const std::string &group) const;
  /// Extents of a dataset; throws if it is missing.
  std::vector<hsize_t> extents(const std::string &dataset) const;

  // Attributes on groups ("/" for the root).
  bool hasAttribute(const std::string &object, const std::string &attr) const;
  double readAttrDouble(const std::string &object, const std::string &attr) const;
  long long readAttrInt(const std::string &object, const std::string &attr) const;
  std::string readAttrString(const std::string &object, const std::string &attr) const;
  std::vector<double> readAttrDoubles(const std::string &object, const std::string &attr) const;
  std::vector<long long> readAttrInts(const std::string &object, const std::string &attr) const;
  void writeAttr(const std::string &object, const std::string &attr, double v) const;
  void writeAttr(const std::string &object, const std::string &attr, long long v) const;
  void writeAttr(const std::string &object, const std::string &attr, const std::string &v) const;
  void writeAttr(const std::string &object, const std::string &attr, const std::vector<double> &v) const;
  void writeAttr(const std::string &object, const std::string &attr,
                 const std::vector<long long> &v) const;

  /// Write a whole dataset of rank 1 (cols == 0) or rank 2 (rows x cols).
  template <typename T>
  void write(const std::string &dataset, const std::vector<T> &data, hsize_t cols = 0) const;
  /// Read a whole dataset; the element count must be `expected` (0: any).
  template <typename T> std::vector<T> read(const std::string &dataset, size_t expected = 0) const;
  /// Read the elements of a 1-D dataset in the given sorted, disjoint [begin, end) runs,
  /// concatenated.  Used so that each rank reads only its own rows.
  template <typename T>
  std::vector<T> readRuns(const std::string &dataset,
                          const std::vector<std::pair<hsize_t, hsize_t>> &runs) const;

  /// Throws naming the file if one of its writes failed on disk.
  void throwIfWriteFailed() const;

private:
  // Declared before `file`: the driver stores into it until the file is closed.
  std::unique_ptr<int> writeError; // the first failed write's errno (files opened for writing)
  Id file;
  std::string name; // for messages: the final name of an atomic file
  Checksums protection = Checksums::none; // of what is written and read

  void adoptChecksums(); // reads the root attribute `checksums`
  void requireChecksum(hid_t dataset, const std::string &name) const;
};

} // namespace rcfd::h5
