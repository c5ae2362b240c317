// Operators act on the fraction state once per recurrence step.  Every
// operator has PETSc's life cycle: create (by name, from a registry) ->
// setFromOptions -> setUp (re-entrant) -> apply ... -> view (-<prefix>view) ->
// destroy, as every extension point of rcfd (docs/extending.md).  Researchers add their own by
// registering a factory under a new name; `-pipeline shift,mine` then uses it.
// What an operator sees is in rcfd/operator_context.hpp; an operator that
// moves mass between neighbouring cells derives from SwapOperator
// (rcfd/swap_operator.hpp) and uses the FaceExchange (rcfd/face_exchange.hpp).
#pragma once

#include "rcfd/carry_kind.hpp"
#include "rcfd/operator_context.hpp"
#include "rcfd/registry.hpp"
#include "rcfd/size_law.hpp"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace rcfd {

class Monitor; // rcfd/observables.hpp

/// A monitor an operator brings along (Operator::monitors), e.g. the
/// discharge's product size distribution; `every` in steps as Run::addMonitor.
struct OperatorMonitor {
  std::unique_ptr<Monitor> monitor;
  long every = 1;
  std::string name;
};

class Operator {
public:
  virtual ~Operator() = default;
  /// Registered name of the implementation.
  virtual std::string type() const = 0;
  /// Options of this operator are read as -<prefix><name>; by default the
  /// prefix is "<type>_".
  void setOptionsPrefix(const std::string &p) { prefix = p; }
  const std::string &optionsPrefix() const { return prefix; }
  /// Collective.  Reads the operator's options (none by default).
  virtual PetscErrorCode setFromOptions(MPI_Comm comm);
  /// Whether this operator changes anything for the case; the pipeline
  /// leaves out operators that do not (no drift for one fraction, ...).
  virtual bool needed(const RunContext &) const { return true; }
  /// Collective.  Prepares the operator for ctx.db.  Re-entrant: a run on
  /// several databases calls it again on every switch (and the contract test
  /// calls it twice), so it rebuilds what it derives from the database and
  /// keeps what saveState() returns; two calls give the same operator.
  virtual PetscErrorCode setUp(const RunContext &ctx) = 0;
  /// Advance the state in place (an operator may work out of place on the
  /// state's scratch vector and swap).
  virtual PetscErrorCode apply(const StepInfo &step, FractionState &state) = 0;
  virtual PetscErrorCode view(PetscViewer viewer) const;
  /// False for operators that add or remove mass on purpose (feed,
  /// discharge, growth between classes); the run's mass ledger then only
  /// checks the conservative parts.
  virtual bool conservesMass() const { return true; }
  /// For an operator that changes mass on purpose (conservesMass() false):
  /// the mass [kg] it has added to each fraction since the run started
  /// (removed: negative), the same on every rank, kept across restarts by
  /// saveState().  The run's mass ledger adds it to its reference totals, so
  /// it keeps checking every fraction (-mass_check_every) and writes the
  /// balance per fraction to mass_account.csv.  nullptr (the default): the
  /// change is not accounted, and the run's mass ledger is off.
  virtual const std::vector<double> *addedMass() const { return nullptr; }
  /// Whether apply() moves the state's scalar amounts (FractionState::amounts(),
  /// docs/scalars.md) with the masses it moves: a run with -scalars refuses a
  /// pipeline with an operator that does not.  False by default.
  virtual bool carriesScalars() const { return false; }
  /// Checkpoint contract, as Monitor's: what the operator needs to continue a
  /// run exactly (its ledger, mass held back), the same on every rank; the
  /// run stores it under /operators/<type> and hands it back to
  /// restoreState() after setUp() on a restart.  The default saves nothing.
  virtual std::vector<double> saveState() const { return {}; }
  /// Collective.  The default refuses a non-empty state.
  virtual PetscErrorCode restoreState(const std::vector<double> &state);
  /// Collective, after setUp().  Appends the monitors this operator brings
  /// along to the run's list (the default brings none).
  virtual PetscErrorCode monitors(const RunContext &ctx, std::vector<OperatorMonitor> *list);
  /// Collective, called by the pipeline once every operator is set up: the
  /// operators that run before this one in each step, in order, so that an
  /// operator can share work with its neighbours (the granulation operators
  /// hand the bed's totals and a rescale on).  The default does nothing.
  virtual PetscErrorCode setUpInPipeline(const std::vector<Operator *> &before);
  /// For an operator that carries scalars and changes mass on purpose (feed,
  /// discharge, growth in the number reading): the amount of each scalar it
  /// has added to each fraction since the run started, [scalar][fraction]
  /// (removed: negative), the same on every rank, kept by saveState().  The
  /// scalars' ledger adds it to what it expects.  nullptr (the default): the
  /// operator moves amounts only as it moves mass, conserving them.  (Declared
  /// last, so that the other virtual functions keep their places.)
  virtual const std::vector<double> *addedAmounts() const { return nullptr; }

protected:
  std::string prefix;
};

