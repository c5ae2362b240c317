// Files that appear complete or not at all.  Every file rcfd writes for a
// user (databases, checkpoints, fields, CSV series, paths, built inputs)
// goes through AtomicFile, so that a crash, a full disk or an error half-way
// leaves the previous file intact instead of a truncated one.
#pragma once

#include <cstdio>
#include <string>

namespace rcfd {

/// The contents are written under temporaryPath() (`<path>.tmp`, in the same
/// directory so that the rename cannot cross file systems) by any writer --
/// stdio, HDF5, a PETSc viewer -- which closes it with its status checked;
/// commit() then flushes the temporary to disk and renames it over path().
/// If commit() is never reached (an error, an exception), the destructor
/// removes the temporary.
///
///     AtomicFile out(path);
///     h5::File f = h5::File::create(out); // names `path` in messages
///     ... write ...
///     f.close();    // throws if HDF5 could not finish the file
///     out.commit(); // throws naming `path`
///
/// Not collective: when several ranks write one file (a PETSc HDF5 viewer),
/// one rank owns the AtomicFile and commits after the others have closed it.
///
/// Test hook: with the environment variable RCFD_FAIL_WRITE=TEXT, every
/// AtomicFile whose path contains TEXT fails its writes as a full disk would:
/// while it exists, the process may not grow any file beyond
/// RCFD_FAIL_WRITE_BYTES bytes (default 0; setrlimit RLIMIT_FSIZE, SIGXFSZ
/// ignored), so stdio, HDF5 and MPI-IO see real EFBIG errors.  Keep the
/// process's stdout and stderr on pipes while it is used.
class AtomicFile {
public:
  explicit AtomicFile(std::string path);
  ~AtomicFile();
  AtomicFile(const AtomicFile &) = delete;
  AtomicFile &operator=(const AtomicFile &) = delete;

  const std::string &path() const { return finalPath; }
  const std::string &temporaryPath() const { return tmpPath; }
  /// The temporary name used for `path` (the same on every rank).
  static std::string temporaryPathOf(const std::string &path) { return path + ".tmp"; }

  /// Flush the finished, closed temporary to disk (fsync), rename it to
  /// path() and flush the directory entry.  Throws std::runtime_error with a
  /// sentence naming path() and the system's reason.
  void commit();

private:
  std::string finalPath, tmpPath;
  bool committed = false, limited = false;
};

/// A text file written with stdio through an AtomicFile.
class AtomicTextFile {
public:
  explicit AtomicTextFile(const std::string &path); // throws naming `path`
  ~AtomicTextFile();
  AtomicTextFile(const AtomicTextFile &) = delete;
  AtomicTextFile &operator=(const AtomicTextFile &) = delete;
  std::FILE *get() const { return file; }
  /// Check every write, close, commit; throws naming the file.
  void commit();

private:
  AtomicFile target; // declared first: the stream is closed before the temporary is removed
  std::FILE *file = nullptr;
};

/// Write `text` to `path` through an AtomicFile, checking every write and the
/// close; throws std::runtime_error naming `path`.
void writeTextAtomically(const std::string &path, const std::string &text);

} // namespace rcfd
