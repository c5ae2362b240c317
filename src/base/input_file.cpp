#include "base/input_file.hpp"

#include <stdexcept>
#include <sys/stat.h>

namespace rcfd {

std::string notRegularFile(const std::string &path) {
  struct stat s {};
  if (::stat(path.c_str(), &s) != 0 || S_ISREG(s.st_mode)) return "";
  const char *kind = S_ISDIR(s.st_mode)    ? "a directory"
                     : S_ISFIFO(s.st_mode) ? "a FIFO (named pipe)"
                     : S_ISCHR(s.st_mode)  ? "a character device"
                     : S_ISBLK(s.st_mode)  ? "a block device"
                     : S_ISSOCK(s.st_mode) ? "a socket"
                                           : "not a file";
  return "input file '" + path + "' is " + kind + ", not a regular file: rcfd reads its inputs from regular files only";
}

void requireRegularFile(const std::string &path) {
  const std::string problem = notRegularFile(path);
  if (!problem.empty()) throw std::runtime_error(problem);
}

} // namespace rcfd
