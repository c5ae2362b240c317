// Size laws of the drift: how the drift velocity of a size fraction relative
// to the bulk depends on its diameter d_i and a reference diameter d_ref (the
// inventory's Sauter diameter d32, the one given by -drift_d32, or with
// -drift_local_d32 the sending cell's own d32).  A law is registered by name
// like operators and carry kinds and chosen with -drift_size_law (prefix of
// the drift operator); rcfd has A, B, drag, log and power (docs/drift.md),
// and a user adds one with
//   PetscCall(registry.sizeLaws().add("mine", [] { return std::make_unique<MyLaw>(); }, "what it does"));
// then -pipeline shift,drift -drift_size_law mine uses it.
#pragma once

#include "rcfd/registry.hpp"

#include <petscsys.h>
#include <petscviewer.h>

#include <functional>
#include <memory>
#include <string>

namespace rcfd {

/// u_i = k g(d_i, d_ref) [m/s, up positive]: the law is the shape g, the
/// drift operator's -drift_kd the constant k.  The unit of k is the law's:
/// 1/(m s) for laws with g in m^2 (A: g = -(d^2 - d_ref^2), B: g = -(d -
/// d_ref)|d - d_ref|), m/s for dimensionless ones (drag: g = d_ref/d - 1,
/// log: ln(d_ref/d), power: (d_ref/d)^m - 1).  Every built-in g is positive
/// for d < d_ref (small particles rise) and zero at d = d_ref.
class SizeLaw {
public:
  virtual ~SizeLaw() = default;
  /// The registered name of the law.
  virtual std::string type() const = 0;
  /// The drift operator gives its law the prefix "<its prefix>size_law_", so
  /// a law's option -NAME is -drift_size_law_NAME.
  void setOptionsPrefix(const std::string &p) { prefix = p; }
  const std::string &optionsPrefix() const { return prefix; }
  /// Collective.  Reads the law's own options (none by default).
  virtual PetscErrorCode setFromOptions(MPI_Comm comm);
  /// Collective on the viewer: "size law <type>: <formula>, kd in <unit>".
  virtual PetscErrorCode view(PetscViewer viewer) const;
  /// u[i] = k g(d[i], dRef) for i < n [m/s]; d and dRef in m.  Called per
  /// cell with -drift_local_d32, so it should be cheap.
  virtual void velocities(double k, double dRef, const double *d, int n, double *u) const = 0;
  /// The unit of k, e.g. "1/(m s)" or "m/s".
  virtual const char *unitOfK() const = 0;
  /// The law as a formula for -drift_view, e.g. "u = -kd (d^2 - d32^2)".
  virtual std::string formula() const = 0;
  /// The k a run uses without -drift_kd (NaN: the law has none, and the run
  /// refuses to start without -drift_kd).
  virtual double defaultK() const;
  /// The largest |u_i| (i < n) for any d_ref in [dMin, dMax]: the bound of
  /// the sub-step rule with -drift_local_d32 (every cell's d32 lies between
  /// the smallest and the largest diameter).  The default evaluates both
  /// ends, which is the bound for a law monotone in d_ref for every d (all
  /// built-in ones); a law that is not must override it.
  virtual double largestSpeed(double k, double dMin, double dMax, const double *d, int n) const;

  /// A law may have one shape parameter (power: the exponent m) that
  /// rcfd calibrate scans; `option` is its option without the prefix.
  struct ShapeParameter {
    std::string option;
    double low = 0.0, high = 0.0; // the range a calibration scans
    double value = 0.0;           // the law's current value
  };
  /// False for a law without one (the default).
  virtual bool shapeParameter(ShapeParameter *) const { return false; }
  /// Sets it (a value in the range the option accepts).
  virtual void setShapeParameter(double) {}

protected:
  std::string prefix;
};

using SizeLawFactory = std::function<std::unique_ptr<SizeLaw>()>;

/// Name -> factory of size laws (owned by an OperatorRegistry, or by a
/// DriftOperator made without one).
class SizeLawRegistry : public Registry<SizeLaw> {
public:
  SizeLawRegistry() : Registry("-drift_size_law", "size law") {}
  /// A, B, drag, log and power.
  static SizeLawRegistry withBuiltins();
};

} // namespace rcfd
