// The vessel's shapes: their numbers checked, the level function that tells
// inside from outside, the line that names a vessel in a database, and the
// options that make one (include/rcfd/vessel.hpp, docs/vessels.md).
#include "rcfd/vessel.hpp"
#include "base/petsc_compat.hpp"

#include "base/checked_options.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace rcfd {
namespace {

struct KindInfo {
  Vessel::Kind kind;
  const char *name;  // in options (-vessel_NAME_<name>) and in describe()
  std::size_t count; // numbers it takes (cylinder: 3 or 5)
  const char *meaning;
};

const KindInfo kKinds[] = {
    {Vessel::Kind::Box, "box", 6, "xmin,xmax,ymin,ymax,zmin,zmax [m]"},
    {Vessel::Kind::Cylinder, "cylinder", 5, "x,y,radius[,low,high] (vertical axis) [m]"},
    {Vessel::Kind::Cone, "cone", 6, "x,y,low,radius_low,high,radius_high (vertical frustum) [m]"},
    {Vessel::Kind::TubeX, "tube_x", 3, "y,z,radius (horizontal, along x) [m]"},
    {Vessel::Kind::TubeY, "tube_y", 3, "x,z,radius (horizontal, along y) [m]"},
};

const KindInfo &infoOf(Vessel::Kind k) {
  for (const auto &i : kKinds)
    if (i.kind == k) return i;
  return kKinds[0];
}

// Why these numbers do not make a shape of this kind, or "".
std::string problemOf(Vessel::Kind kind, const std::vector<double> &p) {
  const KindInfo &info = infoOf(kind);
  const bool countOk = kind == Vessel::Kind::Cylinder ? (p.size() == 3 || p.size() == 5) : p.size() == info.count;
  std::ostringstream why;
  if (!countOk) {
    why << "takes " << info.meaning << ", not " << p.size() << " numbers";
    return why.str();
  }
  for (double v : p)
    if (!std::isfinite(v)) return "has a number that is not finite";
  switch (kind) {
  case Vessel::Kind::Box:
    if (!(p[0] < p[1] && p[2] < p[3] && p[4] < p[5])) return "needs each min below its max";
    break;
  case Vessel::Kind::Cylinder:
    if (!(p[2] > 0)) return "needs a positive radius";
    if (p.size() == 5 && !(p[3] < p[4])) return "needs low below high";
    break;
  case Vessel::Kind::Cone:
    if (!(p[2] < p[4])) return "needs low below high";
    if (!(p[3] >= 0 && p[5] >= 0 && p[3] + p[5] > 0)) return "needs radii >= 0, not both 0";
    break;
  case Vessel::Kind::TubeX:
  case Vessel::Kind::TubeY:
    if (!(p[2] > 0)) return "needs a positive radius";
    break;
  }
  return "";
}

// Signed lower bound of the distance to one shape's wall (positive inside).
double shapeLevel(const Vessel::Shape &s, const Vec3 &x) {
  const auto &p = s.p;
  switch (s.kind) {
  case Vessel::Kind::Box:
    return std::min({x[0] - p[0], p[1] - x[0], x[1] - p[2], p[3] - x[1], x[2] - p[4], p[5] - x[2]});
  case Vessel::Kind::Cylinder: {
    const double side = p[2] - std::hypot(x[0] - p[0], x[1] - p[1]);
    return p.size() == 5 ? std::min({side, x[2] - p[3], p[4] - x[2]}) : side;
  }
  case Vessel::Kind::Cone: {
    // (r(z) - rho) cos(theta): the distance to the (extended) cone's side,
    // 1-Lipschitz like the others, so min() keeps it a lower bound.
    const double slope = (p[5] - p[3]) / (p[4] - p[2]);
    const double radius = p[3] + slope * (x[2] - p[2]);
    const double side = (radius - std::hypot(x[0] - p[0], x[1] - p[1])) / std::sqrt(1.0 + slope * slope);
    return std::min({side, x[2] - p[2], p[4] - x[2]});
  }
  case Vessel::Kind::TubeX:
    return p[2] - std::hypot(x[1] - p[0], x[2] - p[1]);
  case Vessel::Kind::TubeY:
    return p[2] - std::hypot(x[0] - p[0], x[2] - p[1]);
  }
  return -1.0;
}

std::string numbers(const std::vector<double> &p) {
  std::string out;
  char text[32];
  for (std::size_t i = 0; i < p.size(); ++i) {
    // The shortest of 15 to 17 digits that reads back to the same double.
    for (int digits = 15; digits <= 17; ++digits) {
      std::snprintf(text, sizeof text, "%s%.*g", i ? "," : "", digits, p[i]);
      if (std::strtod(text + (i ? 1 : 0), nullptr) == p[i]) break;
    }
    out += text;
  }
  return out;
}

constexpr ValueRange kMergeShare{0.0, 1.0, true, true, "a share of a cell's volume in [0, 1]"};

} // namespace

