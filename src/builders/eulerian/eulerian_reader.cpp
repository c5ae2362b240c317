// Eulerian frame files read (eulerian_frames.hpp): the rows of a file, the box
// mesh laid over their centres, and the rows placed in its cells.
#include "builders/eulerian/eulerian_frames.hpp"

#include "base/input_file.hpp"
#include "builders/eulerian/eulerian_cells.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rcfd {

using eulerian::cellIjk;
using eulerian::cellCentre;
using eulerian::cellName;
using eulerian::number;
using eulerian::point;

namespace {

constexpr int kColumns = 10;
constexpr const char *kColumnNames[kColumns] = {"x",  "y",  "z",   "alpha", "Ux",
                                                "Uy", "Uz", "Usx", "Usy",   "Usz"};
constexpr const char *kAxisNames[3] = {"x", "y", "z"};

std::string where(const std::string &path, int line) {
  return "Eulerian frame '" + path + "', line " + std::to_string(line) + ": ";
}

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

/// Parses one whole token as a finite double (a leading '+' is allowed).
bool parseNumber(const char *begin, const char *end, double *out) {
  if (begin < end && *begin == '+') ++begin;
  const auto [ptr, ec] = std::from_chars(begin, end, *out);
  return ec == std::errc() && ptr == end && std::isfinite(*out);
}

} // namespace

EulerianRows readEulerianRows(const std::string &path) {
  requireRegularFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open Eulerian frame '" + path + "'.");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw std::runtime_error("cannot read Eulerian frame '" + path + "'.");
  const std::string text = buffer.str();

  EulerianRows rows;
  rows.source = path;
  const char *p = text.data(), *const end = text.data() + text.size();
  int line = 0;
  double v[kColumns];
  while (p < end) {
    const char *eol = static_cast<const char *>(std::memchr(p, '\n', end - p));
    if (!eol) eol = end;
    ++line;
    const char *q = p;
    while (q < eol && isBlank(*q)) ++q;
    if (q < eol && *q != '#') {
      int column = 0;
      while (q < eol) {
        const char *t = q;
        while (q < eol && !isBlank(*q)) ++q;
        if (column < kColumns && !parseNumber(t, q, &v[column]))
          throw std::runtime_error(where(path, line) + "column " + std::to_string(column + 1) +
                                   " (" + kColumnNames[column] + ") is '" + std::string(t, q) +
                                   "', not a finite number.");
        ++column;
        while (q < eol && isBlank(*q)) ++q;
      }
      if (column != kColumns)
        throw std::runtime_error(where(path, line) + "expected " + std::to_string(kColumns) +
                                 " numbers (x y z alpha Ux Uy Uz Usx Usy Usz), found " +
                                 std::to_string(column) + ".");
      if (v[3] < 0.0 || v[3] > 1.0)
        throw std::runtime_error(where(path, line) + "alpha (the void fraction, column 4) is " +
                                 number(v[3]) + ", outside [0, 1].");
      rows.line.push_back(line);
      rows.centre.push_back({v[0], v[1], v[2]});
      rows.voidFraction.push_back(v[3]);
      rows.gasVelocity.push_back({v[4], v[5], v[6]});
      rows.solidVelocity.push_back({v[7], v[8], v[9]});
    }
    p = eol + 1;
  }
  if (rows.size() == 0) throw std::runtime_error("Eulerian frame '" + path + "' holds no cell.");
  return rows;
}

