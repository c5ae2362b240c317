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
  for (size_t t = 0; t < times.size(); ++t) {
    std::snprintf(line, sizeof line,
                  "<Grid Name=\"t%zu\" GridType=\"Uniform\">\n<Time Value=\"%.9g\"/>\n"
                  "<Topology TopologyType=\"3DCoRectMesh\" Dimensions=\"%d %d %d\"/>\n"
                  "<Geometry GeometryType=\"ORIGIN_DXDYDZ\">\n"
                  "<DataItem Dimensions=\"3\" Format=\"XML\">%.9g %.9g %.9g</DataItem>\n"
                  "<DataItem Dimensions=\"3\" Format=\"XML\">%.9g %.9g %.9g</DataItem>\n"
                  "</Geometry>\n",
                  t, times[t], b.nz + 1, b.ny + 1, b.nx + 1, b.origin[2], b.origin[1], b.origin[0],
                  h[2], h[1], h[0]);
    x += line;
    for (const auto &name : names) {
      std::snprintf(line, sizeof line,
                    "<Attribute Name=\"%s\" AttributeType=\"Scalar\" Center=\"Cell\">\n"
                    "<DataItem Dimensions=\"%d %d %d\" NumberType=\"Float\" Precision=\"8\" "
                    "Format=\"HDF\">%s:/%s</DataItem>\n</Attribute>\n",
                    name.c_str(), b.nz, b.ny, b.nx, fieldFileName(static_cast<int>(t)).c_str(),
                    name.c_str());
      x += line;
    }
    x += "</Grid>\n";
  }
  x += "</Grid>\n</Domain>\n</Xdmf>\n";
  PetscCall(writeFileAtomically(dir + "/fields.xmf", x));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
