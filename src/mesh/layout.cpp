#include "rcfd/layout.hpp"
#include "base/petsc_compat.hpp"

#include "mesh/partition.hpp"

#include <algorithm>

namespace rcfd {

PetscErrorCode Layout::create(MPI_Comm comm, const Mesh &mesh, Layout *layout,
                              const std::vector<int> *work) {
  PetscMPIInt size, rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  const PetscInt n = mesh.numCells();
  PetscCheck(n >= size, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "The mesh has %" PetscInt_FMT " cells, fewer than the %d MPI ranks", n, size);
  // Rank 0 partitions and broadcasts, so that every rank uses the same parts
  // even if METIS were not bitwise reproducible across processes.
  std::vector<idx_t> part(n, 0);
  PetscErrorCode status = PETSC_SUCCESS;
  PetscCheck(!work || work->size() == static_cast<size_t>(n), comm, PETSC_ERR_ARG_SIZ,
             "The work per cell has %zu entries for %" PetscInt_FMT " cells", work ? work->size() : 0, n);
  if (rank == 0) status = partitionCells(mesh, size, work, part);
  PetscCallMPI(MPI_Bcast(&status, 1, MPI_INT, 0, comm));
  PetscCheck(status == PETSC_SUCCESS, comm, PETSC_ERR_LIB, "METIS partitioning failed");
  static_assert(sizeof(idx_t) == 4 || sizeof(idx_t) == 8);
  PetscCallMPI(MPI_Bcast(part.data(), (int)n, sizeof(idx_t) == 4 ? MPI_INT32_T : MPI_INT64_T, 0, comm));

  Layout &L = *layout;
  L.comm_ = comm;
  L.toPetsc_.assign(n, -1);
  L.toNatural_.assign(n, -1);
  std::vector<PetscInt> start(size + 1, 0);
  for (PetscInt c = 0; c < n; ++c) ++start[part[c] + 1];
  if (!std::all_of(start.begin() + 1, start.end(), [](PetscInt k) { return k > 0; })) {
    // METIS may leave a part empty on tiny meshes; equal blocks of the
    // natural order are then a fine partition.
    std::fill(start.begin(), start.end(), 0);
    for (PetscInt c = 0; c < n; ++c) {
      part[c] = static_cast<idx_t>((c * size) / n);
      ++start[part[c] + 1];
    }
  }
  for (int p = 0; p < size; ++p) start[p + 1] += start[p];
  std::vector<PetscInt> next(start.begin(), start.end() - 1);
  for (PetscInt c = 0; c < n; ++c) { // ascending natural order within each part
    const PetscInt row = next[part[c]]++;
    L.toPetsc_[c] = row;
    L.toNatural_[row] = c;
  }
  L.starts_.assign(start.begin(), start.end());
  L.rstart = start[rank];
  L.rend = start[rank + 1];
  L.owned.assign(L.toNatural_.begin() + L.rstart, L.toNatural_.begin() + L.rend);
  L.cutFaces = 0;
  for (int f = 0; f < mesh.numFaces(); ++f)
    L.cutFaces += part[mesh.faceOwner[f]] != part[mesh.faceNeighbour[f]];

  PetscBool view = PETSC_FALSE;
  PetscCall(PetscOptionsGetBool(nullptr, nullptr, "-partition_view", &view, nullptr));
  if (view) {
    PetscCall(PetscPrintf(comm, "Partition: %" PetscInt_FMT " cells on %d ranks, %" PetscInt_FMT
                                " faces cut\n", n, size, L.cutFaces));
    double share = 0.0, total = 0.0;
    if (work)
      for (PetscInt c = 0; c < n; ++c) total += (*work)[c], share += part[c] == rank ? (*work)[c] : 0;
    PetscCall(PetscSynchronizedPrintf(comm, "  rank %d: rows [%" PetscInt_FMT ", %" PetscInt_FMT "), %.1f %% of the work\n",
                                      rank, L.rstart, L.rend, total > 0 ? 100.0 * share / total : 100.0 * L.numLocal() / n));
    PetscCall(PetscSynchronizedFlush(comm, PETSC_STDOUT));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::vector<std::pair<PetscInt, PetscInt>> Layout::ownedNaturalRuns() const {
  std::vector<std::pair<PetscInt, PetscInt>> runs;
  for (PetscInt c : owned) {
    if (!runs.empty() && runs.back().second == c) ++runs.back().second;
    else runs.emplace_back(c, c + 1);
  }
  return runs;
}

PetscErrorCode Layout::naturalScatter(PetscInt bs, Vec petscOrdered, Vec *natural,
                                      VecScatter *scatter) const {
  PetscFunctionBeginUser;
  PetscInt localCells = PETSC_DECIDE, totalCells = numCells();
  PetscCall(PetscSplitOwnership(comm_, &localCells, &totalCells)); // whole cells per rank
  PetscCall(VecCreateMPI(comm_, localCells * bs, totalCells * bs, natural));
  PetscCall(VecSetBlockSize(*natural, bs));
  std::vector<PetscInt> rows(owned.begin(), owned.end()); // natural block index of each local row
  OwnedIS from, to;
  PetscCall(ISCreateStride(comm_, numLocal() * bs, rstart * bs, 1, from.put()));
  PetscCall(ISCreateBlock(comm_, bs, numLocal(), rows.data(), PETSC_COPY_VALUES, to.put()));
  PetscCall(VecScatterCreate(petscOrdered, from, *natural, to, scatter));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Layout::rowsScatter(PetscInt bs, PetscInt n, const PetscInt *rows, Vec *local,
                                   VecScatter *scatter) const {
  OwnedVec parallel;
  OwnedIS from, to;
  PetscFunctionBeginUser;
  PetscCall(VecCreateMPI(comm_, numLocal() * bs, numCells() * bs, parallel.put()));
  PetscCall(VecSetBlockSize(parallel, bs));
  PetscCall(ISCreateBlock(PETSC_COMM_SELF, bs, n, rows, PETSC_COPY_VALUES, from.put()));
  PetscCall(ISCreateStride(PETSC_COMM_SELF, n * bs, 0, 1, to.put()));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, n * bs, local));
  PetscCall(VecScatterCreate(parallel, from, *local, to, scatter));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Layout::gatherToAll(PetscInt bs, Vec petscOrdered, std::vector<double> *out) const {
  OwnedVec natural, all;
  OwnedScatter toNatural, toAll;
  const PetscScalar *a;
  PetscInt n;
  PetscFunctionBeginUser;
  PetscCall(naturalScatter(bs, petscOrdered, natural.put(), toNatural.put()));
  PetscCall(VecScatterBegin(toNatural, petscOrdered, natural, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(toNatural, petscOrdered, natural, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterCreateToAll(natural, toAll.put(), all.put()));
  PetscCall(VecScatterBegin(toAll, natural, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(toAll, natural, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGetSize(all, &n));
  PetscCall(VecGetArrayRead(all, &a));
  out->assign(a, a + n);
  PetscCall(VecRestoreArrayRead(all, &a));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode OccupiedGather::gather(const Layout &layout, PetscInt bs, Vec petscOrdered, PetscInt localEnd) {
  PetscMPIInt size;
  const PetscScalar *a;
  PetscFunctionBeginUser;
  const MPI_Comm comm = layout.comm();
  const PetscInt n = layout.numCells();
  PetscCallMPI(MPI_Comm_size(comm, &size));
  if (blockSize != bs || starts != layout.rowStarts() || petscRowOf != layout.petscRows()) {
    starts = layout.rowStarts();
    petscRowOf = layout.petscRows();
    owner.resize(n);
    for (PetscInt c = 0; c < n; ++c) // the last rank whose first row is at or below the cell's
      owner[c] = static_cast<int>(std::upper_bound(starts.begin(), starts.begin() + size, layout.petscRow(c)) -
                                  starts.begin() - 1);
    rows.assign(static_cast<std::size_t>(n) * bs, 0.0);
    natural.assign(static_cast<std::size_t>(n) * bs, 0.0);
    counts.resize(size);
    displs.resize(size);
    blockSize = bs, naturalEnd = 0;
  }
  std::vector<PetscInt> ends(size);
  PetscCallMPI(MPI_Allgather(&localEnd, 1, MPIU_INT, ends.data(), 1, MPIU_INT, comm));
  // A rank's rows ascend in natural order: its rows below its bound are its
  // cells below the natural index one past the last of them.
  std::vector<PetscInt> naturalBound(size, 0);
  PetscInt end = 0;
  for (PetscMPIInt p = 0; p < size; ++p) {
    counts[p] = static_cast<PetscMPIInt>(ends[p] * bs);
    displs[p] = static_cast<PetscMPIInt>(starts[p] * bs);
    if (ends[p] > 0) naturalBound[p] = layout.naturalCell(starts[p] + ends[p] - 1) + 1;
    end = std::max(end, naturalBound[p]);
  }
  PetscCall(VecGetArrayRead(petscOrdered, &a));
  PetscCallMPI(MPI_Allgatherv(a, static_cast<PetscMPIInt>(localEnd * bs), MPIU_SCALAR, rows.data(), counts.data(),
                              displs.data(), MPIU_SCALAR, comm));
  PetscCall(VecRestoreArrayRead(petscOrdered, &a));
  for (PetscInt c = 0; c < end; ++c) {
    double *to = &natural[static_cast<std::size_t>(c) * bs];
    if (c < naturalBound[owner[c]]) std::copy_n(&rows[static_cast<std::size_t>(layout.petscRow(c)) * bs], bs, to);
    else std::fill_n(to, bs, 0.0);
  }
  if (end < naturalEnd) // what the last gather wrote above this one's end
    std::fill(natural.begin() + end * bs, natural.begin() + naturalEnd * bs, 0.0);
  naturalEnd = end;
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
