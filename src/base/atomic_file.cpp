#include "base/atomic_file.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <csignal>
#include <cstdlib>
#include <fcntl.h>
#include <stdexcept>
#include <sys/resource.h>
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

// The test hook (see atomic_file.hpp): whether writes to `path` are to fail.
bool injectedFailureFor(const std::string &path) {
  const char *text = std::getenv("RCFD_FAIL_WRITE");
  return text && *text && path.find(text) != std::string::npos;
}

void setFileSizeLimit(rlim_t limit) {
  rlimit r{};
  if (getrlimit(RLIMIT_FSIZE, &r) != 0) return;
  r.rlim_cur = std::min(limit, r.rlim_max);
  setrlimit(RLIMIT_FSIZE, &r);
}

// Lift the hook's limit (back to the hard limit: unlimited unless the user set one).
void liftFileSizeLimit() { setFileSizeLimit(RLIM_INFINITY); }

} // namespace

AtomicFile::AtomicFile(std::string path)
    : finalPath(std::move(path)), tmpPath(temporaryPathOf(finalPath)) {
  if (injectedFailureFor(finalPath)) {
    const char *bytes = std::getenv("RCFD_FAIL_WRITE_BYTES");
    std::signal(SIGXFSZ, SIG_IGN); // a write past the limit fails with EFBIG instead of killing
    setFileSizeLimit(bytes ? static_cast<rlim_t>(std::strtoull(bytes, nullptr, 10)) : 0);
    limited = true;
  }
}

AtomicFile::~AtomicFile() {
  if (limited) liftFileSizeLimit();
  if (!committed) std::remove(tmpPath.c_str()); // nothing to do if it was never created
}

void AtomicFile::commit() {
  if (committed) throw std::logic_error("AtomicFile '" + finalPath + "' committed twice");
  syncPath(tmpPath, finalPath, false);
  if (std::rename(tmpPath.c_str(), finalPath.c_str()) != 0)
    fail("cannot rename the finished temporary '" + tmpPath + "' to", finalPath, errno);
  committed = true;
  if (limited) liftFileSizeLimit(), limited = false;
  syncPath(directoryOf(finalPath), finalPath, true);
}

AtomicTextFile::AtomicTextFile(const std::string &path)
    : target(path), file(std::fopen(target.temporaryPath().c_str(), "w")) {
  if (!file) fail("cannot write", path, errno);
}

AtomicTextFile::~AtomicTextFile() {
  if (file) std::fclose(file);
}

void AtomicTextFile::commit() {
  const bool flushed = std::fflush(file) == 0 && !std::ferror(file);
  const int writeErr = errno;
  const bool closed = std::fclose(file) == 0;
  const int closeErr = errno;
  file = nullptr;
  if (!flushed) fail("could not write all of", target.path(), writeErr);
  if (!closed) fail("could not finish writing (close failed)", target.path(), closeErr);
  target.commit();
}

void writeTextAtomically(const std::string &path, const std::string &text) {
  AtomicTextFile out(path);
  std::fwrite(text.data(), 1, text.size(), out.get()); // checked by commit()
  out.commit();
}

} // namespace rcfd
