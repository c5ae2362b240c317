// Particle snapshot readers: LIGGGHTS/LAMMPS dumps in any column order,
// plain and gzip, CSV snapshots, and the message of every error.
#include "check.hpp"
#include "particles/particle_dump.hpp"

#include <zlib.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

using namespace rcfd;

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string makeTempDir() {
  char tmpl[] = "/tmp/rcfd_test_dump_XXXXXX";
  const char *dir = mkdtemp(tmpl);
  if (!dir) throw std::runtime_error("mkdtemp failed");
  return dir;
}

void writePlain(const std::string &path, const std::string &text) {
  std::FILE *f = std::fopen(path.c_str(), "w");
  if (!f) throw std::runtime_error("cannot write " + path);
  std::fputs(text.c_str(), f);
  std::fclose(f);
}

void writeGzip(const std::string &path, const std::string &text) {
  gzFile f = gzopen(path.c_str(), "wb");
  if (!f) throw std::runtime_error("cannot write " + path);
  gzwrite(f, text.data(), static_cast<unsigned>(text.size()));
  gzclose(f);
}

/// A dump with the standard 9 header lines (atom lines start at line 10).
std::string dump(const std::string &columns, const std::vector<std::string> &atoms,
                 long declared = -1, long timestep = 100) {
  std::string s = "ITEM: TIMESTEP\n" + std::to_string(timestep) + "\nITEM: NUMBER OF ATOMS\n" +
                  std::to_string(declared >= 0 ? declared : static_cast<long>(atoms.size())) +
                  "\nITEM: BOX BOUNDS ff ff ff\n-0.04 0.04\n-0.006 0.006\n0 0.3\nITEM: ATOMS " +
                  columns + "\n";
  for (const std::string &a : atoms) s += a + "\n";
  return s;
}

/// Checks that `read` throws std::runtime_error whose message holds every
/// one of `parts`.
void expectError(const std::function<void()> &read, const std::vector<std::string> &parts,
                 const char *file, int line) {
  try {
    read();
    rcfd::test::fail(file, line, "no exception thrown");
  } catch (const std::runtime_error &e) {
    const std::string msg = e.what();
    for (const std::string &p : parts)
      if (msg.find(p) == std::string::npos)
        rcfd::test::fail(file, line, "message \"" + msg + "\" lacks \"" + p + "\"");
  }
}
#define EXPECT_ERROR(read, ...) expectError([&] { read; }, {__VA_ARGS__}, __FILE__, __LINE__)

// The three particles every well-formed file in this test describes.
struct Expected {
  int64_t id;
  int type;
  Vec3 x;
  double d;
};
const std::vector<Expected> kParticles = {
    {7, 1, {0.01, -0.002, 0.05}, 0.00195},
    {3, 2, {-0.02, 0.003, 0.12}, 0.00282},
    {12, 1, {0.0, 0.0, 0.001}, 0.00195},
};

void checkParticles(const ParticleSnapshot &s, double density, bool types, const char *file,
                    int line) {
  if (s.size() != kParticles.size()) {
    rcfd::test::fail(file, line, "wrong particle count " + std::to_string(s.size()));
    return;
  }
  for (std::size_t p = 0; p < s.size(); ++p) {
    const Expected &e = kParticles[p];
    const double mass = density * kPi / 6.0 * e.d * e.d * e.d;
    bool ok = s.id[p] == e.id && (!types || s.type[p] == e.type) &&
              std::fabs(s.diameter[p] - e.d) < 1e-15 && std::fabs(s.mass[p] - mass) <= 1e-12 * mass;
    for (int a = 0; a < 3; ++a) ok = ok && s.position[p][a] == e.x[a];
    if (!ok) rcfd::test::fail(file, line, "particle " + std::to_string(p) + " read wrongly");
  }
}
#define CHECK_PARTICLES(s, rho, types) checkParticles(s, rho, types, __FILE__, __LINE__)

