#include "particles/particle_dump.hpp"

#include "base/csv.hpp"
#include "base/input_file.hpp"
#include "base/constants.hpp"

#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string_view>

namespace rcfd {
namespace {


// ---------------------------------------------------------------- errors

[[noreturn]] void failAt(const std::string &file, long line, const std::string &what) {
  throw std::runtime_error("particle snapshot '" + file + "', line " + std::to_string(line) + ": " +
                           what + ".");
}

std::string quoted(std::string_view s) {
  constexpr std::size_t kMax = 60; // keep messages one readable line
  std::string out(s.substr(0, kMax));
  if (s.size() > kMax) out += "...";
  return "'" + out + "'";
}

// ---------------------------------------------------------------- lines

/// Reads a plain or gzip file line by line through zlib (gzread passes
/// plain files through unchanged).  Lines of any length; "\r\n" tolerated.
class LineReader {
public:
  explicit LineReader(std::string path) : path_(std::move(path)) {
    requireRegularFile(path_);
    errno = 0;
    file_ = gzopen(path_.c_str(), "rb");
    if (!file_)
      throw std::runtime_error("cannot open particle snapshot '" + path_ +
                               "': " + (errno ? std::strerror(errno) : "gzopen failed") + ".");
    gzbuffer(file_, 1u << 18); // larger than the default 8 KiB: fewer read calls
  }
  ~LineReader() { gzclose(file_); }
  LineReader(const LineReader &) = delete;
  LineReader &operator=(const LineReader &) = delete;

  const std::string &path() const { return path_; }
  long lineNo() const { return lineNo_; }

  /// Next line without its end-of-line characters; false at end of file.
  bool next(std::string_view &line) {
    if (pushedBack_) {
      pushedBack_ = false;
      ++lineNo_;
      line = current_;
      return true;
    }
    // A line longer than the buffer (or a last line without '\n') arrives in
    // pieces, which are joined in long_.
    long_.clear();
    for (;;) {
      if (!gzgets(file_, buf_, sizeof buf_)) {
        checkStreamError();
        if (long_.empty()) return false;
        current_ = long_;
        break;
      }
      const std::size_t n = std::strlen(buf_);
      const bool complete = n > 0 && buf_[n - 1] == '\n';
      if (complete && long_.empty()) { // the common case: no copy
        current_ = std::string_view(buf_, n);
        break;
      }
      long_.append(buf_, n);
      if (complete) {
        current_ = long_;
        break;
      }
    }
    while (!current_.empty() && (current_.back() == '\n' || current_.back() == '\r'))
      current_.remove_suffix(1);
    ++lineNo_;
    line = current_;
    return true;
  }

  /// The next call to next() returns the last line again.
  void pushBack() {
    pushedBack_ = true;
    --lineNo_;
  }

private:
  void checkStreamError() {
    int code = Z_OK;
    const char *msg = gzerror(file_, &code);
    if (code == Z_OK) return;
    std::string why = code == Z_ERRNO ? std::strerror(errno) : msg;
    if (why.rfind(path_ + ": ", 0) == 0) why.erase(0, path_.size() + 2); // zlib prefixes the path
    failAt(path_, lineNo_ + 1,
           "expected more readable data, but reading stopped (" + why +
               "): the gzip stream is truncated or corrupt");
  }

