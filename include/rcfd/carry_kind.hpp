// Carry kinds: how the `carry` operator takes the state across a jump
// between frames, where the state's bulk mass per cell no longer matches the
// next frame's alpha_s.  Kinds are registered by name like operators and
// chosen with -carry_type; rcfd has `column` (default), `remap` and `level` (see
// rcfd/carry.hpp, docs/paths.md), and a user adds one with
//   registry.carryKinds().add("mine", [] { return std::make_unique<MyCarry>(); }, "what it does");
#pragma once

#include "rcfd/face_exchange.hpp"
#include "rcfd/operator_context.hpp"
#include "rcfd/registry.hpp"

#include <functional>
#include <memory>
#include <string>

namespace rcfd {

/// What a carry kind works with: the case, and the carry operator's face
/// exchange over all internal faces.
struct CarryContext {
  const Database &db;
  FaceExchange &exchange;
  double solidDensity; // [kg/m^3]
  int numFractions;
};

class CarryKind {
public:
  virtual ~CarryKind() = default;
  /// Collective.  Reads the kind's own options, -<prefix><name> with the
  /// carry operator's prefix (none by default).
  virtual PetscErrorCode setFromOptions(MPI_Comm comm, const std::string &prefix);
  /// Whether the kind changes anything; a carry that does not is left out of the pipeline.
  virtual bool needed() const { return true; }
  /// Collective.  Called after every step.  step.jump says whether the next
  /// frame does not follow this step's (most kinds act only then), and
  /// ctx.db.alphaS(step.nextFrame) is the bulk to carry the state towards.
  /// A kind must keep every fraction's total mass and never make a mass negative.
  virtual PetscErrorCode apply(const CarryContext &ctx, const StepInfo &step, FractionState &state) = 0;
  /// What the kind did, one line starting with "carry: ".
  virtual PetscErrorCode view(PetscViewer viewer) const = 0;
};

using CarryKindFactory = std::function<std::unique_ptr<CarryKind>()>;

/// Name -> factory of carry kinds (owned by an OperatorRegistry, or by a
/// CarryOperator made without one).
class CarryKindRegistry : public NamedFactories<CarryKindFactory> {
public:
  /// column, remap and level.
  static CarryKindRegistry withBuiltins();
  /// Throws std::invalid_argument listing the known kinds if `name` is unknown.
  std::unique_ptr<CarryKind> create(const std::string &name) const {
    return find(name, "-carry_type", "carry kind")();
  }
};

} // namespace rcfd
