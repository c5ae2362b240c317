// A granulation chamber (paper Sec. 3.4, Fig. 7): growth in a spray zone and
// a continuous through-flow, fed into one zone and discharged from another.
// Three operators, registered as `growth`, `feed` and `discharge`:
//   -pipeline shift,drift,carry,growth,feed,discharge
// Each acts in a named zone (rcfd/zone.hpp: -zones spray,feed,discharge with
// -zone_<name>_box ...), reads its own options (prefixes growth_, feed_,
// discharge_) and keeps an exact ledger: the mass it has added to each
// fraction (Operator::addedMass), so that the run's mass ledger keeps
// checking every fraction and mass_account.csv closes per fraction to
// round-off.  Their state (ledgers, mass held back) is in checkpoints.
// docs/granulation.md has the model, its reading of the paper and the files.
#pragma once

#include "rcfd/operator.hpp"
#include "rcfd/zone.hpp"

#include <memory>
#include <string>
#include <vector>

namespace rcfd {

/// What the three granulation operators share: a zone given by name
/// (-<prefix>zone NAME) and resolved at set-up, and the ledger of the mass
/// added to each fraction.  A zone that holds no solid in any frame of the
/// database is refused at set-up, naming the zone.
class ZoneOperator : public Operator {
public:
  bool conservesMass() const override { return false; }
  const std::vector<double> *addedMass() const override { return &added; }
  /// The scalars (docs/scalars.md) move with the mass: growth moves a class's
  /// amount with the mass it moves, the feed brings its own values
  /// (-feed_scalar_NAME), the discharge takes the cell's; what they add or
  /// remove is accounted per scalar and fraction (addedAmounts).
  bool carriesScalars() const override { return true; }
  const std::vector<double> *addedAmounts() const override { return ns > 0 ? &addedAmount : nullptr; }
  const std::string &zoneName() const { return zoneName_; }
  /// Frames of the database in which the zone holds no solid.
  int emptyFrames() const { return emptyFrames_; }

protected:
  explicit ZoneOperator(std::string defaultZone) : zoneName_(std::move(defaultZone)) {}
  /// Inside the operator's options block: reads -<prefix>zone and -zones.
  PetscErrorCode readZone(PetscOptionItems *PetscOptionsObject, MPI_Comm comm);
  /// Resolves the zone on the mesh and checks it holds solid in some frame.
  PetscErrorCode setUpZone(const RunContext &ctx);
  /// Collective, one reduction.  Mass of each fraction in the zone's cells
  /// (global) into `perFraction` (nf numbers) and their sum into *total; the
  /// bed's totals before this operator into *bed when they are known
  /// (knownBed) or `needBed` (then summed, in the same reduction; free when
  /// the last writer said them, FractionState::setLocalTotals); *bedValid
  /// says whether *bed holds them.  The same reduction carries what the zone
  /// operator before left to reduce (carryOn) and, for the one after, its
  /// zone's sums (forNext).
  PetscErrorCode zoneMasses(const StepInfo &step, const FractionState &state, std::vector<double> *perFraction,
                            double *total, std::vector<double> *bed, bool needBed, bool *bedValid);
  /// Leaves this rank's `sums` to the next zone operator's reduction (one
  /// meeting for two); it calls sumsReduced() with the global sums before it
  /// reads the bed's totals.  False when there is no next zone operator: the
  /// caller reduces them itself.
  bool carryOn(const StepInfo &step, std::vector<double> sums, bool leavesBed);
  virtual PetscErrorCode sumsReduced(const StepInfo &step, const double *global);
  /// The zone's sums (global, per fraction) the zone operator before reduced
  /// for this one at this step, before its own change (its rescale owed on
  /// top), or false.
  bool presummed(const StepInfo &step, std::vector<double> *perFraction) const;
  /// One line: the zone and its cells, the frames in which it is empty, and
  /// (`bulkNote`, for feed and discharge) whether its cells keep their bulk.
  PetscErrorCode viewZone(PetscViewer viewer, bool bulkNote) const;
  /// Reads -<prefix>keep_bulk inside the options block.
  PetscErrorCode readKeepBulk(PetscOptionItems *PetscOptionsObject);
  /// Keeping the bulk (-keep_bulk), once the operator has scaled each zone
  /// cell back to its bulk: the factor of every fraction of the whole bed,
  /// s_i = (bed_i + change_i) / (bed_i + zoneChange_i), that makes the
  /// totals what the ledger expects.  `bed`: the totals before the operator;
  /// `change`: what it added (kg, per fraction); `zoneChange`: what its
  /// zone's cells gained, rescale included, which each operator knows from
  /// its zone's sums without reading the bed again.
  /// With scalars and -keep_bulk: the amounts' counterpart of the bed's
  /// rescale, one factor per scalar and fraction from the same rule as the
  /// masses' (bedFactors on the amounts' totals): `before` this rank's
  /// amounts before the operator (localAmountTotals), `zoneChange` what its
  /// zone's cells gained (local), `change` what it added (global).  Collective
  /// (one reduction); scales the amounts of the own cells below `end` (the
  /// occupied end before the operator: it put nothing into an empty cell).  A uniform scalar fed
  /// at its own value gets the masses' factors: it stays uniform.
  PetscErrorCode rescaleAmounts(FractionState &state, std::vector<double> before, const std::vector<double> &zoneChange,
                                const std::vector<double> &change, PetscInt end) const;
  /// The checkpoint's part of the amounts added (appended, and read back from `offset`).
  void saveAmounts(std::vector<double> *s) const { s->insert(s->end(), addedAmount.begin(), addedAmount.end()); }
  void restoreAmounts(const std::vector<double> &s, std::size_t offset) {
    addedAmount.assign(s.begin() + offset, s.begin() + offset + ns * nf);
  }
  static std::vector<double> bedFactors(const std::vector<double> &bed, const std::vector<double> &change,
                                        const std::vector<double> &zoneChange);
  /// Not collective.  Multiplies every fraction of the occupied cells by its
  /// factor (nothing when all are 1), and says the state's bound (`end`, the
  /// occupied end before the operator: it put no mass into an empty cell)
  /// and this rank's totals, summed in the same pass.  With `owed` (a
  /// rescale the operator before handed on, takeOwed()) the same pass first
  /// multiplies every occupied cell outside this operator's zone by it.
  PetscErrorCode scaleBed(FractionState &state, const std::vector<double> &factor, PetscInt end,
                          const std::vector<double> *owed = nullptr) const;