  std::string path_;
  gzFile file_ = nullptr;
  char buf_[1 << 16];
  std::string long_;
  std::string_view current_;
  long lineNo_ = 0;
  bool pushedBack_ = false;
};

// ---------------------------------------------------------------- tokens

bool isBlank(std::string_view s) {
  return std::all_of(s.begin(), s.end(),
                     [](char c) { return std::isspace(static_cast<unsigned char>(c)); });
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

void splitWhitespace(std::string_view s, std::vector<std::string_view> &out) {
  out.clear();
  const char *p = s.data(), *end = p + s.size();
  for (;;) {
    while (p != end && (*p == ' ' || *p == '\t')) ++p;
    if (p == end) return;
    const char *b = p;
    while (p != end && *p != ' ' && *p != '\t') ++p;
    out.emplace_back(b, static_cast<std::size_t>(p - b));
  }
}

bool startsWith(std::string_view s, std::string_view prefix) {
  return s.substr(0, prefix.size()) == prefix;
}

// ---------------------------------------------------------------- numbers

// Reals go through csv::parseNumber; both use std::from_chars, which is
// locale-independent and much faster than streams.
bool parseInt(std::string_view t, int64_t &v) {
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  return r.ec == std::errc() && r.ptr == t.data() + t.size();
}

// ---------------------------------------------------------------- columns

/// Where each quantity sits in a particle line; -1 when absent.
struct ColumnLayout {
  int count = 0;
  int id = -1, type = -1, pos[3] = {-1, -1, -1}, radius = -1, diameter = -1, density = -1,
      mass = -1;
  std::string names; // as written, for messages
};

/// Finds the known columns among `names` (already lower-cased for CSV).
/// `diameterAliases` lists the names accepted for the diameter.
ColumnLayout resolveColumns(const std::vector<std::string_view> &names, const std::string &file,
                            long line, const std::vector<std::string_view> &diameterAliases) {
  ColumnLayout L;
  L.count = static_cast<int>(names.size());
  for (std::size_t c = 0; c < names.size(); ++c) L.names += (c ? " " : "") + std::string(names[c]);
  auto setOnce = [&](int &slot, int c, std::string_view name) {
    if (slot >= 0)
      failAt(file, line, "expected each column name once, found " + quoted(name) + " twice");
    slot = c;
  };
  int unwrapped[3] = {-1, -1, -1};
  for (int c = 0; c < L.count; ++c) {
    const std::string_view n = names[c];
    if (n == "id")
      setOnce(L.id, c, n);
    else if (n == "type")
      setOnce(L.type, c, n);
    else if (n == "x")
      setOnce(L.pos[0], c, n);
    else if (n == "y")
      setOnce(L.pos[1], c, n);
    else if (n == "z")
      setOnce(L.pos[2], c, n);
    else if (n == "xu")
      setOnce(unwrapped[0], c, n);
    else if (n == "yu")
      setOnce(unwrapped[1], c, n);
    else if (n == "zu")
      setOnce(unwrapped[2], c, n);
    else if (n == "radius")
      setOnce(L.radius, c, n);
    else if (std::find(diameterAliases.begin(), diameterAliases.end(), n) != diameterAliases.end())
      setOnce(L.diameter, c, n);
    else if (n == "density")
      setOnce(L.density, c, n);
    else if (n == "mass")
      setOnce(L.mass, c, n);
  }
  // Prefer wrapped positions (they lie in the box); fall back to unwrapped.
  for (int a = 0; a < 3; ++a)
    if (L.pos[a] < 0) L.pos[a] = unwrapped[a];
  const char *axis[3] = {"x", "y", "z"};
  if (L.id < 0) failAt(file, line, "expected a column 'id' among the columns " + quoted(L.names));
  for (int a = 0; a < 3; ++a)
    if (L.pos[a] < 0)
      failAt(file, line,
             std::string("expected a column '") + axis[a] + "' (or '" + axis[a] +
                 "u') among the columns " + quoted(L.names));
  if (L.radius < 0 && L.diameter < 0) {
    std::string alt;
    for (auto a : diameterAliases) alt += " or '" + std::string(a) + "'";
    failAt(file, line,
           "expected a column 'radius'" + alt + " among the columns " + quoted(L.names));
  }
  if (L.radius >= 0 && L.diameter >= 0)
    failAt(file, line,
           "expected either a radius or a diameter column, found both in " + quoted(L.names));
  return L;
}

/// Parses one particle line's tokens into `snap`.
class ParticleLineParser {
public:
  ParticleLineParser(const ColumnLayout &layout, const std::string &file, double defaultDensity)
      : L(layout), file(file), defaultDensity(defaultDensity) {
    if (L.density < 0 && L.mass < 0 && !(defaultDensity > 0.0))
      throw std::runtime_error("particle snapshot '" + file +
                               "' has neither a density nor a mass column, so the caller must give "
                               "a positive default density (got " +
                               std::to_string(defaultDensity) + ").");
  }

  void parse(const std::vector<std::string_view> &tok, long line, ParticleSnapshot &snap) const {
    if (static_cast<int>(tok.size()) != L.count)
      failAt(file, line,
             "expected " + std::to_string(L.count) + " values (" + L.names + "), found " +
                 std::to_string(tok.size()));
    int64_t id = 0, type = 1;
    integer(tok, L.id, "id", line, id);
    if (L.type >= 0) integer(tok, L.type, "type", line, type);
    Vec3 p;
    const char *axis[3] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a) p[a] = number(tok, L.pos[a], axis[a], line);
    double d = 0.0;
    if (L.radius >= 0)
      d = 2.0 * positive(tok, L.radius, "radius", line);
    else
      d = positive(tok, L.diameter, "diameter", line);
    const double volume = kPi / 6.0 * d * d * d;
    double m = 0.0;
    if (L.density >= 0)
      m = positive(tok, L.density, "density", line) * volume;
    else if (L.mass >= 0)
      m = positive(tok, L.mass, "mass", line);
    else
      m = defaultDensity * volume;
    if (L.density >= 0 && L.mass >= 0) positive(tok, L.mass, "mass", line); // still validated
    snap.id.push_back(id);
    snap.type.push_back(static_cast<int>(type));
    snap.position.push_back(p);
    snap.diameter.push_back(d);
    snap.mass.push_back(m);
  }

private:
  double number(const std::vector<std::string_view> &tok, int c, const char *name,
                long line) const {
    double v = 0.0;
    if (!csv::parseNumber(tok[c], v))
      failAt(file, line,
             std::string("expected a finite number in column '") + name + "', found " +
                 quoted(tok[c]));
    return v;
  }
  double positive(const std::vector<std::string_view> &tok, int c, const char *name,
                  long line) const {
    const double v = number(tok, c, name, line);
    if (!(v > 0.0))
      failAt(file, line, std::string("expected a positive ") + name + ", found " + quoted(tok[c]));
    return v;
  }
  void integer(const std::vector<std::string_view> &tok, int c, const char *name, long line,
               int64_t &v) const {
    if (!parseInt(tok[c], v))
      failAt(file, line,
             std::string("expected an integer in column '") + name + "', found " + quoted(tok[c]));
  }

  const ColumnLayout &L;
  const std::string &file;
  double defaultDensity;
};

bool nextNonBlank(LineReader &in, std::string_view &line) {
  while (in.next(line))
    if (!isBlank(line)) return true;
  return false;
}

// ================================================================ dump

/// Parses the snapshots of a dump file one after another.
class DumpParser {
public:
  DumpParser(const std::string &path, const SnapshotReadOptions &opt) : in(path), opt(opt) {}

