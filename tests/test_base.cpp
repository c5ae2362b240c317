// src/base: the atomic file writer, the CSV reader, and the defaults that the
// public DatabaseMetadata repeats.
#include "check.hpp"
#include "base/atomic_file.hpp"
#include "base/constants.hpp"
#include "base/csv.hpp"
#include "base/h5.hpp"
#include "rcfd/database.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

using namespace rcfd;
using rcfd::test::throwsWith;

namespace {

bool exists(const std::string &path) { return access(path.c_str(), F_OK) == 0; }

std::string contents(const std::string &path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void atomicFile(const std::string &dir) {
  const std::string path = dir + "/a.txt";
  writeTextAtomically(path, "first\n");
  RCFD_CHECK(contents(path) == "first\n");
  RCFD_CHECK(!exists(path + ".tmp"));
  writeTextAtomically(path, "second\n");
  RCFD_CHECK(contents(path) == "second\n");

  // A writer that fails before commit leaves the previous file and no temporary.
  try {
    AtomicFile out(path);
    std::ofstream(out.temporaryPath()) << "half";
    throw std::runtime_error("writer failed");
  } catch (const std::runtime_error &) {
  }
  RCFD_CHECK(contents(path) == "second\n");
  RCFD_CHECK(!exists(path + ".tmp"));

  // Committing what was never written names the file.
  RCFD_CHECK(throwsWith([&] { AtomicFile(dir + "/never.txt").commit(); }, "'" + dir + "/never.txt'"));
  // A missing directory is an error naming the file, not a silent loss.
  RCFD_CHECK(throwsWith([&] { writeTextAtomically(dir + "/no/such/dir/b.txt", "x"); },
                        "cannot write '" + dir + "/no/such/dir/b.txt': No such file or directory"));
  // HDF5 through the same object: the file only appears after close + commit.
  const std::string h = dir + "/b.h5";
  {
    AtomicFile out(h);
    h5::File f = h5::File::create(out.temporaryPath());
    f.write("/x", std::vector<double>{1.0, 2.0});
    f.close();
    RCFD_CHECK(!exists(h));
    out.commit();
  }
  RCFD_CHECK(exists(h) && !exists(h + ".tmp"));
  RCFD_CHECK(h5::File::openRead(h, MPI_COMM_NULL).read<double>("/x") == std::vector<double>({1.0, 2.0}));
}

void csvReader(const std::string &dir) {
  const std::string path = dir + "/t.csv";
  writeTextAtomically(path, "# a comment\ntime_s, z_m ,name\n\n0,1.5,a\r\n0.5, -2e-3 ,b\n");
  const csv::Table t = csv::Table::read(path);
  RCFD_CHECK(t.columns() == std::vector<std::string>({"time_s", "z_m", "name"}));
  RCFD_CHECK(t.numRows() == 2 && t.lineOf(0) == 4 && t.lineOf(1) == 5);
  RCFD_CHECK(t.find({"time", "time_s"}) == 0 && t.find({"z_m"}) == 1 && t.find({"nope"}) == -1);
  RCFD_CHECK(t.number(1, 1) == -2e-3 && t.number(0, 0) == 0.0);
  RCFD_CHECK(t.field(1, 2) == "b");
  RCFD_CHECK(throwsWith([&] { t.number(1, 2); },
                        "'" + path + "', line 5, column 'name': expected a number, found 'b'"));
  writeTextAtomically(path, "a,b\n1,2\n3\n");
  RCFD_CHECK(throwsWith([&] { csv::Table::read(path); }, "line 3: expected 2 values"));
  writeTextAtomically(path, "# only a comment\n");
  RCFD_CHECK(throwsWith([&] { csv::Table::read(path); }, "expected a header line"));
  RCFD_CHECK(throwsWith([&] { csv::Table::read(dir + "/missing.csv"); }, "missing.csv"));
  double v = 0;
  RCFD_CHECK(csv::parseNumber("+1e3", v) && v == 1e3);
  RCFD_CHECK(!csv::parseNumber("1e3x", v) && !csv::parseNumber("", v) && !csv::parseNumber("nan", v) &&
             !csv::parseNumber("1e999", v));
}

// The suite's own message for a failed closeness check: a tolerance of 1e-14 and values
// that differ in the 17th digit are printed as they are (not 0.000000 and 0.300000).
void checkMessages() {
  RCFD_CHECK(rcfd::test::closeFailure("a", 0.1 + 0.2, "b", 0.3, 1e-14) ==
             "a = 0.30000000000000004, b = 0.29999999999999999, tol 1e-14");
  RCFD_CHECK(rcfd::test::closeFailure("a", -2.5e-300, "b", 1e300, 0.125) ==
             "a = -2.5e-300, b = 1.0000000000000001e+300, tol 0.125");
}

} // namespace

int main() {
  char tmpl[] = "/tmp/rcfd_test_base_XXXXXX";
  const char *dir = mkdtemp(tmpl);
  if (!dir) return 1;
  atomicFile(dir);
  csvReader(dir);
  checkMessages();
  // The public header repeats the defaults of src/base/constants.hpp.
  const DatabaseMetadata meta;
  RCFD_CHECK(meta.solidDensity == kDefaultSolidDensity);
  RCFD_CHECK(meta.gravity[0] == 0.0 && meta.gravity[1] == 0.0 && meta.gravity[2] == -kGravity);
  std::filesystem::remove_all(dir);
  return RCFD_TEST_RESULT();
}
