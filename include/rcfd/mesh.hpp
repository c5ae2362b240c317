// Finite-volume mesh: cells and faces, stored face-addressed so that an
// unstructured mesh can be used later.  Every rank holds the whole mesh
// (a few MB for the paper's 56,000 cells); only the state is distributed.
#pragma once

#include <petscsys.h>

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace rcfd {

using Vec3 = std::array<double, 3>;

/// Axis-aligned box divided into nx * ny * nz equal cells.
/// Cell (i, j, k) has the natural index i + nx * (j + ny * k): x runs fastest.
struct BoxSpec {
  int nx = 40, ny = 10, nz = 140;
  Vec3 origin{0.0, 0.0, 0.0};
  Vec3 length{0.2, 0.05, 0.7};

  int numCells() const { return nx * ny * nz; }
  int cellIndex(int i, int j, int k) const { return i + nx * (j + ny * k); }
  Vec3 spacing() const { return {length[0] / nx, length[1] / ny, length[2] / nz}; }
  /// Index of the cell holding point p, or -1 when p is outside the box.
  int locate(const Vec3 &p) const;
  /// Why nx x ny x nz cells cannot be made here, or "" when they can: a count below
  /// 1, more cells than an int numbers, or a mesh alone larger than this machine's
  /// memory.  Checked before anything per cell is allocated.
  static std::string sizeProblem(double nx, double ny, double nz);
};

class Mesh {
public:
  /// Not collective.  Builds in `*mesh` the box mesh of `spec` with internal
  /// faces and the six boundary patches (0: x-, 1: x+, 2: y-, 3: y+, 4: z-,
  /// 5: z+).  Refuses (PETSC_ERR_ARG_OUTOFRANGE, one sentence: "a box mesh of
  /// nx x ny x nz cells ..." and BoxSpec::sizeProblem()'s reason) a box with
  /// no cell along an axis, more cells than an int numbers, or a mesh larger
  /// than this machine's memory; `*mesh` is then left as it was.
  static PetscErrorCode createBox(const BoxSpec &spec, Mesh *mesh);

  int numCells() const { return static_cast<int>(cellVolume.size()); }
  int numFaces() const { return static_cast<int>(faceOwner.size()); }
  int numBoundaryFaces() const { return static_cast<int>(boundaryOwner.size()); }
  bool isBox() const { return hasBox; }
  const BoxSpec &boxSpec() const { return spec; }
  double totalVolume() const;

  // A vessel cut out of a box (include/rcfd/vessel.hpp): not isBox(), but each
  // cell is one cell of boxSpec(), so box-structured code (layers, columns,
  // field files) finds a cell's (i, j, k) through boxCell and back through
  // cellOfBoxCell.  On a box mesh both are the identity.
  /// Cells cut from a box: some box cells are missing or partly outside.
  bool isMasked() const { return !boxCells.empty(); }
  /// A box mesh or a masked one: boxSpec() is the box of its cells.
  bool onBoxLattice() const { return hasBox || isMasked(); }
  int boxCell(int c) const { return boxCells.empty() ? c : boxCells[c]; }
  /// The cell that is box cell b, or -1 when b is outside the vessel.
  int cellOfBoxCell(int b) const;
  /// The vessel's describe() line ("box" for a box mesh).
  const std::string &vessel() const { return vesselText; }
  /// A mesh of the given box cells (ascending) of `spec`, cut by the vessel
  /// named by `vessel`; its geometry (cells, faces) is left to the caller to fill.
  static Mesh masked(const BoxSpec &spec, std::vector<int> boxCells, std::string vessel);
  /// Tiny cut cells merged into a neighbour (-vessel_merge_below, docs/vessels.md):
  /// box cell b is a member of cell c too (boxCell(c) stays the cell's own box
  /// cell, the one holding its centroid); cellOfBoxCell(b) becomes c.
  void addMergedBoxCell(int b, int c);
  /// The merged members (box cell, cell), in ascending box cell order; empty
  /// unless tiny cut cells were merged.
  const std::vector<std::pair<int, int>> &mergedBoxCells() const { return merged; }

  // Cells.
  std::vector<Vec3> cellCentre;
  std::vector<double> cellVolume;
  // Internal faces: the area vector points from owner to neighbour.
  std::vector<int> faceOwner, faceNeighbour;
  std::vector<Vec3> faceArea;
  // Boundary faces: the area vector points out of the domain.
  std::vector<int> boundaryOwner, boundaryPatch;
  std::vector<Vec3> boundaryArea;

private:
  bool hasBox = false;
  BoxSpec spec;
  std::vector<int> boxCells;       // per cell, its box cell; empty on a box mesh
  std::vector<int> cellOfBox;      // per box cell, its cell or -1; empty on a box mesh
  std::string vesselText = "box";
  std::vector<std::pair<int, int>> merged; // (box cell, cell) of members beyond boxCells
};

} // namespace rcfd