  /// The bed's totals (global, per fraction) just before this operator, when
  /// they are known without reading the bed: from the zone operator just
  /// before it (its bedAfter), or, for the first of the pipeline's operators
  /// that change mass, the run's ledger (StepInfo::expectedTotals).  They
  /// hold the state's totals up to round-off, which moves a factor s_i by
  /// round-off times the step's change over the bed (docs/granulation.md).
  bool knownBed(const StepInfo &step, std::vector<double> *bed) const;
  /// Says the bed's totals after this operator's step (known: before + change).
  void leaveBed(const StepInfo &step, std::vector<double> bed) { bedAfter = std::move(bed), bedStep = step.step; }
  /// Keeping the bulk with the operator after it settling the bed's rescale:
  /// instead of its own pass, the operator leaves `factor` owed (the state
  /// as it wrote it, with its bound), and the next one multiplies its own
  /// zone's cells by it before it reads them and the rest of the bed in its
  /// own pass (scaleBed's `owed`): one pass for two operators, same bits.
  bool defersRescale() const { return defers; }
  bool owedPending() const { return owed.pending; }
  bool carriedPending() const { return carried.pending; }
  void oweRescale(const StepInfo &step, const FractionState &state, std::vector<double> factor, PetscInt end);
  /// Not collective.  Takes the rescale the operator before left owed at this
  /// step, if any (*factor empty when none): its own zone's cells are scaled
  /// now; the caller passes `factor` to scaleBed for the rest and uses `end`.
  PetscErrorCode takeOwed(const StepInfo &step, FractionState &state, std::vector<double> *factor, PetscInt *end);
  /// Whether this operator takes a rescale the one before it left owed
  /// (the discharge keeping the bulk), and whether it may leave one (the feed).
  virtual bool settlesRescale() const { return false; }
  virtual bool mayDeferRescale() const { return false; }