using OperatorFactory = std::function<std::unique_ptr<Operator>()>;

/// Name -> factory of operators (-pipeline), and the carry kinds and size
/// laws the `carry` and `drift` operators choose from.  One registry per
/// program (no global state): the program makes one with the built-in
/// operators and users (or plugins, rcfd/plugin.hpp) add theirs to it, e.g.
///   PetscCall(registry.add("mydrift", [] { return std::make_unique<MyDrift>(); }, "my drift law"));
///   PetscCall(registry.carryKinds().add("mycarry", [] { return std::make_unique<MyCarry>(); }, "..."));
///   PetscCall(registry.sizeLaws().add("mylaw", [] { return std::make_unique<MyLaw>(); }, "..."));
/// then -pipeline shift,mydrift,carry -carry_type mycarry uses both, and
/// -pipeline shift,drift -drift_size_law mylaw the law.
class OperatorRegistry {
public:
  OperatorRegistry();
  /// A registry holding rcfd's built-in operators, carry kinds and size laws.
  static OperatorRegistry withBuiltins();
  /// Registers an operator (rcfd/registry.hpp: an identifier, not taken).
  PetscErrorCode add(const std::string &name, OperatorFactory factory, const std::string &help);
  /// Replaces a registered operator on purpose (rcfd/registry.hpp).
  PetscErrorCode replace(const std::string &name, OperatorFactory factory, const std::string &help);
  bool has(const std::string &name) const { return makers.has(name); }
  /// A new operator with options prefix "<name>_"; an unknown name is refused
  /// with the known names.
  PetscErrorCode create(const std::string &name, std::unique_ptr<Operator> *op) const;
  std::string listing() const { return makers.listing(); }
  std::vector<std::string> names() const { return makers.names(); }
  std::string help(const std::string &name) const { return makers.help(name); }
  /// Collective on the viewer: the operators, carry kinds and size laws with their help.
  PetscErrorCode view(PetscViewer viewer) const;
  /// The kinds a `carry` operator made by this registry knows (-carry_type);
  /// an operator copies them when it is created, so add kinds before.
  CarryKindRegistry &carryKinds() { return carry; }
  const CarryKindRegistry &carryKinds() const { return carry; }
  /// The size laws a `drift` operator made by this registry knows
  /// (-drift_size_law); add laws before it is created.
  SizeLawRegistry &sizeLaws() { return laws; }
  const SizeLawRegistry &sizeLaws() const { return laws; }

private:
  // Built-in operators may depend on the registry (carry takes its kinds).
  using Makers = Registry<Operator, const OperatorRegistry &>;
  Makers makers;
  CarryKindRegistry carry = CarryKindRegistry::withBuiltins();
  SizeLawRegistry laws = SizeLawRegistry::withBuiltins();
};

/// An operator given as a callback, for quick experiments from user code.
class ShellOperator : public Operator {
public:
  using Callback = std::function<PetscErrorCode(const StepInfo &, FractionState &)>;
  /// `conservative`: false for a callback that adds or removes mass on
  /// purpose (the run's mass ledger would refuse it otherwise).
  ShellOperator(std::string name, Callback apply, bool conservative = true)
      : name(std::move(name)), callback(std::move(apply)), conservative(conservative) {}
  std::string type() const override { return name; }
  PetscErrorCode setUp(const RunContext &) override;
  PetscErrorCode apply(const StepInfo &step, FractionState &state) override {
    return callback(step, state);
  }
  bool conservesMass() const override { return conservative; }

private:
  std::string name;
  Callback callback;
  bool conservative;
};

