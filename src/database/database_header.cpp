// The parts of a database file around its frames: format attributes, mesh,
// metadata and identity (database_header.hpp).
#include "database/database_header.hpp"

#include "database/content_hash.hpp"
#include "mesh/box_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace rcfd {
namespace {

// Operating conditions (format version 2): optional attributes on /metadata.
constexpr const char *kConditionNames[3] = {"superficial_velocity", "gas_density", "gas_kinematic_viscosity"};

void readConditions(const h5::File &f, OperatingConditions *c) {
  double *value[3] = {&c->superficialVelocity, &c->gasDensity, &c->gasKinematicViscosity};
  for (int i = 0; i < 3; ++i) {
    if (!f.hasAttribute("/metadata", kConditionNames[i])) continue;
    *value[i] = f.readAttrDouble("/metadata", kConditionNames[i]);
    if (!(*value[i] > 0) || !std::isfinite(*value[i]))
      throw h5::Error("database '" + f.path() + "': /metadata " + kConditionNames[i] +
                      " must be a positive number");
  }
}

std::vector<Vec3> triples(const h5::File &f, const std::string &name) {
  const auto flat = f.read<double>(name);
  if (flat.size() % 3) throw h5::Error("database '" + f.path() + "': " + name + " must hold three numbers per row");
  std::vector<Vec3> out(flat.size() / 3);
  for (std::size_t r = 0; r < out.size(); ++r) out[r] = {flat[3 * r], flat[3 * r + 1], flat[3 * r + 2]};
  return out;
}

std::vector<int> cellIndices(const h5::File &f, const std::string &name, int numCells) {
  const auto stored = f.read<int32_t>(name);
  for (int32_t c : stored)
    if (c < 0 || c >= numCells)
      throw h5::Error("database '" + f.path() + "': " + name + " names cell " + std::to_string(c) + " of a " +
                      std::to_string(numCells) + "-cell mesh");
  return std::vector<int>(stored.begin(), stored.end());
}

// A vessel cut out of a box: its cells are the stored box cells, its geometry
// the stored arrays (checked for sizes and indices, as a reader must).
Mesh readMaskedMesh(const h5::File &f, const BoxSpec &spec) {
  const std::string where = "database '" + f.path() + "': /mesh ";
  const auto boxCell = f.read<int32_t>("/mesh/box_cell");
  for (std::size_t c = 0; c < boxCell.size(); ++c)
    if (boxCell[c] < 0 || boxCell[c] >= spec.numCells() || (c > 0 && boxCell[c] <= boxCell[c - 1]))
      throw h5::Error(where + "box_cell must list box cells in ascending order, each once");
  if (boxCell.empty()) throw h5::Error(where + "box_cell lists no cell");
  Mesh m = Mesh::masked(spec, std::vector<int>(boxCell.begin(), boxCell.end()), f.readAttrString("/mesh", "vessel"));
  const int n = static_cast<int>(boxCell.size());
  if (f.exists("/mesh/merged_box_cell")) { // tiny cut cells merged into their neighbours (docs/vessels.md)
    const auto member = f.read<int32_t>("/mesh/merged_box_cell");
    const auto cell = cellIndices(f, "/mesh/merged_cell", n);
    if (cell.size() != member.size()) throw h5::Error(where + "merged_cell must have one row per merged_box_cell");
    for (std::size_t k = 0; k < member.size(); ++k) {
      if (member[k] < 0 || member[k] >= spec.numCells() || m.cellOfBoxCell(member[k]) >= 0)
        throw h5::Error(where + "merged_box_cell must list box cells of the box that no other cell holds, each once");
      m.addMergedBoxCell(member[k], cell[k]);
    }
  }
  m.cellCentre = triples(f, "/mesh/cell_centres");
  m.cellVolume = f.read<double>("/mesh/cell_volumes");
  m.faceOwner = cellIndices(f, "/mesh/face_owner", n);
  m.faceNeighbour = cellIndices(f, "/mesh/face_neighbour", n);
  m.faceArea = triples(f, "/mesh/face_area");
  m.boundaryOwner = cellIndices(f, "/mesh/boundary_owner", n);
  m.boundaryPatch = f.read<int>("/mesh/boundary_patch");
  m.boundaryArea = triples(f, "/mesh/boundary_area");
  if (m.cellCentre.size() != boxCell.size() || m.cellVolume.size() != boxCell.size())
    throw h5::Error(where + "cell_centres and cell_volumes must have one row per cell of box_cell (" +
                    std::to_string(n) + ")");
  for (double v : m.cellVolume)
    if (!(v > 0) || !std::isfinite(v)) throw h5::Error(where + "cell_volumes must be positive");
  if (m.faceNeighbour.size() != m.faceOwner.size() || m.faceArea.size() != m.faceOwner.size() ||
      m.boundaryPatch.size() != m.boundaryOwner.size() || m.boundaryArea.size() != m.boundaryOwner.size())
    throw h5::Error(where + "face arrays must have one row per face");
  return m;
}

} // namespace

