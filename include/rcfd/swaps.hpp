// Face-swap operators: fractional drift relative to the bulk (paper Eq. 4-6)
// and symmetric dispersion.  Both exchange equal bulk masses across a face,
// so every cell keeps the bulk solid mass the database gives it; they only
// change its composition.  See docs/drift.md for the derivation, the limiter
// and the sub-step rule.
#pragma once

#include "rcfd/operator.hpp"

#include <memory>
#include <vector>

namespace rcfd {

class FaceExchange;

/// Drift of each fraction along -gravity: u_d,i = -k_d (d_i^2 - d32^2)
/// (model A), -k_d (d_i - d32)|d_i - d32| (model B), or given velocities
/// (model constant); positive is upward.  Options (prefix drift_):
/// -drift_model A|B|constant|none, -drift_kd [1/(m s)], -drift_velocities
/// [m/s per fraction], -drift_d32 [m] (override), -drift_local_d32,
/// -drift_hindered, -drift_alpha_max, -drift_alpha_min, -drift_max_share,
/// -drift_max_substeps, -drift_every N (the drift of N steps every N steps),
/// -drift_view.
class DriftOperator : public Operator {
public:
  DriftOperator();
  ~DriftOperator() override;
  std::string type() const override { return "drift"; }
  PetscErrorCode setFromOptions(MPI_Comm comm) override;
  bool needed(const RunContext &ctx) const override;
  PetscErrorCode setUp(const RunContext &ctx) override;
  PetscErrorCode apply(const StepInfo &step, FractionState &state) override;
  PetscErrorCode view(PetscViewer viewer) const override;

  enum class Model { A, B, Constant, None };
  /// Override -drift_model and -drift_kd (after setFromOptions, before setUp; rcfd calibrate).
  void setModel(Model m) { model = m; }
  void setKd(double k) { kd = k; }
  /// Drift velocity [m/s, up positive] of fraction i for a given Sauter diameter.
  double velocity(int i, double d32) const;
  /// Statistics: steps taken and sub-steps used.
  long stepsTaken() const { return steps; }
  long substepsTaken() const { return substeps; }
  int maxSubsteps() const { return mostSubsteps; }

private:
  PetscErrorCode substep(double dt, FractionState &state);
  PetscErrorCode substepsFor(double dt, FractionState &state, int *n);
  template <int NF> void sweep(double dt); // NF = 0: nf read at run time

  Model model = Model::B;
  double kd = 5e3, d32Override = -1.0, alphaMax = 0.65, alphaMin = 1e-3, maxShare = 0.5;
  PetscBool localD32 = PETSC_FALSE, hindered = PETSC_FALSE;
  PetscInt substepLimit = 10000, every = 1;
  std::vector<double> constantVelocity, diameter, velocityCache;
  double d32 = 0.0, rho = 0.0;
  int nf = 0;
  std::unique_ptr<FaceExchange> exchange;
  MPI_Comm comm = MPI_COMM_NULL;
  long steps = 0, substeps = 0;
  int mostSubsteps = 0;
};

/// Symmetric exchange of mixture across every internal face: each side sends
/// X = rho_s alpha_face D A dt / delta of its own composition, which
/// diffuses composition but not bulk mass.  Options (prefix dispersion_):
/// -dispersion_coefficient D [m^2/s], -dispersion_alpha_min.
class DispersionOperator : public Operator {
public:
  DispersionOperator();
  ~DispersionOperator() override;
  std::string type() const override { return "dispersion"; }
  PetscErrorCode setFromOptions(MPI_Comm comm) override;
  bool needed(const RunContext &ctx) const override;
  PetscErrorCode setUp(const RunContext &ctx) override;
  PetscErrorCode apply(const StepInfo &step, FractionState &state) override;
  PetscErrorCode view(PetscViewer viewer) const override;

private:
  double coefficient = 0.0, alphaMin = 1e-3, rho = 0.0;
  int nf = 0;
  std::vector<double> faceDistance;
  std::unique_ptr<FaceExchange> exchange;
  MPI_Comm comm = MPI_COMM_NULL;
  long substeps = 0, steps = 0;
};

/// Carries the state across a jump between frames: after a step whose next
/// frame does not follow its frame (a stitching jump, or replay wrapping),
/// the state's bulk mass per cell differs from the next frame's alpha_s.
///  - remap (default): every cell keeps its composition (mass shares of the
///    fractions; a cell that was empty takes its neighbours') and takes the
///    next frame's bulk mass; one factor per fraction, the same in every
///    cell, then restores each fraction's total exactly.
///  - level: sweeps move mixture from over- to under-filled neighbours
///    (strictly local, but it cannot move mass far: bubbles in other places
///    leave a large mismatch).
/// Both keep every fraction's total and never make a mass negative.
/// Options (prefix carry_): -carry_type remap|level, -carry_sweeps (level,
/// per jump, default 20).  See docs/paths.md.
class CarryOperator : public Operator {
public:
  CarryOperator();
  ~CarryOperator() override;
  std::string type() const override { return "carry"; }
  PetscErrorCode setFromOptions(MPI_Comm comm) override;
  bool needed(const RunContext &ctx) const override;
  PetscErrorCode setUp(const RunContext &ctx) override;
  PetscErrorCode apply(const StepInfo &step, FractionState &state) override;
  PetscErrorCode view(PetscViewer viewer) const override;

private:
  PetscErrorCode sweep(const std::vector<double> &targetAlpha, FractionState &state);
  PetscErrorCode remap(Vec targetAlpha, FractionState &state);
  const Database *db = nullptr;
  std::string kind = "remap";
  PetscInt sweeps = 20, sweepsPerStep = 0;
  double rho = 0.0;
  int nf = 0;
  std::unique_ptr<FaceExchange> exchange;
  long jumps = 0, totalSweeps = 0;
};

} // namespace rcfd
