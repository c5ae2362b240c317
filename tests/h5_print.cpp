// h5_print FILE DATASET             prints a dataset's values, one per line
// h5_print FILE OBJECT ATTR         prints a numeric attribute's values
// h5_print FILE OBJECT ATTR string  prints a string attribute
// A test helper for scripts that check what the rcfd program wrote
// (the machine may have no h5dump).  Numbers are printed with 17 digits.
#include "base/h5.hpp"

#include <cstdio>
#include <exception>
#include <string>

int main(int argc, char **argv) {
  if (argc < 3 || argc > 5) {
    std::fprintf(stderr, "usage: h5_print FILE DATASET | FILE OBJECT ATTR [string]\n");
    return 2;
  }
  try {
    const auto f = rcfd::h5::File::openRead(argv[1], MPI_COMM_NULL);
    if (argc == 5) {
      std::printf("%s\n", f.readAttrString(argv[2], argv[3]).c_str());
    } else {
      const auto v = argc == 4 ? f.readAttrDoubles(argv[2], argv[3]) : f.read<double>(argv[2]);
      for (double x : v) std::printf("%.17g\n", x);
    }
  } catch (const std::exception &e) {
    std::fprintf(stderr, "h5_print: %s\n", e.what());
    return 1;
  }
  return 0;
}
