#include "rcfd/zone.hpp"
#include "base/petsc_compat.hpp"

#include "base/checked_options.hpp"
#include <algorithm>
#include <cmath>
#include <sstream>

namespace rcfd {
namespace {

struct ShapeInfo {
  Zone::Shape shape;
  const char *option; // after -zone_NAME_
  std::size_t count;  // numbers it takes
  const char *meaning;
};

const ShapeInfo kShapes[] = {
    {Zone::Shape::Box, "box", 6, "xmin,xmax,ymin,ymax,zmin,zmax [m]"},
    {Zone::Shape::Layers, "layers", 2, "first,last cell layer from the bottom (0-based)"},
    {Zone::Shape::Heights, "heights", 2, "low,high above the bottom [m]"},
    {Zone::Shape::HalfSpace, "halfspace", 4, "nx,ny,nz,c (cells with n.x <= c)"},
    {Zone::Shape::Cylinder, "cylinder", 5, "x,y,radius,low,high (vertical axis) [m]"},
};

const ShapeInfo &infoOf(Zone::Shape s) {
  for (const auto &i : kShapes)
    if (i.shape == s) return i;
  return kShapes[0];
}

// Height above the bottom of the mesh along the vertical axis.
double heightOf(const Vec3 &x, int axis, bool upward, double bottom) {
  return upward ? x[axis] - bottom : bottom - x[axis];
}

} // namespace

void verticalAxis(const Vec3 &gravity, int *axis, bool *upward) {
  int a = 0;
  for (int d = 1; d < 3; ++d)
    if (std::fabs(gravity[d]) > std::fabs(gravity[a])) a = d;
  *axis = a;
  *upward = gravity[a] <= 0.0; // gravity along -axis: the axis points up
}

Zone::Zone(std::string name, Shape shape, std::vector<double> parameters)
    : name_(std::move(name)), shape_(shape), p(std::move(parameters)) {}

std::string Zone::checkParameters() const {
  const ShapeInfo &info = infoOf(shape_);
  std::ostringstream why;
  if (p.size() != info.count) {
    why << "takes " << info.count << " numbers " << info.meaning << ", not " << p.size();
    return why.str();
  }
  for (double v : p)
    if (!std::isfinite(v)) return "has a number that is not finite";
  switch (shape_) {
  case Shape::Box:
    if (p[0] > p[1] || p[2] > p[3] || p[4] > p[5]) return "needs min <= max on every axis";
    break;
  case Shape::Layers:
    if (p[0] < 0 || p[1] < p[0] || p[0] != std::floor(p[0]) || p[1] != std::floor(p[1]))
      return "needs whole layer numbers 0 <= first <= last";
    break;
  case Shape::Heights:
    if (p[0] > p[1]) return "needs low <= high";
    break;
  case Shape::HalfSpace:
    if (p[0] == 0 && p[1] == 0 && p[2] == 0) return "needs a non-zero normal";
    break;
  case Shape::Cylinder:
    if (!(p[2] > 0) || p[3] > p[4]) return "needs a positive radius and low <= high";
    break;
  }
  return "";
}

bool Zone::contains(const Mesh &mesh, int cell, int vertical, bool upward) const {
  const Vec3 &x = mesh.cellCentre[cell];
  switch (shape_) {
  case Shape::Box:
    return x[0] >= p[0] && x[0] <= p[1] && x[1] >= p[2] && x[1] <= p[3] && x[2] >= p[4] &&
           x[2] <= p[5];
  case Shape::Layers: {
    const BoxSpec &b = mesh.boxSpec();
    const double h = b.length[vertical] / (vertical == 0 ? b.nx : vertical == 1 ? b.ny : b.nz);
    const double base = upward ? b.origin[vertical] : b.origin[vertical] + b.length[vertical];
    const double layer = std::floor(heightOf(x, vertical, upward, base) / h);
    return layer >= p[0] && layer <= p[1];
  }
  case Shape::Heights: {
    const double z = heightOf(x, vertical, upward, bottom);
    return z >= p[0] && z <= p[1];
  }
  case Shape::HalfSpace:
    return p[0] * x[0] + p[1] * x[1] + p[2] * x[2] <= p[3];
  case Shape::Cylinder: {
    const int a = (vertical + 1) % 3, b = (vertical + 2) % 3;
    const int first = std::min(a, b), second = std::max(a, b); // x,y in axis order
    const double dx = x[first] - p[0], dy = x[second] - p[1];
    const double z = heightOf(x, vertical, upward, bottom);
    return dx * dx + dy * dy <= p[2] * p[2] && z >= p[3] && z <= p[4];
  }
  }
  return false;
}

PetscErrorCode Zone::setUp(const Mesh &mesh, const Layout &layout, const Vec3 &gravity) {
  PetscFunctionBeginUser;
  const MPI_Comm comm = layout.comm();
  const std::string why = checkParameters();
  PetscCheck(why.empty(), comm, PETSC_ERR_USER_INPUT, "Zone '%s' (-zone_%s_%s) %s", name_.c_str(),
             name_.c_str(), infoOf(shape_).option, why.c_str());
  PetscCheck(shape_ != Shape::Layers || mesh.onBoxLattice(), comm, PETSC_ERR_USER_INPUT,
             "Zone '%s': cell layers need a box mesh; give heights instead", name_.c_str());
  int vertical = 2;
  bool upward = true;
  verticalAxis(gravity, &vertical, &upward);
  if (mesh.onBoxLattice()) { // a vessel's bottom is its box's: heights are the same numbers
    const BoxSpec &b = mesh.boxSpec();
    bottom = upward ? b.origin[vertical] : b.origin[vertical] + b.length[vertical];
  } else {
    bottom = upward ? 1e300 : -1e300;
    for (const auto &c : mesh.cellCentre) bottom = upward ? std::min(bottom, c[vertical]) : std::max(bottom, c[vertical]);
  }
  local.clear();
  double volume = 0.0;
  const auto &owned = layout.ownedNatural();
  for (PetscInt i = 0; i < static_cast<PetscInt>(owned.size()); ++i)
    if (contains(mesh, static_cast<int>(owned[i]), vertical, upward)) {
      local.push_back(i);
      volume += mesh.cellVolume[owned[i]];
    }
  PetscInt count = static_cast<PetscInt>(local.size());
  PetscCallMPI(MPI_Allreduce(&count, &total, 1, MPIU_INT, MPI_SUM, comm));
  PetscCallMPI(MPI_Allreduce(&volume, &totalVolume, 1, MPI_DOUBLE, MPI_SUM, comm));
  PetscCheck(total > 0, comm, PETSC_ERR_USER_INPUT,
             "Zone '%s' (%s) holds no cell centre of the mesh; check its numbers against the mesh",
             name_.c_str(), describe().c_str());
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::string Zone::describe() const {
  std::ostringstream out;
  out.precision(6);
  out << name_ << ": " << infoOf(shape_).option;
  for (std::size_t i = 0; i < p.size(); ++i) out << (i ? "," : " ") << p[i];
  if (total > 0) out << ", " << total << " cells, " << totalVolume << " m^3";
  return out.str();
}

PetscErrorCode ZoneSet::setFromOptions(MPI_Comm comm) {
  PetscFunctionBeginUser;
  char names[PETSC_MAX_PATH_LEN] = "";
  PetscBool set = PETSC_FALSE;
  PetscOptionsBegin(comm, nullptr, "Named zones", "rcfd");
  PetscCall(PetscOptionsString("-zones", "Names of the case's zones, e.g. spray,feed,discharge", "",
                               names, names, sizeof names, &set));
  PetscOptionsEnd();
  if (!set) PetscFunctionReturn(PETSC_SUCCESS);
  std::stringstream list(names);
  std::string name;
  while (std::getline(list, name, ',')) {
    PetscCheck(!name.empty() && name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_") == std::string::npos,
               comm, PETSC_ERR_USER_INPUT,
               "-zones: '%s' is not a zone name (lower-case letters, digits and _)", name.c_str());
    PetscCheck(!find(name), comm, PETSC_ERR_USER_INPUT, "-zones names '%s' twice", name.c_str());
    const std::string prefix = "zone_" + name + "_";
    int found = 0;
    PetscOptionsBegin(comm, prefix.c_str(), ("Zone " + name).c_str(), "rcfd");
    for (const auto &info : kShapes) {
      PetscReal values[8];
      PetscInt n = 8;
      PetscBool given = PETSC_FALSE;
      PetscCall(checkedRealArray(PetscOptionsObject, (std::string("-") + info.option).c_str(), info.meaning,
                                 values, &n, &given));
      if (!given) continue;
      ++found;
      zones.emplace_back(name, info.shape, std::vector<double>(values, values + n));
    }
    PetscOptionsEnd();
    PetscCheck(found == 1, comm, PETSC_ERR_USER_INPUT,
               "Zone '%s' needs exactly one shape (-%sbox, -%slayers, -%sheights, -%shalfspace or "
               "-%scylinder), not %d",
               name.c_str(), prefix.c_str(), prefix.c_str(), prefix.c_str(), prefix.c_str(), prefix.c_str(),
               found);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ZoneSet::setUp(const Mesh &mesh, const Layout &layout, const Vec3 &gravity) {
  PetscFunctionBeginUser;
  for (auto &z : zones) PetscCall(z.setUp(mesh, layout, gravity));
  PetscFunctionReturn(PETSC_SUCCESS);
}

const Zone *ZoneSet::find(const std::string &name) const {
  for (const auto &z : zones)
    if (z.name() == name) return &z;
  return nullptr;
}

PetscErrorCode ZoneSet::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  if (zones.empty()) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscViewerASCIIPrintf(viewer, "Zones:\n"));
  for (const auto &z : zones) PetscCall(PetscViewerASCIIPrintf(viewer, "  %s\n", z.describe().c_str()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
