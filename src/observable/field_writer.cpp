#include "rcfd/observables.hpp"
#include "base/petsc_compat.hpp"

#include "base/atomic_file.hpp"
#include "base/collective.hpp"
#include "base/h5.hpp"

#include <cmath>
#include <cstdio>
#include <unistd.h>

namespace rcfd {
namespace {

std::string fieldFileName(int index) {
  char name[40];
  std::snprintf(name, sizeof name, "fields_%06d.h5", index);
  return name;
}

} // namespace

PetscErrorCode FieldWriter::setUp(const Database &database, const FractionSet &set,
                                  double solidDensity, const std::string &directory,
                                  Vec stateTemplate) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  comm = database.layout().comm();
  box = database.mesh().boxSpec();
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) cellVolume = database.mesh().cellVolume;
  boxCells.clear();
  vesselPoints = 0;
  if (rank == 0 && database.mesh().isMasked()) {
    const Mesh &mesh = database.mesh();
    for (int c = 0; c < mesh.numCells(); ++c) boxCells.push_back(mesh.boxCell(c));
    const BoxSpec &b = mesh.boxSpec();
    const long px = b.nx + 1, py = b.ny + 1;
    std::vector<char> used(static_cast<std::size_t>(px) * py * (b.nz + 1), 0);
    for (int bc : boxCells) {
      const int i = bc % b.nx, j = (bc / b.nx) % b.ny, k = bc / (b.nx * b.ny);
      for (int o = 0; o < 8; ++o) {
        const long p = (i + (o & 1)) + px * ((j + ((o >> 1) & 1)) + py * static_cast<long>(k + (o >> 2)));
        vesselPoints += !used[p];
        used[p] = 1;
      }
    }
  }
  fractions = &set;
  rho = solidDensity;
  dir = directory;
  PetscCall(database.layout().naturalScatter(set.size(), stateTemplate, natural.put(), toNatural.put()));
  PetscCall(database.layout().naturalScatter(1, database.alphaS(0), naturalAlpha.put(), alphaToNatural.put()));
  PetscCall(VecScatterCreateToZero(natural, toZero.put(), zeroMasses.put()));
  PetscCall(VecScatterCreateToZero(naturalAlpha, alphaToZero.put(), zeroAlpha.put()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FieldWriter::setUpScalars(const Database &database, const std::vector<std::string> &names,
                                         Vec amountsTemplate) {
  PetscFunctionBeginUser;
  scalarNames = names;
  const PetscInt na = static_cast<PetscInt>(names.size()) * fractions->size();
  PetscCall(database.layout().naturalScatter(na, amountsTemplate, naturalAmounts.put(), amountsToNatural.put()));
  PetscCall(VecScatterCreateToZero(naturalAmounts, amountsToZero.put(), zeroAmounts.put()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// The fields are gathered on rank 0 in natural order and written there with
// HDF5's plain file driver: a collective MPI-IO file took 35 ms per output
// on one rank and 100 ms on two for 56,000 cells, several times the step
// they describe.
PetscErrorCode FieldWriter::write(double time, Vec databaseAlpha, Vec masses, Vec amounts) {
  const int nf = fractions->size(), ns = amounts ? static_cast<int>(scalarNames.size()) : 0;
  PetscFunctionBeginUser;
  PetscCheck(!amounts || naturalAmounts, comm, PETSC_ERR_ORDER, "FieldWriter::write() was given scalar amounts "
             "without setUpScalars()");
  if (ns > 0) {
    PetscCall(VecScatterBegin(amountsToNatural, amounts, naturalAmounts, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(amountsToNatural, amounts, naturalAmounts, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterBegin(amountsToZero, naturalAmounts, zeroAmounts, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(amountsToZero, naturalAmounts, zeroAmounts, INSERT_VALUES, SCATTER_FORWARD));
  }
  PetscCall(VecScatterBegin(toNatural, masses, natural, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(toNatural, masses, natural, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterBegin(toZero, natural, zeroMasses, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(toZero, natural, zeroMasses, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterBegin(alphaToNatural, databaseAlpha, naturalAlpha, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(alphaToNatural, databaseAlpha, naturalAlpha, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterBegin(alphaToZero, naturalAlpha, zeroAlpha, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(alphaToZero, naturalAlpha, zeroAlpha, INSERT_VALUES, SCATTER_FORWARD));
  PetscMPIInt rank;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  const std::string file = dir + "/" + fieldFileName(count());
  const PetscScalar *m = nullptr, *a = nullptr, *amount = nullptr;
  PetscCall(VecGetArrayRead(zeroMasses, &m));
  PetscCall(VecGetArrayRead(zeroAlpha, &a));
  if (ns > 0) PetscCall(VecGetArrayRead(zeroAmounts, &amount));
  const PetscErrorCode written = collectively(comm, [&] {
    if (rank != 0) return;
    if (!boxCells.empty() && (times.empty() || access((dir + "/fields_mesh.h5").c_str(), F_OK) != 0))
      writeVesselCells();
    // Derived fields: alpha_s of the state, alpha of each fraction, local
    // Sauter diameter; and the database's alpha_s for comparison.
    const size_t n = cellVolume.size();
    std::vector<std::vector<double>> fields(nf + 2, std::vector<double>(n));
    const auto &vol = cellVolume;
    for (size_t c = 0; c < n; ++c) {
      const double solid = rho * vol[c];
      double total = 0.0, surface = 0.0;
      for (int i = 0; i < nf; ++i) {
        const double mi = m[c * nf + i];
        fields[2 + i][c] = mi / solid;
        total += mi;
        surface += mi / fractions->diameter(i);
      }
      fields[0][c] = total / solid;
      fields[1][c] = surface > 0 ? total / surface : NAN; // no solid: no diameter (ParaView greys it)
    }
    AtomicFile target(file); // declared first: on failure the file is closed, then removed
    h5::File out = h5::File::create(target);
    out.write("/alpha_s", fields[0]);
    out.write("/d32", fields[1]);
    for (int i = 0; i < nf; ++i) out.write("/alpha_" + fractions->label(i), fields[2 + i]);
    out.write("/alpha_s_database", std::vector<double>(a, a + n));
    // Each scalar's value: per fraction, and over the cell's fractions.
    std::vector<double> value(n), cellValue(n);
    for (int s = 0; s < ns; ++s) {
      const int w = ns * nf;
      for (size_t c = 0; c < n; ++c) {
        double amountSum = 0.0, massSum = 0.0;
        for (int i = 0; i < nf; ++i) amountSum += amount[c * w + s * nf + i], massSum += m[c * nf + i];
        cellValue[c] = massSum > 0.0 ? amountSum / massSum : NAN;
      }
      out.write("/" + scalarNames[s], cellValue);
      for (int i = 0; i < nf; ++i) {
        for (size_t c = 0; c < n; ++c) {
          const double mi = m[c * nf + i];
          value[c] = mi > 0.0 ? amount[c * w + s * nf + i] / mi : NAN;
        }
        out.write("/" + scalarNames[s] + "_" + fractions->label(i), value);
      }
    }
    out.close();
    target.commit();
  }, PETSC_ERR_FILE_WRITE);
  if (ns > 0) PetscCall(VecRestoreArrayRead(zeroAmounts, &amount));
  PetscCall(VecRestoreArrayRead(zeroAlpha, &a));
  PetscCall(VecRestoreArrayRead(zeroMasses, &m));
  PetscCall(written);
  times.push_back(time);
  PetscCall(agreeOnStatus(comm, writeIndex())); // written by rank 0: the others must not wait
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FieldWriter::continueSeries(const std::vector<double> &earlier) {
  PetscMPIInt rank;
  int complete = 1;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0)
    for (size_t t = 0; t < earlier.size() && complete; ++t)
      complete = access((dir + "/" + fieldFileName(static_cast<int>(t))).c_str(), F_OK) == 0;
  PetscCallMPI(MPI_Bcast(&complete, 1, MPI_INT, 0, comm));
  if (complete) times = earlier;
  else times.clear(); // another directory: a series of its own
  PetscFunctionReturn(PETSC_SUCCESS);
}

// A vessel's cells as hexahedra (ParaView shows the vessel, not its box):
// their corners, numbered once, and each cell's eight corners in VTK order.
// Written once per series, as fields_mesh.h5 beside the field files.
PetscErrorCode FieldWriter::writeVesselCells() const {
  PetscFunctionBeginUser;
  const BoxSpec &b = box;
  const Vec3 h = b.spacing();
  const long px = b.nx + 1, py = b.ny + 1;
  std::vector<long> pointOf(static_cast<std::size_t>(px) * py * (b.nz + 1), -1);
  std::vector<double> points;
  std::vector<int32_t> cells;
  cells.reserve(boxCells.size() * 8);
  const int corner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  for (int bc : boxCells) {
    const int i = bc % b.nx, j = (bc / b.nx) % b.ny, k = bc / (b.nx * b.ny);
    for (const auto &o : corner) {
      const long p = (i + o[0]) + px * ((j + o[1]) + py * static_cast<long>(k + o[2]));
      if (pointOf[p] < 0) {
        pointOf[p] = static_cast<long>(points.size() / 3);
        points.insert(points.end(), {b.origin[0] + (i + o[0]) * h[0], b.origin[1] + (j + o[1]) * h[1],
                                     b.origin[2] + (k + o[2]) * h[2]});
      }
      cells.push_back(static_cast<int32_t>(pointOf[p]));
    }
  }
  AtomicFile target(dir + "/fields_mesh.h5");
  h5::File out = h5::File::create(target);
  out.write("/points", points, 3);
  out.write("/cells", cells, 8);
  // The share of each cell inside the vessel: its volume over its box cell's.
  std::vector<double> share(cellVolume.size());
  for (std::size_t c = 0; c < share.size(); ++c) share[c] = cellVolume[c] / (h[0] * h[1] * h[2]);
  out.write("/inside_share", share);
  out.close();
  target.commit();
  PetscFunctionReturn(PETSC_SUCCESS);
}

// XDMF 2 index over all field files written so far, a temporal collection of
// co-rectilinear grids (box meshes) that ParaView reads directly.  The data
// items must carry the grid's cell dimensions (z, y, x); with only the
// length of the (1-D) datasets ParaView reads one value per z layer.
PetscErrorCode FieldWriter::writeIndex() const {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank != 0) PetscFunctionReturn(PETSC_SUCCESS);
  const BoxSpec &b = box;
  const Vec3 h = b.spacing();
  std::vector<std::string> names = {"alpha_s", "alpha_s_database", "d32"};
  for (int i = 0; i < fractions->size(); ++i) names.push_back("alpha_" + fractions->label(i));
  for (const std::string &s : scalarNames) {
    names.push_back(s);
    for (int i = 0; i < fractions->size(); ++i) names.push_back(s + "_" + fractions->label(i));
  }
  char line[512];
  std::string x = "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"2.0\">\n<Domain>\n"
                  "<Grid Name=\"rcfd\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  // A box: a co-rectilinear grid whose data items carry the cell dimensions
  // (z, y, x); a vessel: its cells as hexahedra (fields_mesh.h5), one value each.
  const int n = static_cast<int>(boxCells.size());
  char grid[768], dims[64];
  if (n > 0) {
    std::snprintf(grid, sizeof grid,
                  "<Topology TopologyType=\"Hexahedron\" NumberOfElements=\"%d\">\n"
                  "<DataItem Dimensions=\"%d 8\" NumberType=\"Int\" Format=\"HDF\">fields_mesh.h5:/cells</DataItem>\n"
                  "</Topology>\n<Geometry GeometryType=\"XYZ\">\n"
                  "<DataItem Dimensions=\"%d 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">"
                  "fields_mesh.h5:/points</DataItem>\n</Geometry>\n",
                  n, n, vesselPoints);
    std::snprintf(dims, sizeof dims, "%d", n);
  } else {
    std::snprintf(grid, sizeof grid,
                  "<Topology TopologyType=\"3DCoRectMesh\" Dimensions=\"%d %d %d\"/>\n"
                  "<Geometry GeometryType=\"ORIGIN_DXDYDZ\">\n"
                  "<DataItem Dimensions=\"3\" Format=\"XML\">%.9g %.9g %.9g</DataItem>\n"
                  "<DataItem Dimensions=\"3\" Format=\"XML\">%.9g %.9g %.9g</DataItem>\n"
                  "</Geometry>\n",
                  b.nz + 1, b.ny + 1, b.nx + 1, b.origin[2], b.origin[1], b.origin[0], h[2], h[1], h[0]);
    std::snprintf(dims, sizeof dims, "%d %d %d", b.nz, b.ny, b.nx);
  }
  for (size_t t = 0; t < times.size(); ++t) {
    std::snprintf(line, sizeof line, "<Grid Name=\"t%zu\" GridType=\"Uniform\">\n<Time Value=\"%.9g\"/>\n", t,
                  times[t]);
    x += line;
    x += grid;
    for (const auto &name : names) {
      std::snprintf(line, sizeof line,
                    "<Attribute Name=\"%s\" AttributeType=\"Scalar\" Center=\"Cell\">\n"
                    "<DataItem Dimensions=\"%s\" NumberType=\"Float\" Precision=\"8\" "
                    "Format=\"HDF\">%s:/%s</DataItem>\n</Attribute>\n",
                    name.c_str(), dims, fieldFileName(static_cast<int>(t)).c_str(), name.c_str());
      x += line;
    }
    if (n > 0) {
      std::snprintf(line, sizeof line,
                    "<Attribute Name=\"inside_share\" AttributeType=\"Scalar\" Center=\"Cell\">\n"
                    "<DataItem Dimensions=\"%d\" NumberType=\"Float\" Precision=\"8\" "
                    "Format=\"HDF\">fields_mesh.h5:/inside_share</DataItem>\n</Attribute>\n",
                    n);
      x += line;
    }
    x += "</Grid>\n";
  }
  x += "</Grid>\n</Domain>\n</Xdmf>\n";
  PetscCall(writeFileAtomically(dir + "/fields.xmf", x));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
