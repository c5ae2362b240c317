#include "mesh/partition.hpp"
#include "base/petsc_compat.hpp"


#include <algorithm>
#include <vector>

namespace rcfd {

namespace {

/// Whether every cell of the graph (CSR: degree as row starts) reaches cell 0.
bool connected(const std::vector<idx_t> &start, const std::vector<idx_t> &adjacency) {
  const idx_t n = static_cast<idx_t>(start.size()) - 1;
  if (n <= 0) return true;
  std::vector<char> seen(n, 0);
  std::vector<idx_t> queue(1, 0);
  seen[0] = 1;
  for (std::size_t q = 0; q < queue.size(); ++q)
    for (idx_t e = start[queue[q]]; e < start[queue[q] + 1]; ++e)
      if (!seen[adjacency[e]]) seen[adjacency[e]] = 1, queue.push_back(adjacency[e]);
  return static_cast<idx_t>(queue.size()) == n;
}

} // namespace

// Part of each cell from METIS (k-way, contiguous parts, fixed seed so that
// every run of the same mesh on the same number of ranks is identical).
// With `work` (per cell) METIS balances the work, not the cells: a step
// costs nothing in a cell whose content never moves.  (Balancing the cells as
// a second constraint fails on a bed with its freeboard on top: no cut then
// splits both evenly, and METIS returned 18k/38k cells.)
PetscErrorCode partitionCells(const Mesh &mesh, PetscMPIInt nparts, const std::vector<int> *work,
                              std::vector<idx_t> &part) {
  PetscFunctionBeginUser;
  const idx_t n = mesh.numCells();
  part.assign(n, 0);
  if (nparts == 1) PetscFunctionReturn(PETSC_SUCCESS);
  std::vector<idx_t> degree(n + 1, 0);
  for (int f = 0; f < mesh.numFaces(); ++f) {
    ++degree[mesh.faceOwner[f] + 1];
    ++degree[mesh.faceNeighbour[f] + 1];
  }
  for (idx_t c = 0; c < n; ++c) degree[c + 1] += degree[c];
  std::vector<idx_t> adjacency(degree[n]), fill(degree.begin(), degree.end() - 1);
  for (int f = 0; f < mesh.numFaces(); ++f) {
    adjacency[fill[mesh.faceOwner[f]]++] = mesh.faceNeighbour[f];
    adjacency[fill[mesh.faceNeighbour[f]]++] = mesh.faceOwner[f];
  }
  idx_t ncon = 1, np = nparts, objval = 0;
  std::vector<idx_t> weights;
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  if (work && std::any_of(work->begin(), work->end(), [](int w) { return w > 0; }))
    weights.assign(work->begin(), work->end());
  options[METIS_OPTION_SEED] = 7;
  // Contiguous parts need a connected graph: a vessel's mesh may hold a cut
  // cell that touches the others only along an edge (a cone's rim: no open
  // face), and METIS then refuses to partition at all.
  if (connected(degree, adjacency)) options[METIS_OPTION_CONTIG] = 1;
  idx_t nv = n;
  const int status = METIS_PartGraphKway(&nv, &ncon, degree.data(), adjacency.data(),
                                         weights.empty() ? nullptr : weights.data(),
                                         nullptr, nullptr, &np, nullptr, nullptr, options, &objval,
                                         part.data());
  PetscCheck(status == METIS_OK, PETSC_COMM_SELF, PETSC_ERR_LIB,
             "METIS could not partition the %d-cell mesh into %d parts (status %d)", (int)n,
             (int)nparts, status);
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