void writeMesh(const h5::File &f, const Mesh &mesh) {
  f.createGroup("/mesh");
  if (mesh.isBox()) {
    const BoxSpec &b = mesh.boxSpec();
    f.writeAttr("/mesh", "kind", std::string("box"));
    f.writeAttr("/mesh", "box_cells", std::vector<long long>{b.nx, b.ny, b.nz});
    f.writeAttr("/mesh", "box_origin", std::vector<double>(b.origin.begin(), b.origin.end()));
    f.writeAttr("/mesh", "box_length", std::vector<double>(b.length.begin(), b.length.end()));
  } else if (mesh.isMasked()) {
    // A vessel cut out of a box (docs/vessels.md): the box, the vessel's line
    // and each cell's box cell; the arrays below hold the cut geometry.
    const BoxSpec &b = mesh.boxSpec();
    f.writeAttr("/mesh", "kind", std::string("masked_box"));
    f.writeAttr("/mesh", "box_cells", std::vector<long long>{b.nx, b.ny, b.nz});
    f.writeAttr("/mesh", "box_origin", std::vector<double>(b.origin.begin(), b.origin.end()));
    f.writeAttr("/mesh", "box_length", std::vector<double>(b.length.begin(), b.length.end()));
    f.writeAttr("/mesh", "vessel", mesh.vessel());
    std::vector<int32_t> boxCell(mesh.numCells());
    for (int c = 0; c < mesh.numCells(); ++c) boxCell[c] = mesh.boxCell(c);
    f.write("/mesh/box_cell", boxCell);
    if (!mesh.mergedBoxCells().empty()) { // only with -vessel_merge_below: other databases keep their bits
      std::vector<int32_t> member, cell;
      for (const auto &[b, c] : mesh.mergedBoxCells()) member.push_back(b), cell.push_back(c);
      f.write("/mesh/merged_box_cell", member);
      f.write("/mesh/merged_cell", cell);
    }
  } else {
    f.writeAttr("/mesh", "kind", std::string("unstructured"));
  }
  auto flat = [](const std::vector<Vec3> &v) {
    std::vector<double> out;
    out.reserve(3 * v.size());
    for (const auto &p : v) out.insert(out.end(), p.begin(), p.end());
    return out;
  };
  auto ints = [](const std::vector<int> &v) { return std::vector<int32_t>(v.begin(), v.end()); };
  f.write("/mesh/cell_centres", flat(mesh.cellCentre), 3);
  f.write("/mesh/cell_volumes", mesh.cellVolume);
  f.write("/mesh/face_owner", ints(mesh.faceOwner));
  f.write("/mesh/face_neighbour", ints(mesh.faceNeighbour));
  f.write("/mesh/face_area", flat(mesh.faceArea), 3);
  f.write("/mesh/boundary_owner", ints(mesh.boundaryOwner));
  f.write("/mesh/boundary_patch", ints(mesh.boundaryPatch));
  f.write("/mesh/boundary_area", flat(mesh.boundaryArea), 3);
}

Mesh readMesh(const h5::File &f) {
  f.requireGroup("/mesh");
  const std::string kind = f.readAttrString("/mesh", "kind");
  if (kind != "box" && kind != "masked_box")
    throw h5::Error("database '" + f.path() + "' has a mesh of kind '" + kind +
                    "'; this version of rcfd reads box meshes and vessels cut from them only");
  const auto n = f.readAttrInts("/mesh", "box_cells");
  const auto origin = f.readAttrDoubles("/mesh", "box_origin");
  const auto length = f.readAttrDoubles("/mesh", "box_length");
  if (n.size() != 3 || origin.size() != 3 || length.size() != 3 || n[0] < 1 || n[1] < 1 ||
      n[2] < 1 || !(length[0] > 0 && length[1] > 0 && length[2] > 0))
    throw h5::Error("database '" + f.path() +
                    "': /mesh attributes box_cells, box_origin and box_length must hold three "
                    "positive values each");
  BoxSpec spec;
  spec.nx = static_cast<int>(n[0]);
  spec.ny = static_cast<int>(n[1]);
  spec.nz = static_cast<int>(n[2]);
  std::copy(origin.begin(), origin.end(), spec.origin.begin());
  std::copy(length.begin(), length.end(), spec.length.begin());
  if (kind == "masked_box") return readMaskedMesh(f, spec);
  Mesh mesh = boxMesh(spec);
  // The stored arrays must describe the same mesh as the box attributes.
  const auto volumes = f.read<double>("/mesh/cell_volumes");
  if (volumes.size() != static_cast<size_t>(mesh.numCells()))
    throw h5::Error("database '" + f.path() + "': /mesh/cell_volumes has " +
                    std::to_string(volumes.size()) + " cells but the box is " +
                    std::to_string(spec.nx) + " x " + std::to_string(spec.ny) + " x " +
                    std::to_string(spec.nz) + " = " + std::to_string(mesh.numCells()) + " cells");
  return mesh;
}

