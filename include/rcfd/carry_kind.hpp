// Carry kinds: how the `carry` operator takes the state across a jump
// between frames, where the state's bulk mass per cell no longer matches the
// next frame's alpha_s.  Kinds are registered by name like operators and
// chosen with -carry_type; rcfd has `column` (default), `remap` and `level` (see
// rcfd/carry.hpp, docs/paths.md), and a user adds one with
//   PetscCall(registry.carryKinds().add("mine", [] { return std::make_unique<MyCarry>(); }, "what it does"));
#pragma once

#include "rcfd/face_exchange.hpp"
#include "rcfd/operator_context.hpp"
#include "rcfd/registry.hpp"

#include <functional>
#include <memory>
#include <string>

namespace rcfd {

/// What a carry kind works with: the case, and the carry operator's face
/// exchange over all internal faces.  With scalars (docs/scalars.md), a second
/// exchange over the same faces for the state's ns x nf amounts per cell (its
/// gathered cells numbered as `exchange`'s); null without scalars.
struct CarryContext {
  const Database &db;
  FaceExchange &exchange;
  double solidDensity; // [kg/m^3]
  int numFractions;
  FaceExchange *amountExchange = nullptr;
};

class CarryKind {
public:
  virtual ~CarryKind() = default;
  /// The registered name of the kind.
  virtual std::string type() const = 0;
  /// The carry operator gives its kind its own prefix ("carry_"), so a
  /// kind's option -NAME is -carry_NAME.
  void setOptionsPrefix(const std::string &p) { prefix = p; }
  const std::string &optionsPrefix() const { return prefix; }
  /// Collective.  Reads the kind's own options (none by default).
  virtual PetscErrorCode setFromOptions(MPI_Comm comm);
  /// Whether the kind changes anything; a carry that does not is left out of the pipeline.
  virtual bool needed() const { return true; }
  /// Collective.  Called after every step.  step.jump says whether the next
  /// frame does not follow this step's (most kinds act only then), and
  /// ctx.db.alphaS(step.nextFrame) is the bulk to carry the state towards.
  /// A kind must keep every fraction's total mass and never make a mass negative.
  virtual PetscErrorCode apply(const CarryContext &ctx, const StepInfo &step, FractionState &state) = 0;
  /// Whether apply() moves the state's scalar amounts with the masses
  /// (docs/scalars.md); a run with -scalars refuses a kind that does not.
  virtual bool carriesScalars() const { return false; }
  /// What the kind did, one line starting with "carry: ".
  virtual PetscErrorCode view(PetscViewer viewer) const = 0;

protected:
  std::string prefix;
};

using CarryKindFactory = std::function<std::unique_ptr<CarryKind>()>;

/// Name -> factory of carry kinds (owned by an OperatorRegistry, or by a
/// CarryOperator made without one).
class CarryKindRegistry : public Registry<CarryKind> {
public:
  CarryKindRegistry() : Registry("-carry_type", "carry kind") {}
  /// column, remap and level.
  static CarryKindRegistry withBuiltins();
};

} // namespace rcfd
