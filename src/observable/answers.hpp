// The answers a user runs rcfd for (paper Sec. 3, docs/answers.md), as
// monitors a case asks for by option; a case that asks for none gets none and
// pays nothing.  All decisions (the warning, the halves' split) are taken from
// globally reduced numbers, so every rank and every rank count agree.
//
//   -observables_every N        steps between samples of the monitors below (default 1)
//   -profiles                   profiles.csv: each fraction's alpha and alpha_s per cell layer,
//   -profiles_window t0,t1        averaged over [t0, t1] s (default: the last second of the run)
//   -halves                     halves.csv: mass fraction of each class below and above the split,
//   -halves_window t0,t1          averaged over the window (default: the last second)
//   -halves_split median|H        split at the mass-median layer (default) or at height H [m]
//   -bottom_layer               bottom.csv: Sauter diameter of the bottom cell layer (and of each
//                                 zone of -zones), u_mf, u_sup, de-fluidized flag; warning once
//   -umf_correlation NAME       wen-yu (default), richardson, saxena-vogel, grace, chitester
//   -superficial_velocity, -gas_density, -gas_kinematic_viscosity: case > database > default
//   -mixing_index               mixing.csv: Lacey's index of each fraction over time
//   -bed_dynamics               bed_dynamics.csv: mean z_CoG and Delta z_CoG of the run
//   -snapshots_times t1,t2,...  snapshot_<t>s.csv: each fraction's alpha in the mid-plane
#pragma once

#include "database/fluidization_model.hpp"
#include "state/layer_masses.hpp"
#include "rcfd/observables.hpp"
#include "rcfd/zone.hpp"

#include <memory>

