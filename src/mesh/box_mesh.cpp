#include "mesh/box_mesh.hpp"
#include "base/petsc_compat.hpp"

#include "base/collective.hpp"

#include <climits>
#include <cmath>
#include <numeric>
#include <utility>
#include <unistd.h>

namespace rcfd {

int BoxSpec::locate(const Vec3 &p) const {
  const Vec3 h = spacing();
  int idx[3];
  const int n[3] = {nx, ny, nz};
  for (int a = 0; a < 3; ++a) {
    const double s = (p[a] - origin[a]) / h[a];
    if (!(s >= 0.0) || s > n[a]) return -1; // also rejects NaN
    idx[a] = std::min(static_cast<int>(std::floor(s)), n[a] - 1);
  }
  return cellIndex(idx[0], idx[1], idx[2]);
}

std::string BoxSpec::sizeProblem(double nx, double ny, double nz) {
  if (!(nx >= 1 && ny >= 1 && nz >= 1)) return "needs at least one cell along each axis";
  const double cells = nx * ny * nz;
  char text[200];
  if (cells > INT_MAX) {
    std::snprintf(text, sizeof text, "asks for %.3g cells, more than the %d a mesh can number", cells, INT_MAX);
    return text;
  }
  // Centres, volumes and about three faces of owner, neighbour and area per cell.
  constexpr double bytesPerCell = 24 + 8 + 3 * (4 + 4 + 24);
  const double memory = static_cast<double>(sysconf(_SC_PHYS_PAGES)) * sysconf(_SC_PAGE_SIZE);
  if (memory > 0 && cells * bytesPerCell > memory) {
    std::snprintf(text, sizeof text, "asks for %.3g cells, whose mesh alone needs %.3g GB of the %.3g GB of memory here",
                  cells, cells * bytesPerCell / 1e9, memory / 1e9);
    return text;
  }
  return "";
}

namespace {
// The cells, faces and boundary faces of the box into m's (empty) arrays.
void fillBox(const BoxSpec &spec, Mesh &m) {
  const Vec3 h = spec.spacing();
  const int N = spec.numCells();
  m.cellCentre.resize(N);
  m.cellVolume.assign(N, h[0] * h[1] * h[2]);
  for (int k = 0; k < spec.nz; ++k)
    for (int j = 0; j < spec.ny; ++j)
      for (int i = 0; i < spec.nx; ++i)
        m.cellCentre[spec.cellIndex(i, j, k)] = {spec.origin[0] + (i + 0.5) * h[0],
                                                 spec.origin[1] + (j + 0.5) * h[1],
                                                 spec.origin[2] + (k + 0.5) * h[2]};
  const double area[3] = {h[1] * h[2], h[0] * h[2], h[0] * h[1]};
  const int n[3] = {spec.nx, spec.ny, spec.nz};
  // Internal faces in the order of their owner cell, then by direction, so
  // that the face list is deterministic and local in memory.
  for (int k = 0; k < spec.nz; ++k)
    for (int j = 0; j < spec.ny; ++j)
      for (int i = 0; i < spec.nx; ++i) {
        const int ijk[3] = {i, j, k};
        for (int a = 0; a < 3; ++a) {
          if (ijk[a] + 1 >= n[a]) continue;
          int nb[3] = {i, j, k};
          ++nb[a];
          Vec3 s{0.0, 0.0, 0.0};
          s[a] = area[a];
          m.faceOwner.push_back(spec.cellIndex(i, j, k));
          m.faceNeighbour.push_back(spec.cellIndex(nb[0], nb[1], nb[2]));
          m.faceArea.push_back(s);
        }
      }
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side)
      for (int k = 0; k < spec.nz; ++k)
        for (int j = 0; j < spec.ny; ++j)
          for (int i = 0; i < spec.nx; ++i) {
            const int ijk[3] = {i, j, k};
            if (ijk[a] != (side == 0 ? 0 : n[a] - 1)) continue;
            Vec3 s{0.0, 0.0, 0.0};
            s[a] = side == 0 ? -area[a] : area[a];
            m.boundaryOwner.push_back(spec.cellIndex(i, j, k));
            m.boundaryPatch.push_back(2 * a + side);
            m.boundaryArea.push_back(s);
          }
}
} // namespace

PetscErrorCode Mesh::createBox(const BoxSpec &spec, Mesh *mesh) {
  PetscFunctionBeginUser;
  const std::string problem = BoxSpec::sizeProblem(spec.nx, spec.ny, spec.nz);
  PetscCheck(problem.empty(), PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "a box mesh of %d x %d x %d cells %s",
             spec.nx, spec.ny, spec.nz, problem.c_str());
  // Built aside and moved in, so that *mesh keeps its old value on an error
  // (a std::bad_alloc of a mesh that passed the memory check included).
  Mesh m;
  PetscCallCXX(fillBox(spec, m));
  m.hasBox = true;
  m.spec = spec;
  *mesh = std::move(m);
  PetscFunctionReturn(PETSC_SUCCESS);
}

Mesh boxMesh(const BoxSpec &spec) {
  Mesh mesh;
  throwOnError([&] { return Mesh::createBox(spec, &mesh); });
  return mesh;
}

double Mesh::totalVolume() const {
  return std::accumulate(cellVolume.begin(), cellVolume.end(), 0.0);
}

} // namespace rcfd
