// rcfd's built-in size laws (rcfd/size_law.hpp; docs/drift.md derives them
// and says which carry no net volume).
#include "rcfd/size_law.hpp"
#include "base/checked_options.hpp"
#include "base/petsc_compat.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

namespace rcfd {

PetscErrorCode SizeLaw::setFromOptions(MPI_Comm) { return PETSC_SUCCESS; }

PetscErrorCode SizeLaw::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer, "size law %s: %s, kd in %s\n", type().c_str(), formula().c_str(), unitOfK()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

double SizeLaw::defaultK() const { return std::numeric_limits<double>::quiet_NaN(); }

double SizeLaw::largestSpeed(double k, double dMin, double dMax, const double *d, int n) const {
  std::vector<double> atMin(n), atMax(n);
  velocities(k, dMin, d, n, atMin.data());
  velocities(k, dMax, d, n, atMax.data());
  double largest = 0.0;
  for (int i = 0; i < n; ++i) largest = std::max({largest, std::fabs(atMin[i]), std::fabs(atMax[i])});
  return largest;
}

namespace {

// The paper's laws in d^2, k_d in 1/(m s); the expressions are those of the
// drift operator before laws were registered, so runs keep their bits.
// Their default k_d is the operator's old default, 5e3 for both.
class SquareLaw : public SizeLaw {
public:
  const char *unitOfK() const override { return "1/(m s)"; }
  double defaultK() const override { return 5e3; }
};

class LawA : public SquareLaw {
public:
  std::string type() const override { return "A"; }
  void velocities(double k, double dRef, const double *d, int n, double *u) const override {
    for (int i = 0; i < n; ++i) u[i] = -k * (d[i] * d[i] - dRef * dRef);
  }
  std::string formula() const override { return "u = -kd (d^2 - d32^2)"; }
};

class LawB : public SquareLaw {
public:
  std::string type() const override { return "B"; }
  void velocities(double k, double dRef, const double *d, int n, double *u) const override {
    for (int i = 0; i < n; ++i) u[i] = -k * (d[i] - dRef) * std::fabs(d[i] - dRef);
  }
  std::string formula() const override { return "u = -kd (d - d32)|d - d32|"; }
};

// Dimensionless laws, k in m/s.
class DragLaw : public SizeLaw {
public:
  std::string type() const override { return "drag"; }
  void velocities(double k, double dRef, const double *d, int n, double *u) const override {
    for (int i = 0; i < n; ++i) u[i] = k * (dRef / d[i] - 1.0);
  }
  const char *unitOfK() const override { return "m/s"; }
  std::string formula() const override { return "u = kd (d32/d - 1)"; }
};

class LogLaw : public SizeLaw {
public:
  std::string type() const override { return "log"; }
  void velocities(double k, double dRef, const double *d, int n, double *u) const override {
    for (int i = 0; i < n; ++i) u[i] = k * std::log(dRef / d[i]);
  }
  const char *unitOfK() const override { return "m/s"; }
  std::string formula() const override { return "u = kd ln(d32/d)"; }
};

class PowerLaw : public SizeLaw {
public:
  std::string type() const override { return "power"; }
  PetscErrorCode setFromOptions(MPI_Comm comm) override {
    PetscFunctionBeginUser;
    PetscOptionsBegin(comm, prefix.c_str(), "Size law power: u = kd ((d32/d)^m - 1)", "rcfd");
    PetscCall(checkedReal(PetscOptionsObject, "-exponent", "Exponent m of the power size law", &m,
                          {0.0, kLargest, false, true, "an exponent m in (0, 20] (m = 1 is the drag law)"}));
    PetscOptionsEnd();
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  void velocities(double k, double dRef, const double *d, int n, double *u) const override {
    for (int i = 0; i < n; ++i) u[i] = k * (std::pow(dRef / d[i], m) - 1.0);
  }
  const char *unitOfK() const override { return "m/s"; }
  std::string formula() const override {
    char text[64];
    std::snprintf(text, sizeof text, "u = kd ((d32/d)^%g - 1)", m);
    return text;
  }
  bool shapeParameter(ShapeParameter *p) const override {
    *p = {"size_law_exponent", 0.05, 5.0, m};
    return true;
  }
  void setShapeParameter(double value) override { m = value; }

private:
  static constexpr double kLargest = 20.0;
  double m = 1.0;
};

} // namespace

SizeLawRegistry SizeLawRegistry::withBuiltins() {
  SizeLawRegistry r;
  // The built-in names are identifiers and distinct: add() cannot fail here.
  PetscCallAbort(PETSC_COMM_SELF, r.add("A", [] { return std::make_unique<LawA>(); }, "u = -kd (d^2 - d32^2), kd in 1/(m s) (paper)"));
  PetscCallAbort(PETSC_COMM_SELF, r.add("B", [] { return std::make_unique<LawB>(); }, "u = -kd (d - d32)|d - d32|, kd in 1/(m s) (paper)"));
  PetscCallAbort(PETSC_COMM_SELF, r.add("drag", [] { return std::make_unique<DragLaw>(); },
        "u = kd (d32/d - 1), kd in m/s: drag per unit mass ~ d32/d; no net volume with -drift_local_d32"));
  PetscCallAbort(PETSC_COMM_SELF, r.add("log", [] { return std::make_unique<LogLaw>(); },
        "u = kd ln(d32/d), kd in m/s: the percolation velocity of continuum segregation models"));
  PetscCallAbort(PETSC_COMM_SELF, r.add("power", [] { return std::make_unique<PowerLaw>(); },
        "u = kd ((d32/d)^m - 1), kd in m/s, m = -drift_size_law_exponent (default 1)"));
  return r;
}

} // namespace rcfd