namespace rcfd {

/// %g as C prints it (PETSc's own %g adds a trailing dot to whole numbers), for messages.
std::string plain(double value);

/// A closed time interval [begin, end] in seconds; NaN ends mean "the last
/// second of the run" until resolved.
struct TimeWindow {
  double begin = std::numeric_limits<double>::quiet_NaN();
  double end = std::numeric_limits<double>::quiet_NaN();
  /// The last second of [0, tEnd] when the window was not given.
  void resolve(double tEnd);
  /// Inclusive, with a tolerance far below any time step.
  bool contains(double t) const;
};

/// The masses per horizontal layer of the current state, computed once per
/// step however many monitors ask (one pass, one reduction).
class LayerSampler {
public:
  PetscErrorCode setUp(const Database &db) { return layers.setUp(db); }
  const HorizontalLayers &geometry() const { return layers; }
  /// Collective: [l * nf + i], the same on every rank.
  PetscErrorCode masses(const MonitorContext &ctx, const std::vector<double> **perLayer);
  /// Collective, with scalars (docs/scalars.md): their amounts per layer,
  /// [(l * ns + s) * nf + i], the same on every rank (a pass and a reduction per step).
  PetscErrorCode amounts(const MonitorContext &ctx, const std::vector<double> **perLayer);

private:
  HorizontalLayers layers;
  long cachedStep = -1, cachedAmountStep = -1;
  double cachedTime = 0.0, cachedAmountTime = 0.0;
  std::vector<double> cached, cachedAmounts;
};

/// profiles.csv: the window mean of each fraction's volume fraction per cell
/// layer (its mass / (rho_p V_layer)) and their sum alpha_total, in the layout
/// of rcfd reference's profiles.csv; with scalars, then a column per scalar:
/// its value in the layer, mass-weighted over the classes and the window.
class ProfilesMonitor final : public Monitor {
public:
  ProfilesMonitor(std::shared_ptr<LayerSampler> sampler, TimeWindow window)
      : sampler(std::move(sampler)), window(window) {}
  PetscErrorCode setUp(const RunContext &run, const FractionState &, const std::string &dir) override;
  PetscErrorCode sample(const MonitorContext &ctx) override;
  PetscErrorCode flush() override;
  std::vector<double> saveState() const override;
  PetscErrorCode restoreState(const std::vector<double> &state) override;

private:
  std::shared_ptr<LayerSampler> sampler;
  TimeWindow window;
  MPI_Comm comm = MPI_COMM_NULL;
  const FractionSet *fractions = nullptr;
  double rho = 0.0;
  std::string path;
  double count = 0.0;       // samples in the window
  std::vector<double> sums; // [l * nf + i] summed masses [kg]
  std::vector<std::string> scalars; // their names; none without -scalars
  std::vector<double> amountSums;   // [l * ns + s] summed over the classes
};

/// halves.csv: the window mean of each class's mass fraction in the bottom
/// half (layers up to the split) and the top half, with d_i / d32 of the
/// inventory; the layout of rcfd reference's halves.csv plus that column.
/// With scalars, then per scalar the class's value in the bottom and the top
/// half (bottom_NAME, top_NAME), mass-weighted over the window.
class HalvesMonitor final : public Monitor {
public:
  /// splitHeight NaN: split at the mass-median layer of each sample.
  HalvesMonitor(std::shared_ptr<LayerSampler> sampler, TimeWindow window, double splitHeight)
      : sampler(std::move(sampler)), window(window), splitHeight(splitHeight) {}
  PetscErrorCode setUp(const RunContext &run, const FractionState &, const std::string &dir) override;
  PetscErrorCode sample(const MonitorContext &ctx) override;
  PetscErrorCode flush() override;
  std::vector<double> saveState() const override;
  PetscErrorCode restoreState(const std::vector<double> &state) override;

private:
  std::shared_ptr<LayerSampler> sampler;
  TimeWindow window;
  double splitHeight;
  int fixedSplit = -1; // layer index of splitHeight
  MPI_Comm comm = MPI_COMM_NULL;
  const FractionSet *fractions = nullptr;
  std::string path;
  double count = 0.0;
  std::vector<double> bottomSum, topSum;
  std::vector<std::string> scalars; // their names; none without -scalars
  // With scalars: each half's summed masses [i] and amounts [s * nf + i].
  std::vector<double> bottomMass, topMass, bottomAmount, topAmount;
};

/// bottom.csv: time_s,d32_bottom_m,umf_m_s,usup_m_s,defluidized[,d32_<zone>_m...]
/// The warning is printed once, on rank 0, the first time u_mf of the bottom
/// layer reaches u_sup; `defluidized` is 1 in every row where it has.  The
/// conditions are resolved at every sample against the database in use
/// (RunContext::operatingConditions) by `model`, so they follow a run's switches
/// (docs/databases.md) and agree with the switcher's umf_usup.
class BottomLayerMonitor final : public Monitor {
public:
  BottomLayerMonitor(std::shared_ptr<LayerSampler> sampler, FluidizationModel model, const ZoneSet *zones, bool quiet)
      : sampler(std::move(sampler)), model(std::move(model)), zones(zones), quiet(quiet) {}
  /// Fixed conditions, whatever the database says.
  BottomLayerMonitor(std::shared_ptr<LayerSampler> sampler, UmfCorrelation correlation, GasProperties gas,
                     double superficialVelocity, const ZoneSet *zones, bool quiet)
      : BottomLayerMonitor(std::move(sampler),
                           FluidizationModel{OperatingConditions{superficialVelocity, gas.density,
                                                                 gas.kinematicViscosity},
                                             std::move(correlation)},
                           zones, quiet) {}
  PetscErrorCode setUp(const RunContext &run, const FractionState &, const std::string &dir) override;
  PetscErrorCode sample(const MonitorContext &ctx) override;
  PetscErrorCode flush() override;
  std::vector<double> saveState() const override;
  PetscErrorCode restoreState(const std::vector<double> &state) override;
  const DefluidizationDetector &warning() const { return detector; }
  /// The latest row of bottom.csv's first five columns (time, d32, u_mf, u_sup,
  /// de-fluidized), empty before the first sample: the status page's.
  const std::vector<double> &latestRow() const { return latest; }
  /// With a scalar named moisture (docs/scalars.md): bottom.csv gains the
  /// bottom layer's moisture (moisture_bottom, kg per kg solid), and a warning
  /// is printed once when it passes `threshold` (> 0) while u_mf of the bottom
  /// layer is at least `umfShare` of u_sup (near de-fluidization by size).
  void setMoistureWarning(double threshold, double umfShare) { wetThreshold = threshold, nearShare = umfShare; }
  /// With a scalar named moisture and kappa > 0 (docs/scalars.md, "Wet bottom"): the bottom layer's
  /// u_mf raised by its moisture X, u_mf,wet = u_mf (1 + kappa X); bottom.csv gains umf_wet_m_s and
  /// the de-fluidization flag and warning use it (u_mf by size stays in umf_m_s).
  void setMoistureUmf(double kappa) { wetUmf = kappa; }
  /// Time of the moisture warning [s] (NaN: not given).
  double wetSince() const { return wetTime; }
  /// Its threshold [kg/kg] and u_mf's share of u_sup (0: no warning).
  double wetThresholdValue() const { return wetThreshold; }
  double wetUmfShare() const { return nearShare; }

private:
  int moisture = -1, ns = 0; // the moisture's column among the scalars, their number
  double wetThreshold = 0.0, nearShare = 0.8, wetTime = std::numeric_limits<double>::quiet_NaN();
  double wetUmf = 0.0; // kappa of u_mf (1 + kappa X); 0: u_mf by size alone
  std::shared_ptr<LayerSampler> sampler;
  FluidizationModel model; // the case's conditions (NaN: the database's in use) and correlation
  DefluidizationDetector detector;
  std::vector<double> latest;
  const ZoneSet *zones;
  bool quiet;
  MPI_Comm comm = MPI_COMM_NULL;
  const FractionSet *fractions = nullptr;
  double rhoP = 0.0, gravity = 0.0;
  std::unique_ptr<CsvSeries> csv;
};

/// mixing.csv: time_s,lacey_<label>... (observable/mixing_index.hpp, docs/answers.md).
/// n_c of a cell = its solid volume / the mean particle volume of the inventory,
/// 1 / sum_i (w_i / v_i) with w_i the mass shares and v_i = pi d_i^3 / 6.
class MixingMonitor final : public Monitor {
public:
  std::string type() const override { return "mixing_index"; }
  PetscErrorCode setUp(const RunContext &run, const FractionState &, const std::string &dir) override;
  PetscErrorCode sample(const MonitorContext &ctx) override;
  PetscErrorCode flush() override;
  /// State: the length of mixing.csv.
  std::vector<double> saveState() const override { return csv->state(); }
  PetscErrorCode restoreState(const std::vector<double> &state) override;

private:
  MPI_Comm comm = MPI_COMM_NULL;
  int nf = 0;
  double meanParticleVolume = 0.0, rho = 0.0;
  std::unique_ptr<CsvSeries> csv;
};

/// bed_dynamics.csv: the bed's centre of gravity at every sample gives its
/// mean and Delta z_CoG = mean |z_CoG - mean z_CoG| (observable/bed_dynamics.hpp),
/// printed at the end of the run.
class BedDynamicsMonitor final : public Monitor {
public:
  explicit BedDynamicsMonitor(std::shared_ptr<LayerSampler> sampler, bool quiet)
      : sampler(std::move(sampler)), quiet(quiet) {}
  PetscErrorCode setUp(const RunContext &run, const FractionState &, const std::string &dir) override;
  PetscErrorCode sample(const MonitorContext &ctx) override;
  PetscErrorCode flush() override;
  std::vector<double> saveState() const override { return zBed; }
  PetscErrorCode restoreState(const std::vector<double> &state) override;

private:
  std::shared_ptr<LayerSampler> sampler;
  bool quiet;
  MPI_Comm comm = MPI_COMM_NULL;
  int nf = 0;
  std::string path;
  std::vector<double> zBed;
};

/// snapshot_<t>s.csv at the chosen times: each fraction's alpha and
/// alpha_total in the vertical mid-plane (the middle cell layer across the
/// horizontal axis with fewer cells), one row per cell, bottom row first.
class SnapshotMonitor final : public Monitor {
public:
  explicit SnapshotMonitor(std::vector<double> times) : times(std::move(times)) {}
  PetscErrorCode setUp(const RunContext &run, const FractionState &, const std::string &dir) override;
  PetscErrorCode sample(const MonitorContext &ctx) override;

private:
  std::vector<double> times;
  std::vector<long> steps; // step of each time
  MPI_Comm comm = MPI_COMM_NULL;
  const FractionSet *fractions = nullptr;
  std::string directory, header;
  std::vector<PetscInt> planeCells;       // local indices of this rank's cells in the plane
  std::vector<double> planeCoordinates;   // (across, up) of each
  std::vector<double> planeVolumes;
  double rho = 0.0;
};

/// The options above, and the monitors they ask for.
class Answers {
public:
  /// Collective: reads the options (and -zones); refuses bad values with a sentence.
  PetscErrorCode setFromOptions(MPI_Comm comm);
  /// Collective: resolves the windows against the run's end time, the operating
  /// conditions (case > database > default, printed unless quiet when the bottom
  /// layer is watched) and the zones; appends the monitors asked for.
  struct Named {
    std::unique_ptr<Monitor> monitor;
    long every;
    std::string name;
  };
  PetscErrorCode createMonitors(const RunContext &run, double tEnd, bool quiet, std::vector<Named> *out);
  PetscErrorCode view(PetscViewer viewer) const;
  /// The case's conditions and u_mf correlation (after setFromOptions), which
  /// the switcher's umf_usup uses as the bottom layer does.
  const FluidizationModel &fluidization() const { return fluidization_; }
  /// -moisture_warning [kg/kg] (0: off) and -moisture_warning_umf_share: the wet-bottom warning's.
  double moistureWarningThreshold() const { return moistureWarning; }
  double moistureWarningUmfShare() const { return moistureUmfShare; }

private:
  MPI_Comm comm = MPI_COMM_NULL;
  PetscInt every = 1;
  double moistureWarning = 0.0, moistureUmfShare = 0.8; // -moisture_warning, -moisture_warning_umf_share
  double moistureUmf = 0.0;                              // -moisture_umf_coefficient
  PetscBool profiles = PETSC_FALSE, halves = PETSC_FALSE, bottom = PETSC_FALSE, mixing = PETSC_FALSE,
            dynamics = PETSC_FALSE;
  TimeWindow profilesWindow, halvesWindow;
  double splitHeight = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> snapshotTimes;
  FluidizationModel fluidization_; // -superficial_velocity, -gas_*, -umf_correlation
  OperatingConditions used;
  std::string sources[3]; // where u_sup, rho_g, nu came from
  ZoneSet zones;
};

} // namespace rcfd
