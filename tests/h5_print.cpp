// h5_print FILE DATASET             prints a dataset's values, one per line
// h5_print FILE OBJECT ATTR         prints a numeric attribute's values
// h5_print FILE OBJECT ATTR string  prints a string attribute
// A test helper for scripts that check what the rcfd program wrote
// (the machine may have no h5dump).  Numbers are printed with 17 digits.
// A database frame's shift_row_ptr, shift_col and shift_val are printed as
// the full CSR in every format version (version 3 stores moving rows only and
// readStoredFrame puts the identity rows back), so that scripts check frames
// whatever version wrote them.
#include "base/h5.hpp"
#include "database/stored_frame.hpp"

#include <cstdio>
#include <exception>
#include <regex>
#include <string>
#include <vector>

namespace {

// The full-CSR dataset `name` of a database frame, if `name` is one.
bool storedShift(const rcfd::h5::File &f, const std::string &name, std::vector<double> *values) {
  std::smatch m;
  static const std::regex frame("/frames/([0-9]{6})/shift_(row_ptr|col|val)");
  if (!std::regex_match(name, m, frame) || !f.hasAttribute("/", "format_version") ||
      f.readAttrInt("/", "format_version") < 3)
    return false;
  const int cells = static_cast<int>(f.extents("/mesh/cell_volumes").at(0));
  const rcfd::FrameRecord r = rcfd::readStoredFrame(f, std::stoi(m[1]), cells);
  if (m[2] == "row_ptr") values->assign(r.shift.rowPtr.begin(), r.shift.rowPtr.end());
  else if (m[2] == "col") values->assign(r.shift.col.begin(), r.shift.col.end());
  else *values = r.shift.val;
  return true;
}

} // namespace

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
      std::vector<double> v;
      if (argc == 4) v = f.readAttrDoubles(argv[2], argv[3]);
      else if (!storedShift(f, argv[2], &v)) v = f.read<double>(argv[2]);
      for (double x : v) std::printf("%.17g\n", x);
    }
  } catch (const std::exception &e) {
    std::fprintf(stderr, "h5_print: %s\n", e.what());
    return 1;
  }
  return 0;
}
