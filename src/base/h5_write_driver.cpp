#include "base/h5_write_driver.hpp"

#include <H5FDpublic.h>

#include <cerrno>
#include <climits>
#include <cstring>
#include <fcntl.h>
#include <new>
#include <sys/stat.h>
#include <unistd.h>

namespace rcfd::h5 {
namespace {

struct Config {
  int *firstError;
};

struct CheckedFile {
  H5FD_t pub; // first: HDF5 sees the file as an H5FD_t
  int fd = -1;
  haddr_t eoa = 0, eof = 0;
  dev_t device = 0;
  ino_t inode = 0;
  int *firstError = nullptr;

  void failed(int err) {
    if (*firstError == 0) *firstError = err ? err : EIO;
  }
  bool broken() const { return *firstError != 0; }
};

CheckedFile *cast(H5FD_t *f) { return reinterpret_cast<CheckedFile *>(f); }
const CheckedFile *cast(const H5FD_t *f) { return reinterpret_cast<const CheckedFile *>(f); }

H5FD_t *openFile(const char *name, unsigned flags, hid_t fapl, haddr_t) {
  const auto *config = static_cast<const Config *>(H5Pget_driver_info(fapl));
  if (!config || !config->firstError) return nullptr;
  int o = (flags & H5F_ACC_RDWR) ? O_RDWR : O_RDONLY;
  if (flags & H5F_ACC_TRUNC) o |= O_TRUNC;
  if (flags & H5F_ACC_CREAT) o |= O_CREAT;
  if (flags & H5F_ACC_EXCL) o |= O_EXCL;
  const int fd = ::open(name, o, 0666);
  if (fd < 0) return nullptr;
  struct stat st {};
  if (fstat(fd, &st) != 0) {
    ::close(fd);
    return nullptr;
  }
  auto *f = new (std::nothrow) CheckedFile();
  if (!f) {
    ::close(fd);
    return nullptr;
  }
  f->fd = fd;
  f->eof = static_cast<haddr_t>(st.st_size);
  f->device = st.st_dev;
  f->inode = st.st_ino;
  f->firstError = config->firstError;
  return &f->pub;
}

herr_t closeFile(H5FD_t *file) {
  CheckedFile *f = cast(file);
  if (::close(f->fd) != 0) f->failed(errno);
  delete f;
  return 0;
}

int compare(const H5FD_t *a, const H5FD_t *b) {
  const CheckedFile *x = cast(a), *y = cast(b);
  if (x->device != y->device) return x->device < y->device ? -1 : 1;
  if (x->inode != y->inode) return x->inode < y->inode ? -1 : 1;
  return 0;
}

herr_t query(const H5FD_t *, unsigned long *flags) {
  if (flags)
    *flags = H5FD_FEAT_AGGREGATE_METADATA | H5FD_FEAT_ACCUMULATE_METADATA | H5FD_FEAT_DATA_SIEVE |
             H5FD_FEAT_AGGREGATE_SMALLDATA;
  return 0;
}

haddr_t getEoa(const H5FD_t *file, H5FD_mem_t) { return cast(file)->eoa; }
herr_t setEoa(H5FD_t *file, H5FD_mem_t, haddr_t addr) {
  cast(file)->eoa = addr;
  return 0;
}
haddr_t getEof(const H5FD_t *file, H5FD_mem_t) { return cast(file)->eof; }

herr_t getHandle(H5FD_t *file, hid_t, void **handle) {
  *handle = &cast(file)->fd;
  return 0;
}

herr_t readAt(H5FD_t *file, H5FD_mem_t, hid_t, haddr_t addr, size_t size, void *buffer) {
  CheckedFile *f = cast(file);
  auto *out = static_cast<unsigned char *>(buffer);
  while (size > 0) {
    const ssize_t n = pread(f->fd, out, size, static_cast<off_t>(addr));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return -1;
    if (n == 0) { // past the end of the file: HDF5 expects zeros
      std::memset(out, 0, size);
      break;
    }
    out += n, addr += static_cast<haddr_t>(n), size -= static_cast<size_t>(n);
  }
  return 0;
}

herr_t writeAt(H5FD_t *file, H5FD_mem_t, hid_t, haddr_t addr, size_t size, const void *buffer) {
  CheckedFile *f = cast(file);
  const haddr_t end = addr + size;
  const auto *in = static_cast<const unsigned char *>(buffer);
  while (size > 0 && !f->broken()) {
    const ssize_t n = pwrite(f->fd, in, size, static_cast<off_t>(addr));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) f->failed(n < 0 ? errno : ENOSPC);
    else in += n, addr += static_cast<haddr_t>(n), size -= static_cast<size_t>(n);
  }
  if (end > f->eof) f->eof = end;
  return 0; // a failure is reported by h5::File, never to HDF5
}

herr_t truncateFile(H5FD_t *file, hid_t, hbool_t) {
  CheckedFile *f = cast(file);
  if (f->eoa != f->eof && !f->broken() && ftruncate(f->fd, static_cast<off_t>(f->eoa)) != 0)
    f->failed(errno);
  f->eof = f->eoa;
  return 0;
}

hid_t driverId() {
  static const H5FD_class_t cls = [] {
    H5FD_class_t c{};
    c.name = "rcfd_checked_write";
    c.maxaddr = static_cast<haddr_t>(LLONG_MAX);
    c.fc_degree = H5F_CLOSE_WEAK;
    c.fapl_size = sizeof(Config);
    c.open = openFile;
    c.close = closeFile;
    c.cmp = compare;
    c.query = query;
    c.get_eoa = getEoa;
    c.set_eoa = setEoa;
    c.get_eof = getEof;
    c.get_handle = getHandle;
    c.read = readAt;
    c.write = writeAt;
    c.truncate = truncateFile;
    const H5FD_mem_t map[H5FD_MEM_NTYPES] = H5FD_FLMAP_DICHOTOMY;
    std::memcpy(c.fl_map, map, sizeof map);
    return c;
  }();
  static const hid_t id = H5FDregister(&cls);
  return id;
}

} // namespace

hid_t checkedWriteAccess(int *firstError) {
  const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  const Config config{firstError};
  if (fapl >= 0 && (driverId() < 0 || H5Pset_driver(fapl, driverId(), &config) < 0)) {
    H5Pclose(fapl);
    return -1;
  }
  return fapl;
}

} // namespace rcfd::h5