void writeConditions(const h5::File &f, const OperatingConditions &c) {
  const double value[3] = {c.superficialVelocity, c.gasDensity, c.gasKinematicViscosity};
  for (int i = 0; i < 3; ++i)
    if (std::isfinite(value[i])) f.writeAttr("/metadata", kConditionNames[i], value[i]);
}

// The file's format version, one this rcfd reads.
long long checkFormat(const h5::File &f) {
  if (!f.hasAttribute("/", "format") || f.readAttrString("/", "format") != kFormatName)
    throw h5::Error("'" + f.path() + "' is not an rcfd database (its root has no attribute format = \"" +
                    kFormatName + "\")");
  const long long version = f.readAttrInt("/", "format_version");
  if (version < 1 || version > kDatabaseFormatVersion)
    throw h5::Error("database '" + f.path() + "' has format version " + std::to_string(version) +
                    ", this rcfd reads versions 1 to " + std::to_string(kDatabaseFormatVersion));
  return version;
}

// The identity a run's checkpoint records (docs/database-format.md, "Identity").
std::string readIdentity(const h5::File &f) {
  if (f.hasAttribute("/", "content_hash")) return "content " + f.readAttrString("/", "content_hash");
  ContentHash made; // an older file: when and how it was made, and its size
  if (f.hasAttribute("/", "created")) made.add(f.readAttrString("/", "created"));
  if (f.hasAttribute("/metadata", "source")) made.add(f.readAttrString("/metadata", "source"));
  if (f.hasAttribute("/frames", "num_frames")) made.add(std::to_string(f.readAttrInt("/frames", "num_frames")));
  return "made " + made.hex();
}

DatabaseMetadata readMetadata(const h5::File &f) {
  f.requireGroup("/metadata");
  DatabaseMetadata m;
  m.dtRec = f.readAttrDouble("/metadata", "dt_rec");
  m.solidDensity = f.readAttrDouble("/metadata", "solid_density");
  const auto g = f.readAttrDoubles("/metadata", "gravity");
  if (g.size() != 3) throw h5::Error("database '" + f.path() + "': /metadata gravity must have 3 components");
  std::copy(g.begin(), g.end(), m.gravity.begin());
  if (f.hasAttribute("/metadata", "source")) m.source = f.readAttrString("/metadata", "source");
  if (f.hasAttribute("/metadata", "units")) m.units = f.readAttrString("/metadata", "units");
  readConditions(f, &m.conditions); // version 2; absent in version 1
  if (f.hasAttribute("/metadata", "weight_bits")) {
    const long long bits = f.readAttrInt("/metadata", "weight_bits");
    if (bits < 1 || bits > kMaxWeightBits)
      throw h5::Error("database '" + f.path() + "': /metadata weight_bits is " + std::to_string(bits) +
                      ", expected the number of bits of its quantised weights, 1 to " +
                      std::to_string(kMaxWeightBits));
    m.weightBits = static_cast<int>(bits);
  }
  if (!(m.dtRec > 0) || !std::isfinite(m.dtRec))
    throw h5::Error("database '" + f.path() + "': dt_rec must be a positive number of seconds");
  if (!(m.solidDensity > 0))
    throw h5::Error("database '" + f.path() + "': solid_density must be positive");
  if (!(std::hypot(g[0], g[1], g[2]) > 0))
    throw h5::Error("database '" + f.path() + "': gravity must not be the zero vector");
  if (m.units != "SI")
    throw h5::Error("database '" + f.path() + "' is in units '" + m.units + "'; rcfd expects SI");
  return m;
}

} // namespace rcfd
