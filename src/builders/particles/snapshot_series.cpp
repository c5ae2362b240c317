#include "builders/particles/snapshot_series.hpp"

#include "base/input_file.hpp"

#include <glob.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace rcfd {
namespace {

bool isDigit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }

/// Natural order: digit runs compare by value (then by length, so "01" and
/// "1" still have an order), everything else character by character.
bool naturalLess(const std::string &a, const std::string &b) {
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (isDigit(a[i]) && isDigit(b[j])) {
      std::size_t ie = i, je = j;
      while (ie < a.size() && isDigit(a[ie])) ++ie;
      while (je < b.size() && isDigit(b[je])) ++je;
      // Compare the runs without leading zeros: longer is larger, else lexically.
      std::size_t is = i, js = j;
      while (is + 1 < ie && a[is] == '0') ++is;
      while (js + 1 < je && b[js] == '0') ++js;
      if (ie - is != je - js) return ie - is < je - js;
      const int c = a.compare(is, ie - is, b, js, je - js);
      if (c != 0) return c < 0;
      if (ie - i != je - j) return ie - i < je - j;
      i = ie;
      j = je;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i;
      ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

std::string trim(const std::string &s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

} // namespace

std::vector<std::string> globSnapshotFiles(const std::string &pattern) {
  glob_t g{};
  const int rc = ::glob(pattern.c_str(), GLOB_NOSORT, nullptr, &g);
  std::vector<std::string> files;
  if (rc == 0)
    for (std::size_t i = 0; i < g.gl_pathc; ++i) files.emplace_back(g.gl_pathv[i]);
  globfree(&g);
  if (rc != 0 && rc != GLOB_NOMATCH)
    throw std::runtime_error("cannot list the particle snapshots '" + pattern +
                             "' (a directory could not be read).");
  if (files.empty())
    throw std::runtime_error("no particle snapshot file matches '" + pattern + "'.");
  std::sort(files.begin(), files.end(), naturalLess);
  return files;
}

std::vector<std::string> readSnapshotList(const std::string &path) {
  requireRegularFile(path);
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open the snapshot list '" + path + "'.");
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  std::vector<std::string> files;
  for (std::string line; std::getline(in, line);) {
    line = trim(line);
    if (line.empty() || line.front() == '#') continue;
    const std::filesystem::path p(line);
    files.push_back(p.is_absolute() || dir.empty() ? p.string() : (dir / p).string());
  }
  if (files.empty())
    throw std::runtime_error("the snapshot list '" + path + "' names no files.");
  return files;
}

double uniformInterval(const std::vector<double> &times, const std::vector<std::size_t> &sel) {
  if (sel.size() < 2)
    throw std::invalid_argument("uniformInterval: at least two snapshots are needed");
  for (std::size_t s : sel)
    if (s >= times.size())
      throw std::invalid_argument("uniformInterval: snapshot index outside the times");
  const double interval = (times[sel.back()] - times[sel.front()]) / double(sel.size() - 1);
  if (!(interval > 0.0))
    throw std::runtime_error("the snapshot times do not increase (first " +
                             std::to_string(times[sel.front()]) + " s, last " +
                             std::to_string(times[sel.back()]) + " s).");
  for (std::size_t k = 0; k + 1 < sel.size(); ++k) {
    const double dt = times[sel[k + 1]] - times[sel[k]];
    if (std::fabs(dt - interval) > 1e-3 * interval) {
      char text[256];
      std::snprintf(text, sizeof text,
                    "the snapshots are not equally spaced in time: %.9g s from snapshot %zu to "
                    "%zu, %.9g s on average; a database needs one dt_rec.",
                    dt, sel[k], sel[k + 1], interval);
      throw std::runtime_error(text);
    }
  }
  return interval;
}

BoxSpec resolveMesh(const MeshRequest &req, const ParticleSnapshot &first, const AxisMap &axes) {
  Vec3 lo{}, hi{};
  if (!req.lo || !req.hi) {
    if (!first.hasBox)
      throw std::runtime_error("particle snapshot '" + first.source +
                               "' has no BOX BOUNDS, so the mesh needs -mesh_lo and -mesh_hi.");
    // Map both corners; a flipped axis swaps its bounds.
    const Vec3 a = axes.apply(first.boxLo), b = axes.apply(first.boxHi);
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::min(a[d], b[d]);
      hi[d] = std::max(a[d], b[d]);
    }
  }
  if (req.lo) lo = *req.lo;
  if (req.hi) hi = *req.hi;
  BoxSpec box;
  box.origin = lo;
  for (int d = 0; d < 3; ++d) {
    box.length[d] = hi[d] - lo[d];
    if (!(box.length[d] > 0.0) || !std::isfinite(box.length[d])) {
      char text[200];
      std::snprintf(text, sizeof text,
                    "the mesh is empty along %c: from %g to %g m (-mesh_lo, -mesh_hi or the "
                    "snapshot's box).",
                    "xyz"[d], lo[d], hi[d]);
      throw std::runtime_error(text);
    }
  }
  double n[3] = {0, 0, 0};
  const char *option = req.cells ? "-mesh_cells" : "-mesh_cell_size";
  if (req.cells) {
    for (int d = 0; d < 3; ++d) n[d] = (*req.cells)[d];
  } else if (req.cellSize > 0.0) {
    for (int d = 0; d < 3; ++d) n[d] = std::max(1.0, std::round(box.length[d] / req.cellSize));
  } else {
    throw std::runtime_error("the mesh needs -mesh_cells nx,ny,nz or -mesh_cell_size h.");
  }
  const std::string problem = BoxSpec::sizeProblem(n[0], n[1], n[2]);
  if (!problem.empty()) {
    char counts[96];
    std::snprintf(counts, sizeof counts, " (%.0f x %.0f x %.0f) ", n[0], n[1], n[2]);
    throw std::runtime_error(std::string(option) + counts + problem + ".");
  }
  box.nx = static_cast<int>(n[0]);
  box.ny = static_cast<int>(n[1]);
  box.nz = static_cast<int>(n[2]);
  return box;
}

std::vector<double> classMassesPerCell(const ParticleSnapshot &snap, const AxisMap &axes,
                                       const BoxSpec &mesh, const SizeClasses &classes,
                                       ParticleVolume rule, std::size_t *outside) {
  const std::size_t nc = classes.diameter.size();
  std::vector<double> m(static_cast<std::size_t>(mesh.numCells()) * nc, 0.0);
  std::size_t out = 0;
  std::vector<CellShare> shares;
  for (std::size_t p = 0; p < snap.size(); ++p) {
    const int c = classes.classOf(snap.diameter[p]);
    if (c < 0) {
      char text[64];
      std::snprintf(text, sizeof text, "%.4f mm", snap.diameter[p] * 1e3);
      throw std::runtime_error("particle snapshot '" + snap.source + "': particle id " +
                               std::to_string(snap.id[p]) + " has diameter " + text +
                               ", which is within the tolerance of no size class.");
    }
    cellShares(mesh, axes.apply(snap.position[p]), snap.diameter[p], rule, shares);
    if (shares.empty()) ++out;
    for (const CellShare &s : shares)
      m[static_cast<std::size_t>(s.cell) * nc + static_cast<std::size_t>(c)] += snap.mass[p] * s.share;
  }
  if (outside) *outside = out;
  return m;
}

} // namespace rcfd