/// Applies a list of operators in order.  Operators are added before setUp;
/// setUp drops those a case does not need and refuses changes afterwards.
class Pipeline : public Operator {
public:
  std::string type() const override { return "pipeline"; }
  PetscErrorCode add(std::unique_ptr<Operator> op);
  /// Collective.  Every operator reads its options, and -<prefix>view
  /// (e.g. -drift_view, -drift_view ascii:drift.txt) through PetscOptionsGetViewer.
  PetscErrorCode setFromOptions(MPI_Comm comm) override;
  PetscErrorCode setUp(const RunContext &ctx) override;
  PetscErrorCode apply(const StepInfo &step, FractionState &state) override;
  PetscErrorCode view(PetscViewer viewer) const override;
  bool conservesMass() const override;
  /// Whether every operator that changes mass says how much (addedMass()),
  /// so that the run's ledger can keep checking.
  bool accountsMass() const;
  /// Sum over the operators of addedMass(), per fraction (empty: none reports).
  void addedMass(std::vector<double> *perFraction) const;
  /// Sum over the operators of addedAmounts(), [scalar][fraction] (empty: none reports).
  void addedAmounts(std::vector<double> *perScalarFraction) const;
  const std::vector<std::unique_ptr<Operator>> &operators() const { return ops; }
  const std::vector<std::string> &skipped() const { return left; }
  /// This rank's wall time [s] spent in each operator's apply() so far, in
  /// the order of operators() (waiting at its collectives included).
  const std::vector<double> &applySeconds() const { return seconds; }
  /// Collective.  Views every operator given -<prefix>view in the viewer
  /// that option names (plain -drift_view: stdout), and flushes it.
  PetscErrorCode viewRequested() const;

private:
  struct RequestedView {
    OwnedViewer viewer; // from -<prefix>view; empty when not given
    PetscViewerFormat format = PETSC_VIEWER_DEFAULT;
  };
  std::vector<std::unique_ptr<Operator>> ops;
  std::vector<RequestedView> views; // one per operator once setFromOptions ran
  std::vector<std::string> left;
  std::vector<double> seconds; // per operator, see applySeconds()
  bool isSetUp = false;
};

class MovingRows;

/// The shift operator: frame k's matrix applied to all fractions at once,
/// exactly mass-conserving because the columns sum to one.  Two kernels give
/// the same numbers: `moving` (default) updates in place only the rows of
/// cells whose solid moves (see src/operator/moving_rows.hpp), `maij` is the
/// product with a MAIJ view of the whole AIJ matrix (-shift_kernel).
class ShiftOperator : public Operator {
public:
  enum class Kernel { Moving, Maij };
  ShiftOperator();
  ~ShiftOperator() override;
  std::string type() const override { return "shift"; }
  PetscErrorCode setFromOptions(MPI_Comm comm) override;
  PetscErrorCode setUp(const RunContext &ctx) override;
  PetscErrorCode apply(const StepInfo &step, FractionState &state) override;
  PetscErrorCode view(PetscViewer viewer) const override;
  void setKernel(Kernel k) { kernel = k; }
  /// Before setUp: move `n` interleaved columns per cell instead of the
  /// run's fractions (0, the default: the fractions), e.g. the fractions of
  /// several replays at once (src/analysis/batched_replay.hpp).  Each column
  /// is summed in the same order whatever their number.
  void setColumns(int n) { columns = n; }
  /// The scalar amounts move with the frame's matrix, as the masses.
  bool carriesScalars() const override { return true; }

private:
  Kernel kernel = Kernel::Moving;
  int columns = 0;
  std::unique_ptr<MovingRows> moving, movingAmounts; // the second: the ns x nf scalar amounts
  std::vector<OwnedMat> perFrame, perFrameAmounts;   // MAIJ wrappers, one per frame
  int nf = 0;
};

} // namespace rcfd
