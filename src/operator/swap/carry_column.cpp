// The `column` carry kind (default): monotone transport by height in every
// vertical column, and the columns' gains and losses of solid exchanged at
// their tops.
#include "operator/swap/carry_kinds.hpp"
#include "base/petsc_compat.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace rcfd {
namespace {

/// The vertical columns of a box mesh whose gravity is along one of its axes:
/// the natural cell indices of each column, bottom to top.  On a vessel cut
/// from a box a column holds the cells of its box column that are inside (a
/// column through a tube passes it by), and columns with none are left out.
struct Columns {
  int count = 0, levels = 0; // levels: of the tallest column
  std::vector<PetscInt> cells; // column after column: cells[start[col] + lev]
  std::vector<size_t> start;   // count + 1 offsets
  int levelsOf(int col) const { return static_cast<int>(start[col + 1] - start[col]); }

  /// Why the mesh cannot be cut into columns, or "" when it can.
  static std::string problem(const Mesh &mesh, const Vec3 &g) {
    if (!mesh.onBoxLattice()) return "a box mesh";
    const double gn = std::hypot(g[0], g[1], g[2]);
    int along = 0;
    for (int a = 0; a < 3; ++a) along += std::fabs(g[a]) > 1e-12 * gn;
    return gn > 0.0 && along == 1 ? "" : "gravity along one of the mesh's axes";
  }

  /// The whole bed as one column: every cell, by height (then by number).
  static Columns bed(const Mesh &mesh, const Vec3 &g) {
    Columns c;
    c.count = 1;
    c.levels = mesh.numCells();
    c.cells.resize(c.levels);
    std::vector<double> h(c.levels);
    for (int k = 0; k < c.levels; ++k) {
      const Vec3 &x = mesh.cellCentre[k];
      h[k] = -(g[0] * x[0] + g[1] * x[1] + g[2] * x[2]);
      c.cells[k] = k;
    }
    c.start = {0, static_cast<size_t>(c.levels)};
    std::stable_sort(c.cells.begin(), c.cells.end(), [&](PetscInt a, PetscInt b) { return h[a] < h[b]; });
    return c;
  }

