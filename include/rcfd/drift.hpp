// Fractional drift relative to the bulk (paper Eq. 4-6) by face swaps along
// gravity.  See docs/drift.md for the derivation, the limiter and the
// sub-step rule.
#pragma once

#include "rcfd/size_law.hpp"
#include "rcfd/swap_operator.hpp"

#include <algorithm>
#include <memory>
#include <vector>

namespace rcfd {

class AgitationField;
class MeasuredDriftField;

/// Drift of each fraction along -gravity by a registered size law
/// (rcfd/size_law.hpp): u_d,i = k_d g(d_i, d32), e.g. -k_d (d_i^2 - d32^2)
/// (law A), -k_d (d_i - d32)|d_i - d32| (law B, the default), k_d (d32/d_i -
/// 1) (drag); or given velocities (model constant); positive is upward.
/// Each face swaps equal bulk masses, so every cell keeps the bulk solid mass
/// the database gives it and only its composition changes.  Options (prefix
/// drift_): -drift_size_law NAME, -drift_model A|B|constant|none (A and B:
/// the laws of those names), -drift_kd [the law's unit], -drift_velocities
/// [m/s per fraction], -drift_d32 [m] (override), -drift_local_d32,
/// -drift_hindered, -drift_alpha_max, -drift_alpha_min, -drift_max_share,
/// -drift_model measured (the database's measured velocities per frame and
/// region, rcfd/measured_drift_field.hpp),
/// -drift_max_substeps, -drift_every N (the drift of N steps every N steps),
/// -drift_agitation, -drift_agitation_exponent, -drift_agitation_reference,
/// -drift_view [viewer].
class DriftOperator : public SwapOperator {
public:
  /// SizeLaw: u from the size law (A, B, drag, ...); Constant: given velocities.
  /// Measured: the velocities the particle data show per frame and region
  /// (rcfd/measured_drift_field.hpp, -drift_model measured).
  enum class Model { SizeLaw, Constant, None, Measured };
  /// Knows the built-in size laws.
  DriftOperator();
  /// Knows the given laws (e.g. an OperatorRegistry's sizeLaws()).
  explicit DriftOperator(SizeLawRegistry laws);
  ~DriftOperator() override;
  std::string type() const override { return "drift"; }
  PetscErrorCode setFromOptions(MPI_Comm comm) override;
  bool needed(const RunContext &ctx) const override;
  PetscErrorCode apply(const StepInfo &step, FractionState &state) override;
  PetscErrorCode view(PetscViewer viewer) const override;
  /// A swapped mass carries its sending cell's scalar values (docs/scalars.md).
  bool carriesScalars() const override { return true; }
  /// Before setUp (setFromOptions reads -drift_model and -drift_kd over these).
  void setModel(Model m) { model = m; }
  void setKd(double value) { kd = value, kdGiven = true; }
  /// Before setUp: the size law of that name (and Model::SizeLaw), with its
  /// default parameters; an unknown name is refused with the known ones.
  PetscErrorCode setSizeLaw(const std::string &name);
  const std::string &sizeLawName() const { return lawName; }
  /// The size law (null for models constant and none); its shape parameter
  /// may be set before setUp.
  SizeLaw *sizeLaw() { return model == Model::SizeLaw ? law.get() : nullptr; }
  /// Before setUp: scale by this field (already set up on the run's database)
  /// instead of one made from -drift_agitation; shares one field between runs.
  void useAgitation(std::shared_ptr<const AgitationField> field) { agitation = std::move(field); }
  void setAgitationExponent(double n) { agitationExponent = n; }
  /// The measure -drift_agitation names ("none", "leaving", "dispersion"),
  /// after setFromOptions: runs that share a database can share its field
  /// (useAgitation), as a batch of candidates does.
  const std::string &agitationOption() const { return agitationName; }
  /// The solid-weighted mean of the factor (a/a_bar)^n over the occupied
  /// cells of all frames (1 when unscaled), once set up: a law scaled so
  /// drifts on average k_d / this as fast as the unscaled one.
  double meanAgitationFactor() const { return meanFactor; }
  /// The field the drift is scaled by (null when unscaled), once set up.
  std::shared_ptr<const AgitationField> agitationField() const { return agitation; }

  /// -drift_every N: the drift acts at the end of every N-th step (1: every step).
  PetscInt applyEvery() const { return every; }