  LineReader in;
  SnapshotReadOptions opt;
  std::vector<std::string_view> tok;

  /// Reads the value line that follows an ITEM header.
  std::string_view valueLine(const char *what) {
    std::string_view line;
    if (!in.next(line))
      failAt(in.path(), in.lineNo() + 1,
             std::string("expected ") + what + ", found the end of the file");
    return line;
  }

  int64_t integerLine(const char *what) {
    const std::string_view line = valueLine(what);
    splitWhitespace(line, tok);
    int64_t v = 0;
    if (tok.size() != 1 || !parseInt(tok[0], v))
      failAt(in.path(), in.lineNo(), std::string("expected ") + what + ", found " + quoted(line));
    return v;
  }

  void readBox(std::string_view header, ParticleSnapshot &snap) {
    snap.hasBox = true;
    snap.triclinic = header.find("xy") != std::string_view::npos;
    const std::size_t want = snap.triclinic ? 3 : 2;
    for (int a = 0; a < 3; ++a) {
      const std::string_view line = valueLine("a box-bounds line");
      splitWhitespace(line, tok);
      double lo = 0.0, hi = 0.0, tilt = 0.0;
      if (tok.size() != want || !csv::parseNumber(tok[0], lo) || !csv::parseNumber(tok[1], hi) ||
          (want == 3 && !csv::parseNumber(tok[2], tilt)))
        failAt(in.path(), in.lineNo(),
               "expected " + std::to_string(want) + " numbers (box bounds), found " + quoted(line));
      snap.boxLo[a] = lo;
      snap.boxHi[a] = hi;
    }
  }