PetscErrorCode Vessel::add(Kind kind, std::vector<double> p, bool subtract) {
  PetscFunctionBeginUser;
  const std::string why = problemOf(kind, p);
  PetscCheck(why.empty(), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "vessel shape %s %s", infoOf(kind).name,
             why.c_str());
  PetscCheck(!shapes_.empty() || !subtract, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "a vessel cannot start with a shape taken away: give a shape to take it from first");
  PetscCallCXX(shapes_.push_back({kind, std::move(p), subtract}));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Vessel::setSamples(int n) {
  PetscFunctionBeginUser;
  PetscCheck(n >= 1 && n <= 64, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "vessel samples must be between 1 and 64 per cell edge, not %d", n);
  samples_ = n;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Vessel::setMergeBelow(double S) {
  PetscFunctionBeginUser;
  PetscCheck(S >= 0 && S <= 1, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "vessel merge threshold must be a share of a cell's volume between 0 and 1, not %g", S);
  mergeBelow_ = S;
  PetscFunctionReturn(PETSC_SUCCESS);
}

double Vessel::level(const Vec3 &x) const {
  if (shapes_.empty()) return HUGE_VAL;
  double v = shapeLevel(shapes_[0], x);
  for (std::size_t s = 1; s < shapes_.size(); ++s) {
    const double l = shapeLevel(shapes_[s], x);
    v = shapes_[s].subtract ? std::min(v, -l) : std::max(v, l);
  }
  return v;
}

std::string Vessel::describe() const {
  if (fitted_) return "cylinder (its box not given yet)";
  if (shapes_.empty()) return "box";
  std::string out;
  for (const auto &s : shapes_)
    out += std::string(out.empty() ? "" : " ") + (s.subtract ? "-" : "+") + infoOf(s.kind).name + "(" +
           numbers(s.p) + ")";
  out += " samples " + std::to_string(samples_);
  // Only when merging: a vessel without it keeps its line, and so its databases' content hash.
  if (mergeBelow_ > 0) out += " merge " + numbers({mergeBelow_});
  return out;
}

PetscErrorCode Vessel::parse(const std::string &text, Vessel *out) {
  Vessel v;
  PetscFunctionBeginUser;
  if (text == "box") {
    *out = v;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  std::istringstream in(text);
  std::string token;
  bool sampled = false;
  while (in >> token) {
    if (token == "samples") {
      int n = 0;
      if (!(in >> n)) break;
      PetscCall(v.setSamples(n));
      sampled = true;
      continue;
    }
    if (token == "merge") {
      double S = -1;
      if (!(in >> S)) break;
      PetscCall(v.setMergeBelow(S));
      continue;
    }
    const std::size_t open = token.find('(');
    PetscCheck(token.size() >= 4 && (token[0] == '+' || token[0] == '-') && open != std::string::npos &&
                   token.back() == ')',
               PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "'%s' does not name a vessel (at '%s')", text.c_str(),
               token.c_str());
    const std::string name = token.substr(1, open - 1);
    const KindInfo *info = nullptr;
    for (const auto &i : kKinds)
      if (name == i.name) info = &i;
    PetscCheck(info, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "'%s' names an unknown vessel shape '%s'", text.c_str(),
               name.c_str());
    std::vector<double> p;
    std::istringstream list(token.substr(open + 1, token.size() - open - 2));
    std::string number;
    while (std::getline(list, number, ',')) {
      char *end = nullptr;
      p.push_back(std::strtod(number.c_str(), &end));
      PetscCheck(end != number.c_str() && !*end, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
                 "'%s' has a bad number '%s'", text.c_str(), number.c_str());
    }
    PetscCall(v.add(info->kind, std::move(p), token[0] == '-'));
  }
  PetscCheck(sampled && !v.shapes_.empty(), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "'%s' does not name a vessel",
             text.c_str());
  *out = std::move(v);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Vessel::in(const BoxSpec &box, Vessel *out) const {
  PetscFunctionBeginUser;
  Vessel v = *this;
  if (fitted_) {
    v.fitted_ = false;
    const double x = std::isnan(fitAxis_[0]) ? box.origin[0] + 0.5 * box.length[0] : fitAxis_[0];
    const double y = std::isnan(fitAxis_[1]) ? box.origin[1] + 0.5 * box.length[1] : fitAxis_[1];
    const double r = std::isnan(fitRadius_) ? 0.5 * std::min(box.length[0], box.length[1]) : fitRadius_;
    PetscCall(v.add(Kind::Cylinder, {x, y, r}));
  }
  *out = std::move(v);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Vessel::setFromOptions(MPI_Comm comm, const BoxSpec &box) {
  PetscFunctionBeginUser;
  PetscCall(setFromOptions(comm));
  PetscCall(in(box, this)); // the same on every rank: options and box are
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Vessel::setFromOptions(MPI_Comm comm) {
  std::vector<std::string> names, minus;
  PetscBool given = PETSC_FALSE, minusGiven = PETSC_FALSE, axisGiven = PETSC_FALSE, radiusGiven = PETSC_FALSE;
  PetscReal axis[2] = {NAN, NAN};
  PetscReal radius = NAN;
  PetscInt nAxis = 2, samples = samples_;
  PetscReal merge = mergeBelow_;
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, nullptr, "Vessel (docs/vessels.md)", nullptr);
  PetscCall(checkedStringArray(PetscOptionsObject, "-vessel",
                               "box, cylinder, or the names of shapes united (-vessel_NAME_<shape>); rcfd build from dumps also from-particles", 64, &names,
                               &given));
  PetscCall(checkedStringArray(PetscOptionsObject, "-vessel_minus", "names of shapes taken away", 64, &minus,
                               &minusGiven));
  PetscCall(checkedInt(PetscOptionsObject, "-vessel_samples", "sub-samples per cell edge of a cut cell", &samples,
                       1, 64));
  PetscCall(checkedReal(PetscOptionsObject, "-vessel_merge_below",
                        "a cut cell with less than this share of its box cell inside joins its open neighbour of "
                        "the largest open area (0: none)",
                        &merge, kMergeShare));
  PetscCall(checkedRealArray(PetscOptionsObject, "-vessel_axis",
                             "x,y of -vessel cylinder's axis [m] (nan: the box's centre)", axis, &nAxis,
                             &axisGiven));
  PetscCall(checkedReal(PetscOptionsObject, "-vessel_radius",
                        "radius of -vessel cylinder [m] (nan: half the narrower side of the box)", &radius, kPositive,
                        &radiusGiven));
  PetscOptionsEnd();
  PetscCheck(!(given && names.size() == 1 && names[0] == "from-particles"), comm, PETSC_ERR_USER_INPUT,
             "-vessel from-particles takes the vessel from particle dumps (rcfd build -dumps); give the vessel's shapes here");
  const bool shortcut = names.size() == 1 && (names[0] == "box" || names[0] == "cylinder");
  PetscCheck(!(axisGiven || radiusGiven) || (shortcut && names[0] == "cylinder"), comm, PETSC_ERR_USER_INPUT,
             "-vessel_axis and -vessel_radius belong to -vessel cylinder; give a named shape's numbers in "
             "-vessel_NAME_cylinder instead");
  PetscCheck(!axisGiven || nAxis == 2, comm, PETSC_ERR_USER_INPUT, "-vessel_axis takes x,y [m], not %d numbers",
             (int)nAxis);
  PetscCheck(!minusGiven || (given && !(shortcut && names[0] == "box")), comm, PETSC_ERR_USER_INPUT,
             "-vessel_minus takes shapes away from a -vessel: name the shapes to take them from");
  shapes_.clear();
  fitted_ = false;
  samples_ = static_cast<int>(samples);
  mergeBelow_ = merge;
  if (!given || (shortcut && names[0] == "box")) PetscFunctionReturn(PETSC_SUCCESS);
  if (shortcut) { // the box is not known yet: in(box) completes it
    fitted_ = true;
    fitAxis_[0] = axis[0];
    fitAxis_[1] = axis[1];
    fitRadius_ = radius;
  } else {
    auto readShape = [&](const std::string &name, bool subtract) -> PetscErrorCode {
      PetscFunctionBeginUser;
      PetscCheck(name != "box" && name != "cylinder" && name != "minus" && name != "samples" && name != "axis" &&
                     name != "radius",
                 comm, PETSC_ERR_USER_INPUT,
                 "-vessel: '%s' is a word of the vessel options, not a shape name; name the shape otherwise",
                 name.c_str());
      int found = 0;
      for (const auto &info : kKinds) {
        const std::string option = "-vessel_" + name + "_" + info.name;
        PetscReal p[8];
        PetscInt n = 8;
        PetscBool set = PETSC_FALSE;
        PetscOptionsBegin(comm, nullptr, "Vessel shape", nullptr);
        PetscCall(checkedRealArray(PetscOptionsObject, option.c_str(), info.meaning, p, &n, &set));
        PetscOptionsEnd();
        if (!set) continue;
        ++found;
        const std::string why = problemOf(info.kind, std::vector<double>(p, p + n));
        PetscCheck(why.empty(), comm, PETSC_ERR_USER_INPUT, "%s %s", option.c_str(), why.c_str());
        PetscCheck(found == 1, comm, PETSC_ERR_USER_INPUT, "Vessel shape '%s' has more than one shape option "
                   "(-vessel_%s_<shape>); give exactly one", name.c_str(), name.c_str());
        PetscCall(add(info.kind, std::vector<double>(p, p + n), subtract));
      }
      PetscCheck(found == 1, comm, PETSC_ERR_USER_INPUT,
                 "Vessel shape '%s' has no shape: give one of -vessel_%s_box, _cylinder, _cone, _tube_x or _tube_y",
                 name.c_str(), name.c_str());
      PetscFunctionReturn(PETSC_SUCCESS);
    };
    for (const auto &n : names) PetscCall(readShape(n, false));
    for (const auto &n : minus) PetscCall(readShape(n, true));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