  /// Drift velocity [m/s, up positive] of fraction i for a given Sauter diameter.
  double velocity(int i, double d32) const;
  /// The denominator of the agitation factor (a/a_ref)^n, once set up: the
  /// database's own a_bar, or -drift_agitation_reference (times dt_rec for
  /// the leaving share, whose reference is a rate in 1/s).
  double agitationNormaliser() const { return normaliser; }
  /// The bed's factor on every drift velocity, once set up: u_sup - u_mf in
  /// m/s with -drift_excess_gas (0 when the bed is not fluidized), else 1.
  double excessGasFactor() const { return gasFactor; }

private:
  FaceChoice swapFaces(const RunContext &ctx) const override;
  PetscErrorCode setUpSwap(const RunContext &ctx) override;
  PetscErrorCode substep(double dt, const double *scale, FractionState &state);
  PetscErrorCode substepsFor(double dt, double largestScale, int *n) const;
  PetscErrorCode setUpScaling(const RunContext &ctx);
  PetscErrorCode setUpExcessGas(const RunContext &ctx);
  /// u_sup - u_mf at the conditions `now` (a schedule's or a live file's u_sup),
  /// and the velocities that follow from it.
  PetscErrorCode excessGasAt(const OperatingConditions &now);
  void setUpVelocities();
  std::string kdUnit() const;
  // u of every fraction [m/s] for the reference diameter dRef.
  void velocitiesAt(double dRef, double *u) const;
  void setUpTables();
  template <int NF> PetscErrorCode sweep(double dt, const double *scale); // NF = 0: nf read at run time

  // The sweep's tables, made once (setUpSwap): each face's two cells and
  // area / volume on each side; each gathered cell's masses at alpha_min and
  // at alpha_max; each fraction's upward and downward speed with the fixed
  // d32 (u and -u where positive, else 0).
  struct DriftFace {
    PetscInt lower, upper;
    double areaOverVolumeLower, areaOverVolumeUpper;
  };
  // The larger index of a face's own cells (ghosts come after the own cells).
  static PetscInt lastOwnCell(const DriftFace &f, PetscInt own) {
    return f.lower < own ? (f.upper < own ? std::max(f.lower, f.upper) : f.lower) : f.upper;
  }
  std::vector<DriftFace> driftFaces; // in the order of lastOwnCell()
  std::vector<double> dilute, packed, fixedUp, fixedDown;
  // Per sub-step, per gathered cell: whether it swaps (solid at
  // or above alpha_min), its sums, and with the local d32 its speeds.
  struct CellSums {
    double mass, inverseMass; // M and 1 / M
    double rate; // dt times the agitation and hindrance factors
    double up, down; // sum over fractions of m_i times the upward / downward speed
  };
  std::vector<CellSums> cellSums;
  std::vector<unsigned char> live;
  std::vector<double> cellUp, cellDown; // nf per gathered cell, -drift_local_d32 only
  // One past the last own cell that may hold mass: the state's bound before
  // a sweep, the last cell found holding any after it (a swap only moves
  // mass between two cells that hold some).
  PetscInt occupiedEnd = 0;

  SizeLawRegistry known;
  Model model = Model::SizeLaw;
  std::string lawName = "B";
  std::unique_ptr<SizeLaw> law;
  bool kdGiven = false; // else the law's default k (setFromOptions)
  double kd = 5e3, d32Override = -1.0, alphaMax = 0.65, alphaMin = 1e-3, maxShare = 0.5;
  PetscBool localD32 = PETSC_FALSE, hindered = PETSC_FALSE;
  PetscInt substepLimit = 10000, every = 1;
  std::vector<double> constantVelocity, diameter, velocityCache;
  double d32 = 0.0;
  // Agitation scaling: the measure's name ("none": unscaled), the exponent,
  // the field, and per frame the factor (a/a_bar)^n of every gathered cell
  // and its largest value over all ranks (for the sub-step rule).
  std::string agitationName = "none";
  double agitationExponent = 1.0;
  double agitationReference = 0.0; // -drift_agitation_reference (0: the database's a_bar)
  // -drift_excess_gas: every velocity times u_sup - u_mf [m/s] of the bed
  // (u_mf of the inventory's d32 by -umf_correlation in the run's gas), so
  // that k_d is per m/s of excess gas; the case's conditions as given
  // (NaN where not) and what set-up resolved.
  PetscBool excessGas = PETSC_FALSE;
  OperatingConditions givenConditions;
  std::string umfCorrelation = "wen-yu";
  double gasFactor = 1.0, gasUsup = 0.0, gasUmf = 0.0, gasSauter = 0.0;
  double gasGravity = 0.0, gasSolidDensity = 0.0;
  double followedUsup = 0.0; // the run's u_sup the factor was last worked out for
  std::string usupSource;
  double normaliser = 1.0;
  std::shared_ptr<const AgitationField> agitation;
  std::vector<std::vector<double>> scaleByFrame;
  std::vector<double> largestScaleByFrame;
  double meanFactor = 1.0;
  // -drift_model measured: the database's field, and the largest |u| of the
  // step's frame (for the sub-step rule).
  std::shared_ptr<MeasuredDriftField> measured;
  double measuredSpeed = 0.0;
};

} // namespace rcfd