  static Columns of(const Mesh &mesh, const Vec3 &g) {
    const BoxSpec &b = mesh.boxSpec();
    const int axis = std::fabs(g[0]) > 0.0 ? 0 : std::fabs(g[1]) > 0.0 ? 1 : 2;
    const bool upIsPlus = g[axis] < 0.0;
    const int n[3] = {b.nx, b.ny, b.nz};
    const int p = (axis + 1) % 3, q = (axis + 2) % 3; // the two horizontal axes
    Columns c;
    c.cells.reserve(mesh.numCells());
    c.start.push_back(0);
    for (int iq = 0; iq < n[q]; ++iq)
      for (int ip = 0; ip < n[p]; ++ip) {
        for (int l = 0; l < n[axis]; ++l) {
          int ijk[3];
          ijk[p] = ip, ijk[q] = iq, ijk[axis] = upIsPlus ? l : n[axis] - 1 - l;
          const int box = b.cellIndex(ijk[0], ijk[1], ijk[2]), cell = mesh.cellOfBoxCell(box);
          // A merged cell (-vessel_merge_below) stands once, in the column of its own box cell.
          if (cell >= 0 && mesh.boxCell(cell) == box) c.cells.push_back(cell);
        }
        if (c.cells.size() == c.start.back()) continue; // wholly outside the vessel
        c.levels = std::max(c.levels, static_cast<int>(c.cells.size() - c.start.back()));
        c.start.push_back(c.cells.size());
      }
    c.count = static_cast<int>(c.start.size()) - 1;
    return c;
  }
};

class ColumnCarry : public CarryKind {
public:
  std::string type() const override { return "column"; }
  PetscErrorCode setFromOptions(MPI_Comm comm) override {
    PetscBool set = PETSC_FALSE;
    PetscFunctionBeginUser;
    PetscOptionsBegin(comm, prefix.c_str(), "Column carry (-carry_type column)", "rcfd");
    PetscCall(PetscOptionsBool("-column_bed", "One column of the whole bed, cells by height", "", wholeBed,
                               &wholeBed, &set));
    PetscOptionsEnd();
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscErrorCode apply(const CarryContext &ctx, const StepInfo &step, FractionState &state) override;
  PetscErrorCode view(PetscViewer viewer) const override;
  bool carriesScalars() const override { return true; }

private:
  PetscErrorCode carry(const CarryContext &ctx, Vec targetAlpha, FractionState &state);
  PetscBool wholeBed = PETSC_FALSE;
  const Database *columnsOf = nullptr;
  Columns columns;
  std::vector<PetscInt> lowestAbove; // per column and level: the smallest natural cell at or above the level
  OccupiedGather gatherMasses, gatherAlpha, gatherAmounts;
  // Natural order, zero at and above `valid` (the last jump's bound), kept
  // between jumps: a jump writes only the cells below its bound.
  std::vector<double> bulk, target, out, content;
  PetscInt valid = 0;
  long jumps = 0;
  double movedAcross = 0.0, movedAcrossMax = 0.0; // share of the bed's mass moved between columns
  double seconds = 0.0;                            // wall time in the carry, this rank
};

PetscErrorCode ColumnCarry::apply(const CarryContext &ctx, const StepInfo &step, FractionState &state) {
  PetscFunctionBeginUser;
  if (step.jump) {
    const double start = MPI_Wtime();
    PetscCall(carry(ctx, ctx.db.alphaS(step.nextFrame), state));
    seconds += MPI_Wtime() - start;
  }
  jumps += step.jump;
  PetscFunctionReturn(PETSC_SUCCESS);
}

// A column's mass, bottom to top, as pieces of composition: a piece of bulk
// mass M holds the fraction masses m_i (sum M).
struct Piece {
  double mass;
  const double *fractions;
};

// Hands the pieces, in order, to the cells of `target` (bulk masses, bottom
// to top) by cumulative mass: the monotone (optimal 1-D) transport.  The
// target is scaled to the pieces' total, so the column's mass is kept; every
// overlap is >= 0, so no mass turns negative.
void transport(const std::vector<Piece> &pieces, const PetscInt *cells, const double *target, int levels,
               int nf, std::vector<double> &out) {
  double have = 0.0, want = 0.0;
  for (const Piece &p : pieces) have += p.mass;
  for (int l = 0; l < levels; ++l) want += target[l];
  for (int l = 0; l < levels; ++l) std::fill_n(&out[cells[l] * nf], nf, 0.0);
  if (!(have > 0.0) || !(want > 0.0)) return;
  const double scale = have / want;
  int top = levels - 1; // the highest cell with solid takes what round-off leaves of the column
  while (top > 0 && !(target[top] > 0.0)) --top;
  size_t k = 0;
  double pieceLeft = pieces.empty() ? 0.0 : pieces[0].mass;
  for (int l = 0; l <= top && k < pieces.size(); ++l) {
    const bool lastCell = l == top;
    double cellLeft = target[l] * scale;
    double *m = &out[cells[l] * nf];
    while ((cellLeft > 0.0 || lastCell) && k < pieces.size()) {
      const double o = lastCell ? pieceLeft : std::min(pieceLeft, cellLeft);
      for (int i = 0; i < nf; ++i) m[i] += o * (pieces[k].fractions[i] / pieces[k].mass);
      pieceLeft -= o;
      cellLeft -= o;
      if (pieceLeft <= 0.0 || lastCell) {
        if (++k < pieces.size()) pieceLeft = pieces[k].mass;
      }
    }
  }
}

// One past the last own row (local index) whose value is not zero.
PetscErrorCode nonzeroEnd(Vec v, PetscInt *end) {
  const PetscScalar *a;
  PetscInt n;
  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(v, &n));
  PetscCall(VecGetArrayRead(v, &a));
  while (n > 0 && a[n - 1] == 0.0) --n;
  PetscCall(VecRestoreArrayRead(v, &a));
  *end = n;
  PetscFunctionReturn(PETSC_SUCCESS);
}

// Every rank gathers the state and the target bulk in natural order and
// computes the whole carry in that order, so 1 and n ranks give the same bits;
// then keeps its own cells.  Only the occupied cells travel and are computed:
// the state's (FractionState::occupiedEnd) and the next frame's; the cells
// above both, in natural order, hold nothing before and after and add
// nothing to any sum (the same bits as gathering and computing all).
//  1. Target bulk M*_c = rho alpha_c V_c, scaled to the state's total (one
//     factor, 1 when the frame holds the bed's mass).
//  2. A column whose bulk already matches (sum |M - M*| <= 1e-13 of its mass)
//     is left as it is.
//  3. Every other column keeps its composition as a function of the mass
//     below (from the bottom) up to the smaller of its old and new total; a
//     column that loses solid gives the slice above its new total (its top)
//     to a pool, and a column that gains takes from the pool in proportion
//     to its gain: solid crosses between columns only at their tops, where a
//     bubbling bed throws it, and only as much as the two frames' columns differ.
//  4. Each column's pieces go to its cells by cumulative mass (transport()).
//  5. One factor per fraction restores its total to round-off.
// With scalars each cell's content is its nf masses followed by its ns x nf
// amounts (w numbers), and every share of a cell's content takes its amounts
// in the same share as its masses; the bulk is the masses' sum alone.
PetscErrorCode ColumnCarry::carry(const CarryContext &ctx, Vec targetAlpha, FractionState &state) {
  PetscFunctionBeginUser;
  const Database &db = ctx.db;
  const Layout &layout = db.layout();
  const int nf = ctx.numFractions;
  const std::vector<double> &volume = db.mesh().cellVolume;
  const size_t n = volume.size();
  if (columnsOf != &db) {
    const std::string missing = Columns::problem(db.mesh(), db.metadata().gravity);
    PetscCheck(missing.empty(), layout.comm(), PETSC_ERR_USER_INPUT,
               "-carry_type column needs %s; database '%s' does not have it (choose -carry_type remap)",
               missing.c_str(), db.path().c_str());
    columns = wholeBed ? Columns::bed(db.mesh(), db.metadata().gravity) : Columns::of(db.mesh(), db.metadata().gravity);
    // Every cell in one column once (a cell listed twice would have its mass carried twice).
    PetscCheck(columns.cells.size() == n, PETSC_COMM_SELF, PETSC_ERR_PLIB,
               "column carry: the columns list %zu cells of database '%s''s %zu", columns.cells.size(),
               db.path().c_str(), n);
    lowestAbove.resize(columns.cells.size());
    for (int col = 0; col < columns.count; ++col) {
      const int L = columns.levelsOf(col);
      for (int l = L - 1; l >= 0; --l) {
        const size_t k = columns.start[col] + l;
        lowestAbove[k] = l == L - 1 ? columns.cells[k] : std::min(columns.cells[k], lowestAbove[k + 1]);
      }
    }
    bulk.assign(n, 0.0);
    target.assign(n, 0.0);
    out.clear();
    valid = 0;
    columnsOf = &db;
  }
  PetscInt massEnd = 0, alphaEnd = 0;
  PetscCall(state.occupiedEnd(&massEnd));
  PetscCall(nonzeroEnd(targetAlpha, &alphaEnd));
  PetscCall(gatherMasses.gather(layout, nf, state.masses(), massEnd));
  PetscCall(gatherAlpha.gather(layout, 1, targetAlpha, alphaEnd));
  const std::vector<double> &alpha = gatherAlpha.values();
  const size_t end = static_cast<size_t>(std::max(gatherMasses.end(), gatherAlpha.end()));
  const int na = nf * state.numScalars(), w = nf + na; // the numbers of a cell's content
  if (out.size() != n * w) out.assign(n * w, 0.0), valid = 0;
  if (na > 0) { // masses and amounts side by side, cell by cell (amounts are zero where masses are)
    PetscCall(gatherAmounts.gather(layout, na, state.amounts(), massEnd));
    const std::vector<double> &mm = gatherMasses.values(), &a = gatherAmounts.values();
    content.resize(end * w);
    for (size_t c = 0; c < end; ++c) {
      std::copy_n(&mm[c * nf], nf, &content[c * w]);
      std::copy_n(&a[c * na], na, &content[c * w + nf]);
    }
  }
  const std::vector<double> &m = na > 0 ? content : gatherMasses.values();
  if (end < static_cast<size_t>(valid)) { // what the last jump wrote above this one's bound
    std::fill(bulk.begin() + end, bulk.begin() + valid, 0.0);
    std::fill(target.begin() + end, target.begin() + valid, 0.0);
    std::fill(out.begin() + end * w, out.begin() + valid * w, 0.0);
  }
  valid = static_cast<PetscInt>(end);
  std::vector<double> before(w, 0.0);
  double inventory = 0.0, targetTotal = 0.0;
  for (size_t c = 0; c < end; ++c) {
    bulk[c] = 0.0;
    for (int i = 0; i < nf; ++i) bulk[c] += m[c * w + i];
    for (int i = 0; i < w; ++i) before[i] += m[c * w + i];
    target[c] = ctx.solidDensity * alpha[c] * volume[c];
    inventory += bulk[c];
    targetTotal += target[c];
  }
  PetscCheck(targetTotal > 0.0 || !(inventory > 0.0), layout.comm(), PETSC_ERR_USER_INPUT,
             "The carry cannot move the bed onto a frame of database '%s' that holds no solid", db.path().c_str());
  if (targetTotal > 0.0 && targetTotal != inventory)
    for (size_t c = 0; c < end; ++c) target[c] *= inventory / targetTotal;

  // The levels of each column below which all its cells below `end` lie.
  const int L = columns.levels;
  std::vector<int> height(columns.count);
  for (int col = 0; col < columns.count; ++col) {
    const PetscInt *above = &lowestAbove[columns.start[col]];
    height[col] = static_cast<int>(
        std::partition_point(above, above + columns.levelsOf(col),
                             [&](PetscInt c) { return static_cast<size_t>(c) < end; }) - above);
  }
  std::copy(m.begin(), m.begin() + end * w, out.begin());
  std::vector<double> colTarget(L), pool(w, 0.0), pieceStore(static_cast<size_t>(L + 1) * w);
  std::vector<double> oldTotal(columns.count, 0.0), newTotal(columns.count, 0.0);
  std::vector<char> moves(columns.count, 0);
  double deficit = 0.0;
  for (int col = 0; col < columns.count; ++col) {
    const PetscInt *cells = &columns.cells[columns.start[col]];
    const int H = height[col];
    double off = 0.0;
    for (int l = 0; l < H; ++l) {
      oldTotal[col] += bulk[cells[l]];
      newTotal[col] += target[cells[l]];
      off += std::fabs(bulk[cells[l]] - target[cells[l]]);
    }
    moves[col] = off > 1e-13 * oldTotal[col] || (oldTotal[col] == 0.0 && newTotal[col] > 0.0);
    if (!moves[col]) continue;
    if (newTotal[col] > oldTotal[col]) deficit += newTotal[col] - oldTotal[col];
    else { // the slice above the new total goes to the pool
      double below = 0.0;
      for (int l = 0; l < H; ++l) {
        const double M = bulk[cells[l]];
        const double above = std::min(M, std::max(0.0, below + M - newTotal[col]));
        if (above > 0.0)
          for (int i = 0; i < w; ++i) pool[i] += above * (m[cells[l] * w + i] / M);
        below += M;
      }
    }
  }
  double poolMass = 0.0;
  for (int i = 0; i < nf; ++i) poolMass += pool[i];

  std::vector<Piece> pieces;
  for (int col = 0; col < columns.count; ++col) {
    if (!moves[col]) continue;
    const PetscInt *cells = &columns.cells[columns.start[col]];
    const int H = height[col];
    pieces.clear();
    const double keep = std::min(oldTotal[col], newTotal[col]);
    double below = 0.0;
    for (int l = 0; l < H && below < keep; ++l) {
      const double M = bulk[cells[l]];
      if (!(M > 0.0)) continue;
      const double part = std::min(M, keep - below);
      double *f = &pieceStore[static_cast<size_t>(l) * w];
      for (int i = 0; i < w; ++i) f[i] = part == M ? m[cells[l] * w + i] : part * (m[cells[l] * w + i] / M);
      pieces.push_back({part, f});
      below += M;
    }
    if (newTotal[col] > oldTotal[col] && deficit > 0.0) { // its share of the pool, on top
      const double share = (newTotal[col] - oldTotal[col]) / deficit;
      double *f = &pieceStore[static_cast<size_t>(L) * w];
      double M = 0.0;
      for (int i = 0; i < nf; ++i) f[i] = share * pool[i], M += f[i];
      for (int i = nf; i < w; ++i) f[i] = share * pool[i];
      if (M > 0.0) pieces.push_back({M, f});
    }
    for (int l = 0; l < H; ++l) colTarget[l] = target[cells[l]];
    transport(pieces, cells, colTarget.data(), H, w, out);
  }

  std::vector<double> after(w, 0.0);
  for (size_t c = 0; c < end; ++c)
    for (int i = 0; i < w; ++i) after[i] += out[c * w + i];
  std::vector<double> factor(w, 1.0);
  for (int i = 0; i < w; ++i) factor[i] = after[i] > 0.0 ? before[i] / after[i] : 1.0;
  // The own cells below the bound; those above held nothing and hold nothing.
  const std::vector<PetscInt> &owned = layout.ownedNatural(); // ascending
  const PetscInt ownEnd = static_cast<PetscInt>(
      std::lower_bound(owned.begin(), owned.end(), static_cast<PetscInt>(end)) - owned.begin());
  PetscScalar *own;
  PetscCall(VecGetArray(state.masses(), &own));
  for (PetscInt r = 0; r < ownEnd; ++r)
    for (int i = 0; i < nf; ++i) own[r * nf + i] = out[owned[r] * w + i] * factor[i];
  PetscCall(VecRestoreArray(state.masses(), &own));
  if (na > 0) { // own cells above the bound hold no mass, so no amount either
    PetscCall(VecGetArray(state.amounts(), &own));
    for (PetscInt r = 0; r < ownEnd; ++r)
      for (int k = 0; k < na; ++k) own[r * na + k] = out[owned[r] * w + nf + k] * factor[nf + k];
    PetscCall(VecRestoreArray(state.amounts(), &own));
  }
  PetscCall(state.setOccupiedEnd(ownEnd));
  const double across = inventory > 0.0 ? poolMass / inventory : 0.0;
  movedAcross += across;
  movedAcrossMax = std::max(movedAcrossMax, across);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ColumnCarry::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer,
                                   "carry: column transport at %ld jumps (%.3g ms each on rank 0); mass moved "
                                   "between columns per jump %.3g of the bed on average, %.3g at most\n",
                                   jumps, jumps ? 1e3 * seconds / jumps : 0.0, jumps ? movedAcross / jumps : 0.0,
                                   movedAcrossMax));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

std::unique_ptr<CarryKind> makeColumnCarry() { return std::make_unique<ColumnCarry>(); }

} // namespace rcfd