BoxSpec resolveEulerianMesh(const EulerianMeshRequest &request, const EulerianRows &rows) {
  BoxSpec box;
  const std::string file = "Eulerian frame '" + rows.source + "'";
  for (int a = 0; a < 3; ++a) {
    std::vector<double> x(rows.size());
    for (std::size_t r = 0; r < rows.size(); ++r) x[r] = rows.centre[r][a];
    std::sort(x.begin(), x.end());
    const double lo = x.front(), hi = x.back();
    // Distinct coordinates, merging values closer than 1e-5 of the extent
    // (ASCII files round the centres).
    int distinct = 1;
    for (std::size_t r = 1; r < x.size(); ++r)
      if (x[r] - x[r - 1] > 1e-5 * (hi - lo)) ++distinct;
    const double spacing = distinct > 1 ? (hi - lo) / (distinct - 1) : 0.0;
    const bool hasBounds = request.lo && request.hi;
    int n = request.cells ? (*request.cells)[a] : distinct;
    if (hasBounds) {
      box.origin[a] = (*request.lo)[a];
      box.length[a] = (*request.hi)[a] - (*request.lo)[a];
      if (!request.cells && distinct > 1)
        n = std::max(1, static_cast<int>(std::lround(box.length[a] / spacing)));
    } else {
      if (n < 1)
        throw std::invalid_argument("the mesh needs at least one cell along each axis.");
      if (n == 1 && distinct == 1)
        throw std::runtime_error(file + ": every cell centre has " + kAxisNames[a] + " = " +
                                 number(lo) + ", so the cells' extent along " + kAxisNames[a] +
                                 " is unknown; give it with -mesh_lo and -mesh_hi.");
      const double h = n > 1 ? (hi - lo) / (n - 1) : 0.0;
      if (n == 1 || !(h > 0))
        throw std::runtime_error(file + ": the cell centres span " + number(lo) + " to " +
                                 number(hi) + " along " + kAxisNames[a] + ", which " +
                                 std::to_string(n) +
                                 " cell(s) cannot have as centres; give -mesh_lo and -mesh_hi.");
      box.origin[a] = lo - 0.5 * h;
      box.length[a] = (hi - lo) + h;
      // A box starting at 0 should say so, not 4e-19.
      if (std::fabs(box.origin[a]) < 1e-9 * box.length[a]) box.origin[a] = 0.0;
    }
    if (!(box.length[a] > 0))
      throw std::invalid_argument(std::string("-mesh_hi must exceed -mesh_lo along ") +
                                  kAxisNames[a] + ".");
    (a == 0 ? box.nx : a == 1 ? box.ny : box.nz) = n;
  }
  return box;
}

EulerianFrame mapOntoMesh(const EulerianRows &rows, const BoxSpec &mesh) {
  const int N = mesh.numCells();
  const Vec3 h = mesh.spacing();
  EulerianFrame f;
  f.source = rows.source;
  f.alphaS.assign(N, 0.0);
  f.gasVelocity.assign(N, Vec3{0.0, 0.0, 0.0});
  f.solidVelocity.assign(N, Vec3{0.0, 0.0, 0.0});
  std::vector<int> lineOf(N, 0);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const Vec3 &p = rows.centre[r];
    const int c = mesh.locate(p);
    if (c < 0) {
      const Vec3 hi{mesh.origin[0] + mesh.length[0], mesh.origin[1] + mesh.length[1],
                    mesh.origin[2] + mesh.length[2]};
      throw std::runtime_error(where(rows.source, rows.line[r]) + "the cell centre " + point(p) +
                               " is outside the mesh " + point(mesh.origin) + " to " + point(hi) +
                               ".");
    }
    const Vec3 x = cellCentre(mesh, cellIjk(mesh, c));
    for (int a = 0; a < 3; ++a)
      if (std::fabs(p[a] - x[a]) > 0.25 * h[a])
        throw std::runtime_error(where(rows.source, rows.line[r]) + "the cell centre " + point(p) +
                                 " lies in " + cellName(mesh, c) + " but " +
                                 number(std::fabs(p[a] - x[a]) / h[a]) + " cells away from its centre along " +
                                 kAxisNames[a] + ": the file's cells are not the mesh's.");
    if (lineOf[c])
      throw std::runtime_error(where(rows.source, rows.line[r]) + "the cell centre " + point(p) +
                               " gives " + cellName(mesh, c) + ", as line " +
                               std::to_string(lineOf[c]) + " does.");
    lineOf[c] = rows.line[r];
    f.alphaS[c] = 1.0 - rows.voidFraction[r];
    f.gasVelocity[c] = rows.gasVelocity[r];
    f.solidVelocity[c] = rows.solidVelocity[r];
  }
  const auto missing = std::find(lineOf.begin(), lineOf.end(), 0);
  if (missing != lineOf.end())
    throw std::runtime_error("Eulerian frame '" + rows.source + "' has " +
                             std::to_string(rows.size()) + " cells but the mesh " +
                             std::to_string(mesh.nx) + " x " + std::to_string(mesh.ny) + " x " +
                             std::to_string(mesh.nz) + " has " + std::to_string(N) + ": " +
                             std::to_string(std::count(lineOf.begin(), lineOf.end(), 0)) +
                             " missing, the first is " +
                             cellName(mesh, static_cast<int>(missing - lineOf.begin())) + ".");
  return f;
}

} // namespace rcfd