  /// Reads `count` particle lines after the ATOMS header.
  void readAtoms(std::string_view header, int64_t count, long countLine, ParticleSnapshot &snap) {
    const long headerLine = in.lineNo();
    splitWhitespace(header.substr(std::strlen("ITEM: ATOMS")), tok);
    const ColumnLayout layout = resolveColumns(tok, in.path(), headerLine, {"diameter"});
    const ParticleLineParser parser(layout, in.path(), opt.defaultDensity);
    // The header's count is a claim until the lines are there: reserve no more
    // than a million up front, so that a wrong count is reported, not a bad_alloc.
    const auto expected = static_cast<std::size_t>(std::min<int64_t>(count, int64_t{1} << 20));
    snap.id.reserve(expected);
    snap.type.reserve(expected);
    snap.position.reserve(expected);
    snap.diameter.reserve(expected);
    snap.mass.reserve(expected);
    std::string_view line;
    for (int64_t n = 0; n < count; ++n) {
      const bool got = in.next(line);
      if (!got || startsWith(line, "ITEM:"))
        failAt(in.path(), got ? in.lineNo() : in.lineNo() + 1,
               "expected " + std::to_string(count) + " atom lines (ITEM: NUMBER OF ATOMS, line " +
                   std::to_string(countLine) + "), found " + std::to_string(n) +
                   (got ? " before " + quoted(line) : " before the end of the file"));
      splitWhitespace(line, tok);
      parser.parse(tok, in.lineNo(), snap);
    }
  }

  bool next(ParticleSnapshot &snap) {
    snap = ParticleSnapshot{};
    snap.source = in.path();
    std::string_view line;
    if (!nextNonBlank(in, line)) return false;
    int64_t count = -1;
    long countLine = 0;
    for (;;) {
      if (!startsWith(line, "ITEM:"))
        failAt(in.path(), in.lineNo(), "expected an 'ITEM:' header line, found " + quoted(line));
      const std::string header(line); // the line buffer is reused by the next read
      if (startsWith(header, "ITEM: TIMESTEP")) {
        snap.timestep = integerLine("the timestep (one integer)");
      } else if (startsWith(header, "ITEM: NUMBER OF ATOMS")) {
        count = integerLine("the number of atoms (one integer)");
        countLine = in.lineNo();
        if (count < 0)
          failAt(in.path(), countLine,
                 "expected a non-negative number of atoms, found " + std::to_string(count));
      } else if (startsWith(header, "ITEM: BOX BOUNDS")) {
        readBox(header, snap);
      } else if (startsWith(header, "ITEM: ATOMS")) {
        if (count < 0)
          failAt(in.path(), in.lineNo(), "expected 'ITEM: NUMBER OF ATOMS' before 'ITEM: ATOMS'");
        readAtoms(header, count, countLine, snap);
        return true;
      } else {
        // Other sections (ITEM: UNITS, ITEM: TIME, ...): skip to the next ITEM.
        while (in.next(line)) {
          if (startsWith(line, "ITEM:")) {
            in.pushBack();
            break;
          }
        }
      }
      if (!nextNonBlank(in, line))
        failAt(in.path(), in.lineNo() + 1,
               "expected an 'ITEM: ATOMS' section, found the end of the file");
    }
  }
};

} // namespace

struct DumpStream::Impl {
  Impl(const std::string &path, const SnapshotReadOptions &opt) : parser(path, opt) {}
  DumpParser parser;
};

DumpStream::DumpStream(const std::string &path, const SnapshotReadOptions &opt)
    : impl(std::make_unique<Impl>(path, opt)) {}
DumpStream::~DumpStream() = default;
bool DumpStream::next(ParticleSnapshot &snap) { return impl->parser.next(snap); }

namespace {

/// The rest of a dump after its first snapshot must be empty.
void expectEnd(LineReader &in, std::size_t atoms) {
  std::string_view line;
  if (!nextNonBlank(in, line)) return;
  if (startsWith(line, "ITEM:"))
    failAt(in.path(), in.lineNo(),
           "expected the end of the file after one snapshot, found " + quoted(line) +
               " (read files with several snapshots through DumpStream)");
  failAt(in.path(), in.lineNo(),
         "expected " + std::to_string(atoms) +
             " atom lines as ITEM: NUMBER OF ATOMS says, found more");
}

ParticleSnapshot readOneDump(DumpParser &reader) {
  ParticleSnapshot snap;
  if (!reader.next(snap))
    failAt(reader.in.path(), reader.in.lineNo() + 1,
           "expected 'ITEM: TIMESTEP', found an empty file");
  expectEnd(reader.in, snap.size());
  return snap;
}

ParticleSnapshot readCsv(LineReader &in, const SnapshotReadOptions &opt) {
  ParticleSnapshot snap;
  snap.source = in.path();
  std::string_view line;
  auto nextData = [&]() {
    while (in.next(line))
      if (!isBlank(line) && trim(line).front() != '#') return true;
    return false;
  };
  if (!nextData())
    failAt(in.path(), in.lineNo() + 1,
           "expected a header line naming the columns, found the end of the file");
  std::vector<std::string_view> tok;
  csv::splitLine(line, tok);
  // Header names: case-insensitive, optional quotes.
  std::vector<std::string> names;
  for (std::string_view t : tok) {
    if (t.size() >= 2 && (t.front() == '"' || t.front() == '\'') && t.back() == t.front())
      t = t.substr(1, t.size() - 2);
    std::string n(t);
    std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return std::tolower(c); });
    names.push_back(std::move(n));
  }
  const std::vector<std::string_view> nameViews(names.begin(), names.end());
  const ColumnLayout layout = resolveColumns(nameViews, in.path(), in.lineNo(), {"d", "diameter"});
  const ParticleLineParser parser(layout, in.path(), opt.defaultDensity);
  while (nextData()) {
    csv::splitLine(line, tok);
    parser.parse(tok, in.lineNo(), snap);
  }
  return snap;
}

} // namespace

