#include "base/atomic_file.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <stdexcept>
#include <unistd.h>

namespace rcfd {
namespace {

[[noreturn]] void fail(const std::string &what, const std::string &path, int err) {
  throw std::runtime_error(what + " '" + path + "': " + (err ? std::strerror(err) : "disk full?"));
}

// fsync a file or directory by name; directories that cannot be synced
// (EINVAL on some file systems) are not an error.
void syncPath(const std::string &name, const std::string &path, bool directory) {
  const int fd = ::open(name.c_str(), directory ? O_RDONLY | O_DIRECTORY : O_RDONLY);
  if (fd < 0) fail("cannot open for flushing to disk", path, errno);
  const bool synced = ::fsync(fd) == 0 || (directory && (errno == EINVAL || errno == EROFS));
  const int syncErr = errno;
  const bool closed = ::close(fd) == 0;
  if (!synced) fail("cannot flush to disk", path, syncErr);
  if (!closed) fail("cannot close after flushing", path, errno);
}

std::string directoryOf(const std::string &path) {
  const size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

} // namespace

AtomicFile::AtomicFile(std::string path)
    : finalPath(std::move(path)), tmpPath(temporaryPathOf(finalPath)) {}

AtomicFile::~AtomicFile() {
  if (!committed) std::remove(tmpPath.c_str()); // nothing to do if it was never created
}

void AtomicFile::commit() {
  if (committed) throw std::logic_error("AtomicFile '" + finalPath + "' committed twice");
  syncPath(tmpPath, finalPath, false);
  if (std::rename(tmpPath.c_str(), finalPath.c_str()) != 0)
    fail("cannot rename the finished temporary '" + tmpPath + "' to", finalPath, errno);
  committed = true;
  syncPath(directoryOf(finalPath), finalPath, true);
}

void writeTextAtomically(const std::string &path, const std::string &text) {
  AtomicFile out(path);
  FILE *f = std::fopen(out.temporaryPath().c_str(), "w");
  if (!f) fail("cannot write", path, errno);
  const size_t written = std::fwrite(text.data(), 1, text.size(), f);
  const int writeErr = errno;
  const bool closed = std::fclose(f) == 0;
  if (written != text.size()) fail("could not write all of", path, writeErr);
  if (!closed) fail("could not finish writing (close failed)", path, errno);
  out.commit();
}

} // namespace rcfd
