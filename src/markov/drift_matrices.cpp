#include "markov/drift_matrices.hpp"
#include "base/petsc_compat.hpp"

#include <algorithm>
#include <cmath>

namespace rcfd {

namespace {

// The cells within `depth` faces of `from` (itself included), breadth first
// over `graph`; `stamp` (one entry per cell, never equal to `mark` on entry)
// marks the cells seen.
void cellsWithin(const std::vector<std::vector<int>> &graph, int from, int depth, std::vector<int> &stamp, int mark,
                 std::vector<int> *found) {
  found->assign(1, from);
  stamp[static_cast<size_t>(from)] = mark;
  size_t begin = 0;
  for (int d = 0; d < depth; ++d) {
    const size_t end = found->size();
    for (size_t q = begin; q < end; ++q)
      for (int nb : graph[static_cast<size_t>((*found)[q])])
        if (stamp[static_cast<size_t>(nb)] != mark) {
          stamp[static_cast<size_t>(nb)] = mark;
          found->push_back(nb);
        }
    begin = end;
  }
}

} // namespace

PetscErrorCode DriftMatrices::colour(int r) {
  const Database &db = chain_->database();
  const Mesh &mesh = db.mesh();
  const Layout &layout = db.layout();
  const int cells = mesh.numCells();
  PetscFunctionBeginUser;
  if (vertical_.empty()) {
    // Every face with any component along gravity: the drift's faces (a
    // share above 1e-9 of the area) are among them, which is all the
    // colouring needs.
    const Vec3 g = db.metadata().gravity;
    vertical_.assign(static_cast<size_t>(cells), {});
    for (int f = 0; f < mesh.numFaces(); ++f) {
      const Vec3 &a = mesh.faceArea[static_cast<size_t>(f)];
      if (a[0] * g[0] + a[1] * g[1] + a[2] * g[2] == 0.0) continue;
      const int o = mesh.faceOwner[static_cast<size_t>(f)], nb = mesh.faceNeighbour[static_cast<size_t>(f)];
      vertical_[static_cast<size_t>(o)].push_back(nb);
      vertical_[static_cast<size_t>(nb)].push_back(o);
    }
  }
  reach_ = r;
  // Greedy: each cell takes the smallest colour none of the cells within 2r
  // faces has taken (in a column of cells, the layer index modulo 2r + 1).
  // The same on every rank: the mesh is.
  std::vector<int> stamp(static_cast<size_t>(cells), -1), near, used;
  colour_.assign(static_cast<size_t>(cells), -1);
  colours_ = 0;
  for (int c = 0; c < cells; ++c) {
    cellsWithin(vertical_, c, 2 * r, stamp, c, &near);
    used.assign(near.size() + 1, 0);
    for (int q : near) {
      const int k = colour_[static_cast<size_t>(q)];
      if (k >= 0 && k < static_cast<int>(used.size())) used[static_cast<size_t>(k)] = 1;
    }
    const int k = static_cast<int>(std::find(used.begin(), used.end(), 0) - used.begin());
    colour_[static_cast<size_t>(c)] = k;
    colours_ = std::max(colours_, k + 1);
  }
  // Each chain cell's ball of radius r, as chain indices.
  const std::vector<PetscInt> &rows = chain_->chainRowsAll();
  std::vector<PetscInt> chainOf(static_cast<size_t>(cells), -1);
  for (size_t p = 0; p < rows.size(); ++p) chainOf[static_cast<size_t>(layout.naturalCell(rows[p]))] = static_cast<PetscInt>(p);
  std::fill(stamp.begin(), stamp.end(), -1);
  ballStart_.assign(1, 0);
  ballCell_.clear();
  ballColour_.clear();
  const std::vector<PetscInt> &local = chain_->chainCells();
  const PetscInt n = static_cast<PetscInt>(local.size());
  first_ = static_cast<PetscInt>(std::lower_bound(rows.begin(), rows.end(), layout.rowStart()) - rows.begin());
  localColour_.assign(local.size(), 0);
  diagCount_.assign(local.size(), 0);
  offCount_.assign(local.size(), 0);
  for (size_t c = 0; c < local.size(); ++c) {
    const int m = static_cast<int>(layout.naturalCell(layout.rowStart() + local[c]));
    localColour_[c] = colour_[static_cast<size_t>(m)];
    cellsWithin(vertical_, m, r, stamp, static_cast<int>(c), &near);
    for (int q : near) {
      const PetscInt col = chainOf[static_cast<size_t>(q)];
      if (col < 0) continue;
      ballCell_.push_back(col);
      ballColour_.push_back(colour_[static_cast<size_t>(q)]);
      ++(col >= first_ && col < first_ + n ? diagCount_ : offCount_)[c];
    }
    ballStart_.push_back(static_cast<PetscInt>(ballCell_.size()));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

// D_k by colours, 16 at a time: a unit amount in each cell of the colour,
// then the drift; what a cell holds came from the one cell of that colour in
// its ball.
PetscErrorCode DriftMatrices::probe(int k, ClassDrift &drift, Mat D, bool *explained) {
  const MPI_Comm comm = chain_->database().layout().comm();
  const PetscInt n = chain_->numChainCells();
  constexpr PetscInt W = kWidth;
  PetscFunctionBeginUser;
  OwnedVec x;
  PetscCall(chain_->blockVector(W, x.put()));
  bool unexplained = false;
  for (int group = 0; group * W < colours_; ++group) {
    PetscScalar *px;
    PetscCall(VecGetArrayWrite(x, &px));
    for (PetscInt c = 0; c < n; ++c)
      for (PetscInt s = 0; s < W; ++s) px[c * W + s] = localColour_[static_cast<size_t>(c)] == group * W + s ? 1.0 : 0.0;
    PetscCall(VecRestoreArrayWrite(x, &px));
    PetscCall(drift.apply(k, x, W));
    const PetscScalar *py;
    PetscCall(VecGetArrayRead(x, &py));
    for (PetscInt c = 0; c < n; ++c)
      for (PetscInt s = 0; s < W; ++s) {
        const PetscScalar v = py[c * W + s];
        if (v == 0.0) continue;
        const int want = group * static_cast<int>(W) + static_cast<int>(s);
        PetscInt from = -1;
        for (PetscInt b = ballStart_[static_cast<size_t>(c)]; b < ballStart_[static_cast<size_t>(c) + 1]; ++b)
          if (ballColour_[static_cast<size_t>(b)] == want) from = ballCell_[static_cast<size_t>(b)];
        if (from < 0) {
          unexplained = true;
          continue;
        }
        PetscCall(MatSetValue(D, first_ + c, from, v, INSERT_VALUES));
      }
    PetscCall(VecRestoreArrayRead(x, &py));
  }
  PetscCall(MatAssemblyBegin(D, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(D, MAT_FINAL_ASSEMBLY));
  int bad = unexplained;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &bad, 1, MPI_INT, MPI_MAX, comm));
  *explained = bad == 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode DriftMatrices::setUp(const FrameChain &chain, ClassDrift &drift) {
  const MPI_Comm comm = chain.database().layout().comm();
  const PetscInt n = chain.numChainCells(), N = chain.numChainCellsGlobal();
  PetscFunctionBeginUser;
  PetscCheck(drift.sameEveryPeriod(), comm, PETSC_ERR_ARG_WRONGSTATE,
             "A drift applied every few steps (-drift_every) is no matrix per frame");
  chain_ = &chain;
  d_.clear();
  blocks_.clear();
  work_.clear();
  PetscCall(colour(std::max(1, drift.mostSubsteps())));
  for (int k = 0; k < chain.numFrames();) {
    OwnedMat D;
    PetscCall(MatCreateAIJ(comm, n, n, N, N, 0, diagCount_.data(), 0, offCount_.data(), D.put()));
    bool explained = false;
    PetscCall(probe(k, drift, D, &explained));
    int most = drift.mostSubsteps();
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &most, 1, MPI_INT, MPI_MAX, comm));
    if (most > reach_) { // this frame took more sub-steps than the colouring allows: again, further apart
      PetscCall(colour(most));
      continue;
    }
    // Within its sub-steps every share has its cell; one without would be a
    // drift that moves further than it says (a change in the operator).
    PetscCheck(explained, comm, PETSC_ERR_PLIB,
               "The class drift of frame %d moved solid further than its %d sub-steps", k, reach_);
    d_.push_back(std::move(D));
    ++k;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode DriftMatrices::apply(long long n, Vec x, PetscInt width) {
  PetscFunctionBeginUser;
  std::vector<OwnedMat> &blocks = blocks_[width];
  if (blocks.empty())
    for (const OwnedMat &D : d_) {
      OwnedMat m;
      PetscCall(MatCreateMAIJ(D, width, m.put()));
      blocks.push_back(std::move(m));
    }
  OwnedVec &y = work_[width];
  if (!y) PetscCall(VecDuplicate(x, y.put()));
  PetscCall(MatMult(blocks[static_cast<size_t>(n % static_cast<long long>(blocks.size()))], x, y));
  PetscCall(VecCopy(y, x));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