ParticleSnapshot readDumpSnapshot(const std::string &path, const SnapshotReadOptions &opt) {
  DumpParser reader(path, opt);
  return readOneDump(reader);
}

ParticleSnapshot readCsvSnapshot(const std::string &path, const SnapshotReadOptions &opt) {
  LineReader in(path);
  return readCsv(in, opt);
}

ParticleSnapshot readParticleSnapshot(const std::string &path, const SnapshotReadOptions &opt) {
  // Open once: peek at the first non-blank line, put it back, read on.
  DumpParser reader(path, opt);
  std::string_view line;
  const bool isDump = nextNonBlank(reader.in, line) && startsWith(line, "ITEM:");
  if (reader.in.lineNo() > 0) reader.in.pushBack();
  return isDump ? readOneDump(reader) : readCsv(reader.in, opt);
}

// ================================================================ misc

AxisMap AxisMap::verticalUp(int verticalAxis, int gravitySign) {
  if (verticalAxis < 0 || verticalAxis > 2)
    throw std::invalid_argument(
        "AxisMap::verticalUp: the vertical axis must be 0, 1 or 2 (x, y, z)");
  if (gravitySign != 1 && gravitySign != -1)
    throw std::invalid_argument("AxisMap::verticalUp: the gravity sign must be +1 or -1");
  AxisMap m;
  m.from = {(verticalAxis + 1) % 3, (verticalAxis + 2) % 3, verticalAxis};
  m.sign = {1, 1, -gravitySign}; // gravity along -axis means the axis points up
  return m;
}

bool AxisMap::isIdentity() const {
  return from == std::array<int, 3>{0, 1, 2} && sign == std::array<int, 3>{1, 1, 1};
}

void AxisMap::validate() const {
  std::array<int, 3> seen{0, 0, 0};
  for (int a = 0; a < 3; ++a) {
    if (from[a] < 0 || from[a] > 2 || seen[from[a]]++)
      throw std::invalid_argument("AxisMap: 'from' must be a permutation of 0, 1, 2");
    if (sign[a] != 1 && sign[a] != -1)
      throw std::invalid_argument("AxisMap: signs must be +1 or -1");
  }
}

std::vector<double> readSnapshotTimes(const std::string &path) {
  LineReader in(path);
  std::vector<double> times;
  std::vector<std::string_view> tok;
  std::string_view line;
  while (in.next(line)) {
    line = trim(line);
    if (line.empty() || line.front() == '#') continue;
    splitWhitespace(line, tok);
    double t = 0.0;
    if (tok.empty() || tok.size() > 2 || !csv::parseNumber(tok.back(), t))
      failAt(path, in.lineNo(),
             "expected 'index time' (the time a number in s), found " + quoted(line));
    times.push_back(t);
  }
  return times;
}

} // namespace rcfd
