// The database writer of the builders and tests, which report by exceptions:
// rcfd::DatabaseWriter (include/rcfd/database.hpp) is the public, PETSc-style
// face of this class.
#pragma once

#include "rcfd/database.hpp"

#include <memory>
#include <string>
#include <vector>

namespace rcfd {

/// Writes a database file from one process, frame by frame.  The file is
/// written under a temporary name and renamed by finish(), so a file with the
/// final name is always complete.  Throws std::invalid_argument on bad input
/// and h5::Error (a std::runtime_error) when the file cannot be written.
class DatabaseFileWriter {
public:
  /// `formatVersion` 2 writes the full CSR of older readers (tests keep the
  /// version 2 reader covered with it); the current version is the default.
  DatabaseFileWriter(const std::string &path, const Mesh &mesh, const DatabaseMetadata &meta,
                     long long formatVersion = kDatabaseFormatVersion);
  ~DatabaseFileWriter();
  DatabaseFileWriter(const DatabaseFileWriter &) = delete;
  DatabaseFileWriter &operator=(const DatabaseFileWriter &) = delete;

  void append(const FrameRecord &frame);
  /// Store an extra 2-D dataset (e.g. the recurrence matrix) before finish().
  void writeMatrix(const std::string &name, const std::vector<double> &rowMajor, int cols,
                   const std::string &note);
  /// Store a text attribute `key` on /metadata before finish() (e.g. a
  /// builder's report as "build_report"); `key` must not be a format attribute.
  void setNote(const std::string &key, const std::string &text);
  void finish();
  int numFrames() const { return frames; }

private:
  struct Impl;
  std::unique_ptr<Impl> impl;
  int frames = 0;
};

} // namespace rcfd
