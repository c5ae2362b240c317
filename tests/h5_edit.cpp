// h5_edit FILE delete OBJECT        deletes a dataset or group (and what it holds)
// h5_edit FILE delete OBJECT ATTR   deletes an attribute of OBJECT ("/" for the root)
// h5_edit FILE keep DATASET N       keeps the first N values of a 1-D dataset of doubles
// A test helper for scripts that make the files of an older rcfd (or broken
// ones) out of today's, by removing what that rcfd did not write.  The file is
// edited in place; a missing object or attribute is an error.
#include "base/h5.hpp"

#include <cstdio>
#include <exception>
#include <string>
#include <vector>

namespace {

void remove(const rcfd::h5::File &f, const std::string &object) {
  if (!f.exists(object)) throw rcfd::h5::Error("'" + f.path() + "' has no object '" + object + "'");
  if (H5Ldelete(f.id(), object.c_str(), H5P_DEFAULT) < 0)
    throw rcfd::h5::Error("could not delete '" + object + "' of '" + f.path() + "'");
}

} // namespace

int main(int argc, char **argv) {
  const std::string command = argc > 2 ? argv[2] : "";
  if (!((command == "delete" && (argc == 4 || argc == 5)) || (command == "keep" && argc == 5))) {
    std::fprintf(stderr, "usage: h5_edit FILE delete OBJECT [ATTR] | FILE keep DATASET N\n");
    return 2;
  }
  try {
    auto f = rcfd::h5::File::openReadWrite(argv[1]);
    const std::string object = argv[3];
    if (command == "keep") {
      std::vector<double> values = f.read<double>(object);
      const std::size_t n = std::stoul(argv[4]);
      if (n > values.size())
        throw rcfd::h5::Error("'" + object + "' of '" + f.path() + "' holds fewer than " + argv[4] + " values");
      values.resize(n);
      remove(f, object);
      f.write(object, values);
    } else if (argc == 5) {
      if (!f.hasAttribute(object, argv[4]))
        throw rcfd::h5::Error("'" + f.path() + "' has no attribute '" + argv[4] + "' on '" + object + "'");
      if (H5Adelete_by_name(f.id(), object.c_str(), argv[4], H5P_DEFAULT) < 0)
        throw rcfd::h5::Error("could not delete attribute '" + std::string(argv[4]) + "' of '" + f.path() + "'");
    } else {
      remove(f, object);
    }
    f.close();
  } catch (const std::exception &e) {
    std::fprintf(stderr, "h5_edit: %s\n", e.what());
    return 1;
  }
  return 0;
}