// Formats one particle's value for a named column.
std::string value(const Expected &e, const std::string &col, double density) {
  char buf[64];
  const double v = col == "id"                       ? double(e.id)
                   : col == "type"                   ? double(e.type)
                   : col == "x"                      ? e.x[0]
                   : col == "y"                      ? e.x[1]
                   : col == "z"                      ? e.x[2]
                   : col == "radius"                 ? e.d / 2
                   : col == "diameter" || col == "d" ? e.d
                   : col == "density"                ? density
                   : col == "mass"                   ? density * kPi / 6.0 * e.d * e.d * e.d
                                                     : 0.5; // any other column
  if (col == "id" || col == "type")
    std::snprintf(buf, sizeof buf, "%lld", static_cast<long long>(v));
  else
    std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::vector<std::string> rows(const std::vector<std::string> &cols, double density,
                              const char *sep) {
  std::vector<std::string> out;
  for (const Expected &e : kParticles) {
    std::string r;
    for (std::size_t c = 0; c < cols.size(); ++c) r += (c ? sep : "") + value(e, cols[c], density);
    out.push_back(r);
  }
  return out;
}

std::string join(const std::vector<std::string> &cols, const char *sep) {
  std::string s;
  for (std::size_t c = 0; c < cols.size(); ++c) s += (c ? sep : "") + cols[c];
  return s;
}

void testColumnOrders(const std::string &dir) {
  SnapshotReadOptions opt;
  opt.defaultDensity = 1440.0;
  const std::vector<std::vector<std::string>> layouts = {
      {"id", "type", "x", "y", "z", "radius"},
      {"radius", "z", "id", "vx", "x", "type", "y"},
      {"x", "y", "z", "id", "type", "diameter", "omegax"},
      {"type", "diameter", "density", "z", "y", "x", "id"},
      {"mass", "id", "type", "z", "radius", "x", "y"},
      {"id", "type", "x", "y", "z", "radius", "density", "mass"},
  };
  const double density[] = {1440.0, 1440.0, 1440.0, 2500.0, 900.0, 3000.0};
  int n = 0;
  for (std::size_t l = 0; l < layouts.size(); ++l) {
    const std::string text = dump(join(layouts[l], " "), rows(layouts[l], density[l], " "));
    for (bool gz : {false, true}) {
      const std::string path = dir + "/order" + std::to_string(n++) + (gz ? ".gz" : ".txt");
      gz ? writeGzip(path, text) : writePlain(path, text);
      const ParticleSnapshot s = readDumpSnapshot(path, opt);
      CHECK_PARTICLES(s, density[l], true);
      RCFD_CHECK(s.timestep == 100);
      RCFD_CHECK(s.hasBox && !s.triclinic);
      RCFD_CHECK(s.boxLo[0] == -0.04 && s.boxHi[0] == 0.04 && s.boxLo[2] == 0.0 &&
                 s.boxHi[2] == 0.3);
      RCFD_CHECK(s.source == path);
      CHECK_PARTICLES(readParticleSnapshot(path, opt), density[l], true); // auto-detected
    }
  }
  // Unwrapped coordinates when x y z are absent; tabs and \r\n tolerated.
  std::string text =
      dump("id type xu yu zu radius", rows({"id", "type", "x", "y", "z", "radius"}, 0, "\t"));
  std::string crlf;
  for (char c : text) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  writePlain(dir + "/unwrapped.txt", crlf);
  CHECK_PARTICLES(readDumpSnapshot(dir + "/unwrapped.txt", opt), 1440.0, true);

  // With both a density and a mass column the density decides the mass.
  writePlain(dir + "/both.txt",
             dump("id type x y z radius density mass", {"1 1 0 0 0 0.001 2000 99"}));
  const ParticleSnapshot both = readDumpSnapshot(dir + "/both.txt", opt);
  RCFD_CHECK_CLOSE(both.mass[0], 2000.0 * kPi / 6.0 * 8e-9, 1e-15);
}

void testOtherSections(const std::string &dir) {
  SnapshotReadOptions opt;
  opt.defaultDensity = 1000.0;
  // ITEM: UNITS / ITEM: TIME are skipped; triclinic bounds; no atoms at all.
  const std::string text =
      "ITEM: UNITS\nsi\nITEM: TIME\n0.25\nITEM: TIMESTEP\n5\nITEM: NUMBER OF ATOMS\n0\n"
      "ITEM: BOX BOUNDS xy xz yz pp pp ff\n0 1 0.1\n0 2 0\n0 3 0\n"
      "ITEM: ATOMS id type x y z radius\n";
  writePlain(dir + "/empty.txt", text);
  const ParticleSnapshot s = readDumpSnapshot(dir + "/empty.txt", opt);
  RCFD_CHECK(s.size() == 0 && s.timestep == 5 && s.triclinic && s.boxHi[1] == 2.0);

  // Several snapshots in one file: DumpStream reads them in turn.
  const std::vector<std::string> cols = {"id", "type", "x", "y", "z", "radius"};
  writeGzip(dir + "/multi.gz", dump(join(cols, " "), rows(cols, 0, " "), -1, 10) +
                                   dump(join(cols, " "), rows(cols, 0, " "), -1, 20));
  DumpStream stream(dir + "/multi.gz", opt);
  ParticleSnapshot a;
  RCFD_CHECK(stream.next(a) && a.timestep == 10 && a.size() == 3);
  RCFD_CHECK(stream.next(a) && a.timestep == 20 && a.size() == 3);
  RCFD_CHECK(!stream.next(a));
  EXPECT_ERROR(readDumpSnapshot(dir + "/multi.gz", opt), dir + "/multi.gz", "line 13",
               "expected the end of the file after one snapshot", "DumpStream");
}

void testCsv(const std::string &dir) {
  SnapshotReadOptions opt;
  opt.defaultDensity = 1440.0;
  const std::vector<std::string> plain = {"id", "x", "y", "z", "d"};
  writePlain(dir + "/a.csv", join(plain, ",") + "\n" + join(rows(plain, 0, ","), "\n") + "\n");
  ParticleSnapshot s = readCsvSnapshot(dir + "/a.csv", opt);
  CHECK_PARTICLES(s, 1440.0, false);
  RCFD_CHECK(s.timestep == -1 && !s.hasBox && s.type[0] == 1);
  CHECK_PARTICLES(readParticleSnapshot(dir + "/a.csv", opt), 1440.0, false);

  // Any order, spaces, quotes, upper case, comments, blank lines, gzip.
  const std::vector<std::string> mixed = {"d", "z", "type", "mass", "y", "x", "id"};
  const std::string header = "# written by hand\n \"D\", z ,Type,MASS, y,x,ID\n";
  writeGzip(dir + "/b.csv.gz", header + join(rows(mixed, 2000.0, " , "), "\n\n") + "\n");
  s = readParticleSnapshot(dir + "/b.csv.gz", opt);
  CHECK_PARTICLES(s, 2000.0, true);

  const std::vector<std::string> rad = {"radius", "id", "z", "y", "x", "density"};
  writePlain(dir + "/c.csv", join(rad, ",") + "\n" + join(rows(rad, 800.0, ","), "\n"));
  CHECK_PARTICLES(readCsvSnapshot(dir + "/c.csv", opt), 800.0, false); // no final newline
}

void testErrors(const std::string &dir) {
  SnapshotReadOptions opt;
  opt.defaultDensity = 1440.0;
  const std::string std6 = "id type x y z radius";
  auto file = [&](const std::string &name, const std::string &text) {
    const std::string p = dir + "/" + name;
    writePlain(p, text);
    return p;
  };
  const std::string good = "1 1 0.0 0.0 0.01 0.001";

  EXPECT_ERROR(readDumpSnapshot(dir + "/nope.gz", opt), "cannot open", dir + "/nope.gz",
               "No such file");
  EXPECT_ERROR(readParticleSnapshot(dir + "/nope.csv", opt), "cannot open", dir + "/nope.csv");

  std::string p = file("nocol.txt", dump("id type x y z", {"1 1 0 0 0"}));
  EXPECT_ERROR(readDumpSnapshot(p, opt), p, "line 9", "expected a column 'radius' or 'diameter'");
  p = file("noz.txt", dump("id type x y radius", {"1 1 0 0 0.001"}));
  EXPECT_ERROR(readDumpSnapshot(p, opt), p, "line 9", "expected a column 'z' (or 'zu')");
  p = file("noid.csv", "x,y,z,d\n0,0,0,0.001\n");
  EXPECT_ERROR(readCsvSnapshot(p, opt), p, "line 1", "expected a column 'id'");
  p = file("twice.txt", dump("id type x y z radius x", {"1 1 0 0 0 0.001 0"}));
  EXPECT_ERROR(readDumpSnapshot(p, opt), p, "line 9", "expected each column name once", "'x'");

  p = file("short.txt", dump(std6, {good, "2 1 0.0 0.01 0.001"}));
  EXPECT_ERROR(readDumpSnapshot(p, opt), p, "line 11",
               "expected 6 values (id type x y z radius), found 5");
  p = file("long.csv", "id,x,y,z,d\n1,0,0,0,0.001\n2,0,0,0,0.001,7\n");
  EXPECT_ERROR(readCsvSnapshot(p, opt), p, "line 3", "expected 5 values (id x y z d), found 6");

  p = file("nan.txt", dump(std6, {good, good, "3 1 0.0 0.0 abc 0.001"}));
  EXPECT_ERROR(readDumpSnapshot(p, opt), p, "line 12",
               "expected a finite number in column 'z', found 'abc'");
  p = file("inf.txt", dump(std6, {"1 1 inf 0.0 0.0 0.001"}));
  EXPECT_ERROR(readDumpSnapshot(p, opt), p, "line 10", "expected a finite number in column 'x'");
  p = file("badid.txt", dump(std6, {"1.5 1 0.0 0.0 0.0 0.001"}));
  EXPECT_ERROR(readDumpSnapshot(p, opt), p, "line 10",
               "expected an integer in column 'id', found '1.5'");
  p = file("trail.csv", "id,x,y,z,d\n1,0,0,0.2x,0.001\n");
  EXPECT_ERROR(readCsvSnapshot(p, opt), p, "line 2", "column 'z', found '0.2x'");

  p = file("negr.txt", dump(std6, {good, "2 1 0.0 0.0 0.0 -0.001"}));
  EXPECT_ERROR(readDumpSnapshot(p, opt), p, "line 11",
               "expected a positive radius, found '-0.001'");
  p = file("zeror.txt", dump(std6, {"2 1 0.0 0.0 0.0 0"}));
  EXPECT_ERROR(readDumpSnapshot(p, opt), p, "line 10", "expected a positive radius, found '0'");
  p = file("zerod.csv", "id,x,y,z,d\n1,0,0,0,0\n");
  EXPECT_ERROR(readCsvSnapshot(p, opt), p, "line 2", "expected a positive diameter");
  p = file("negrho.txt", dump("id type x y z radius density", {"2 1 0 0 0 0.001 -5"}));
  EXPECT_ERROR(readDumpSnapshot(p, opt), p, "line 10", "expected a positive density");

  p = file("fewer.txt", dump(std6, {good, good}, 3));
  EXPECT_ERROR(
      readDumpSnapshot(p, opt), p, "line 12",
      "expected 3 atom lines (ITEM: NUMBER OF ATOMS, line 4), found 2 before the end of the file");
  p = file("fewer2.txt", dump(std6, {good}, 2) + "ITEM: TIMESTEP\n200\n");
  EXPECT_ERROR(readDumpSnapshot(p, opt), p, "line 11", "expected 2 atom lines",
               "found 1 before 'ITEM: TIMESTEP'");
  p = file("more.txt", dump(std6, {good, good, good}, 2));
  EXPECT_ERROR(readDumpSnapshot(p, opt), p, "line 12",
               "expected 2 atom lines as ITEM: NUMBER OF ATOMS says, found more");
  p = file("badcount.txt", "ITEM: TIMESTEP\n1\nITEM: NUMBER OF ATOMS\nmany\n");
  EXPECT_ERROR(readDumpSnapshot(p, opt), p, "line 4",
               "expected the number of atoms (one integer), found 'many'");
  p = file("noatoms.txt", "ITEM: TIMESTEP\n1\nITEM: NUMBER OF ATOMS\n1\n");
  EXPECT_ERROR(readDumpSnapshot(p, opt), p, "line 5", "expected an 'ITEM: ATOMS' section");
  p = file("nocount.txt", "ITEM: TIMESTEP\n1\nITEM: ATOMS id type x y z radius\n1 1 0 0 0 0.001\n");
  EXPECT_ERROR(readDumpSnapshot(p, opt), p, "line 3",
               "expected 'ITEM: NUMBER OF ATOMS' before 'ITEM: ATOMS'");
  p = file("garbage.txt", "ITEM: TIMESTEP\n1\nhello\n");
  EXPECT_ERROR(readDumpSnapshot(p, opt), p, "line 3",
               "expected an 'ITEM:' header line, found 'hello'");
  p = file("box.txt", "ITEM: TIMESTEP\n1\nITEM: BOX BOUNDS pp pp pp\n0 1\n0\n");
  EXPECT_ERROR(readDumpSnapshot(p, opt), p, "line 5", "expected 2 numbers (box bounds)");
  p = file("empty.csv", "\n# nothing\n");
  EXPECT_ERROR(readCsvSnapshot(p, opt), p, "line 3", "expected a header line");

  // Neither density nor mass, and no default density.
  p = file("nodensity.csv", "id,x,y,z,d\n1,0,0,0,0.001\n");
  SnapshotReadOptions noDefault;
  EXPECT_ERROR(readCsvSnapshot(p, noDefault), p, "neither a density nor a mass column",
               "default density");

  // A truncated gzip stream.
  const std::vector<std::string> cols = {"id", "type", "x", "y", "z", "radius"};
  std::vector<std::string> many;
  for (int i = 0; i < 20000; ++i)
    many.push_back(std::to_string(i) + " 1 0.001 0.002 " + std::to_string(i * 1e-6) + " 0.001");
  writeGzip(dir + "/whole.gz", dump(join(cols, " "), many));
  {
    std::FILE *in = std::fopen((dir + "/whole.gz").c_str(), "rb");
    std::vector<char> bytes(1 << 22);
    const std::size_t n = std::fread(bytes.data(), 1, bytes.size(), in);
    std::fclose(in);
    std::FILE *out = std::fopen((dir + "/cut.gz").c_str(), "wb");
    std::fwrite(bytes.data(), 1, n / 2, out);
    std::fclose(out);
  }
  EXPECT_ERROR(readDumpSnapshot(dir + "/cut.gz", opt), dir + "/cut.gz",
               "gzip stream is truncated or corrupt");
}

void testTimesAndAxes(const std::string &dir) {
  writePlain(dir + "/times.txt", "# index time\n0 0.005\n1 0.010\n\n2 0.015\n");
  const std::vector<double> t = readSnapshotTimes(dir + "/times.txt");
  RCFD_CHECK(t.size() == 3 && t[0] == 0.005 && t[2] == 0.015);
  writePlain(dir + "/badtimes.txt", "0 0.005\n1 soon\n");
  EXPECT_ERROR(readSnapshotTimes(dir + "/badtimes.txt"), dir + "/badtimes.txt", "line 2",
               "expected 'index time'");

  const Vec3 p{1.0, 2.0, 3.0};
  RCFD_CHECK(AxisMap{}.isIdentity() && AxisMap::verticalUp(2, -1).isIdentity());
  RCFD_CHECK((AxisMap::verticalUp(1, -1).apply(p) == Vec3{3.0, 1.0, 2.0}));
  RCFD_CHECK((AxisMap::verticalUp(0, -1).apply(p) == Vec3{2.0, 3.0, 1.0}));
  RCFD_CHECK((AxisMap::verticalUp(2, 1).apply(p) == Vec3{1.0, 2.0, -3.0}));
  bool threw = false;
  try {
    AxisMap bad;
    bad.from = {0, 0, 2};
    bad.validate();
  } catch (const std::invalid_argument &) {
    threw = true;
  }
  RCFD_CHECK(threw);
}

} // namespace

int main() {
  const std::string dir = makeTempDir();
  testColumnOrders(dir);
  testOtherSections(dir);
  testCsv(dir);
  testErrors(dir);
  testTimesAndAxes(dir);
  std::filesystem::remove_all(dir);
  return RCFD_TEST_RESULT();
}