  MPI_Comm comm = MPI_COMM_NULL;
  int nf = 0, ns = 0; // fractions, scalars
  std::string zoneName_;
  std::unique_ptr<Zone> zone;
  int emptyFrames_ = 0, frames = 0;
  std::vector<double> added; // [kg] per fraction since the start (removed: negative)
  std::vector<double> addedAmount; // [scalar][fraction] since the start (removed: negative)
  PetscBool keepBulk = PETSC_TRUE;

public:
  /// Collective.  Finds the zone operator just before it, whether the run's
  /// ledger gives it the bed's totals, and whether it settles that one's rescale.
  PetscErrorCode setUpInPipeline(const std::vector<Operator *> &before) override;

private:
  ZoneOperator *previous = nullptr; // the zone operator just before this one, if any
  bool ledgerTotals = false;        // StepInfo::expectedTotals hold the bed just before this operator
  bool defers = false;              // leaves its rescale to the next operator
  std::vector<double> bedAfter;     // the bed's totals after this operator's step bedStep
  long bedStep = -1;
  ZoneOperator *following = nullptr; // the zone operator just after this one, if any
  bool sumsForNext = false;           // reduces the following operator's zone sums with its own
  std::vector<double> nextSums;       // those, global, at step nextSumsStep
  long nextSumsStep = -1;
  struct Carried { // this rank's sums left to the following operator's reduction
    bool pending = false, leavesBed = false;
    long step = -1;
    std::vector<double> local;
  } carried;
  struct Owed { // the rescale left to the next operator
    bool pending = false;
    long step = -1;
    std::vector<double> factor;
    PetscInt end = 0;
    Vec of = nullptr;
    PetscObjectState state = 0;
  } owed;
};

/// Growth in the spray zone (-growth_zone, default "spray").  A global
/// granulation rate m_g (-growth_rate, kg/s) is shared by projected area:
/// cell c and class i get m_g,i,c = m_g N_i,c d_i^2 / sum_zone N d^2, i.e.
/// in proportion to m_i,c / d_i.  A fraction c_g (-growth_transfer_fraction,
/// 0.01) of it moves mass from class i to the next larger class each step:
/// T = c_g m_g,i,c dt, never more than the cell's class i holds.  The largest
/// class keeps what it receives (-growth_top closed, default), or its own
/// growth T leaves the bed as oversize (-growth_top open; oversize(); the
/// spray cells keep their bulk with -growth_keep_bulk, default, as feed and
/// discharge do).  -growth_mass says what
/// the moved particles weigh in the larger class:
///  - transfer (default, the paper): class i+1 receives T; the bed's mass and
///    each cell's bulk are kept (they are the database's); the particles
///    moved are fewer in number by (d_i/d_i+1)^3: the coating they would have
///    gained, T ((d_i+1/d_i)^3 - 1), is counted (impliedCoating()) but not added;
///  - number: class i+1 receives T (d_i+1/d_i)^3 (the particles keep their
///    number and gain that coating); the bed's mass grows and the bulk departs
///    from the database's alpha_s.
/// A step whose spray zone holds no solid grows nothing; the rate it would
/// have moved, c_g m_g dt, is counted as missed.
class GrowthOperator : public ZoneOperator {
public:
  enum class Mass { Transfer, Number };
  GrowthOperator() : ZoneOperator("spray") {}
  std::string type() const override { return "growth"; }
  PetscErrorCode setFromOptions(MPI_Comm comm) override;
  PetscErrorCode setUp(const RunContext &ctx) override;
  PetscErrorCode apply(const StepInfo &step, FractionState &state) override;
  PetscErrorCode view(PetscViewer viewer) const override;
  std::vector<double> saveState() const override;
  PetscErrorCode restoreState(const std::vector<double> &state) override;

  void setRate(double kgPerSecond, double transferFraction) { rate = kgPerSecond, fraction = transferFraction; }
  double growthRate() const { return rate; }
  double transferFraction() const { return fraction; }
  void setMass(Mass m) { mass = m; }
  /// Open top: the largest class's growth leaves the bed (before setUp).
  void setOpenTop(bool open) { openTop = open; }
  /// Mass that left the bed as oversize [kg] (open top; 0 when closed).
  double oversize() const { return oversizeMass; }
  /// Mass moved out of each class so far [kg] (the largest: 0 when closed, its oversize when open).
  const std::vector<double> &movedOut() const { return moved; }
  /// Mass that could not move because a cell's class held less [kg], and the
  /// mass that did not move because the spray zone was empty [kg].
  double limited() const { return limitedMass; }
  double missed() const { return missedMass; }
  /// Transfer mode: the coating the moved particles would carry [kg].
  double impliedCoating() const { return coating; }

private:
  double rate = 0.0, fraction = 0.01;
  Mass mass = Mass::Transfer;
  std::vector<double> diameter;
  std::vector<int> next; // next larger class of each, -1 for the largest
  std::vector<double> moved;
  double limitedMass = 0.0, missedMass = 0.0, coating = 0.0, oversizeMass = 0.0;
  long emptySteps = 0;
  bool openTop = false;
  bool bedKnown = false;         // the bed's totals before this step's transfers are known: bedBefore
  std::vector<double> bedBefore;
  /// The step's bookkeeping from the global sums moved per class (and the
  /// limited mass after them): moved, oversize, coating, added, limited;
  /// returns the change per class.
  /// `amountSums`: the amounts moved out of each scalar and class (global), which
  /// give the step's amountChange and addedAmounts.
  std::vector<double> account(const double *sums, const double *amountSums);
  /// Not collective.  Moves a cell's amounts with its masses' transfers `out`
  /// (computed from `cell`, the masses before them): each moved mass takes its
  /// class's value; adds what left each class to `moved`.
  void moveAmounts(const PetscScalar *cell, const std::vector<double> &out, PetscScalar *amount, double *moved);
  std::vector<double> amountChange, going; // [scalar][fraction]: the step's change, a cell's moving amounts
  PetscErrorCode sumsReduced(const StepInfo &step, const double *global) override;
};

/// Feed into the feed zone (-feed_zone, default "feed"): m_f (-feed_rate,
/// kg/s) split between the classes by -feed_mass_shares (default: the
/// inventory's mass shares, -fractions_mass_shares), and between the zone's
/// cells in proportion to the solid each holds.  A step whose feed zone holds
/// no solid holds the feed back (heldBack()); it is delivered, all of it, at
/// the next step whose zone holds solid.  Nothing is lost: delivered +
/// held back = m_f t for each class.
class FeedOperator : public ZoneOperator {
public:
  FeedOperator() : ZoneOperator("feed") {}
  std::string type() const override { return "feed"; }
  PetscErrorCode setFromOptions(MPI_Comm comm) override;
  PetscErrorCode setUp(const RunContext &ctx) override;
  PetscErrorCode apply(const StepInfo &step, FractionState &state) override;
  PetscErrorCode view(PetscViewer viewer) const override;
  std::vector<double> saveState() const override;
  PetscErrorCode restoreState(const std::vector<double> &state) override;
  bool mayDeferRescale() const override { return keepBulk; }

  /// Rate [kg/s] and shares (empty: the inventory's), before setUp; between steps
  /// (a live run, docs/live.md) with one share per fraction, summing to 1.
  void setFeed(double kgPerSecond, std::vector<double> massShares = {}) {
    rate = kgPerSecond, shares = std::move(massShares);
  }
  double feedRate() const { return rate; }
  const std::vector<double> &feedShares() const { return shares; }
  /// The feed's value of each scalar (-feed_scalar_NAME, read at setUp), or
  /// set here before setUp (one per scalar).
  void setScalarValues(std::vector<double> values) { scalarValues = std::move(values); }
  /// Feed not yet delivered, per class [kg].
  const std::vector<double> &heldBack() const { return held; }

private:
  double rate = 0.0;
  std::vector<double> shares, held, scalarValues;
  long heldSteps = 0;
};

/// Discharge from the discharge zone (-discharge_zone, default
/// "discharge"): m_d (-discharge_rate, kg/s; for a steady holdup the feed's)
/// taken from the zone's cells in proportion to the mass of each class in
/// each (the local concentrations).  Never more than the zone holds: a step
/// that asks for more takes all of it, and the rest is owed (taken at the
/// next steps, counted in owed() and limitedSteps()).  The product leaving
/// is written by its monitor, product.csv (discharged mass per class, the
/// product and holdup size distributions, the steady-state criterion) and
/// steady_state.csv.
class DischargeOperator : public ZoneOperator {
public:
  DischargeOperator() : ZoneOperator("discharge") {}
  std::string type() const override { return "discharge"; }
  PetscErrorCode setFromOptions(MPI_Comm comm) override;
  PetscErrorCode setUp(const RunContext &ctx) override;
  PetscErrorCode apply(const StepInfo &step, FractionState &state) override;
  PetscErrorCode view(PetscViewer viewer) const override;
  std::vector<double> saveState() const override;
  PetscErrorCode restoreState(const std::vector<double> &state) override;
  PetscErrorCode monitors(const RunContext &ctx, std::vector<OperatorMonitor> *list) override;
  bool settlesRescale() const override { return keepBulk; }

  void setRate(double kgPerSecond) { rate = kgPerSecond; }
  double dischargeRate() const { return rate; }
  /// Discharged so far, per class [kg] (= -addedMass()).
  std::vector<double> discharged() const;
  /// Discharged so far of each scalar, [scalar][fraction] (= -addedAmounts()):
  /// the product's value of a scalar is its amount over the discharged mass.
  std::vector<double> dischargedAmounts() const;
  /// Mass asked for but not yet taken because the zone held less [kg].
  double owed() const { return owedMass; }
  long limitedSteps() const { return limitedCount; }
  /// The product monitor's settings: seconds between rows, tolerance of the
  /// steady-state criterion.
  double sampleInterval() const { return interval; }
  double steadyTolerance() const { return tolerance; }

private:
  double rate = 0.0, owedMass = 0.0, interval = 1.0, tolerance = 0.02;
  long limitedCount = 0, emptySteps = 0;
};

} // namespace rcfd
