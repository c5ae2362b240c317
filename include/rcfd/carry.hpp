// Carrying the state across jumps between frames.
#pragma once

#include "rcfd/carry_kind.hpp"
#include "rcfd/swap_operator.hpp"

#include <memory>
#include <string>

namespace rcfd {

/// Carries the state across a jump between frames: after a step whose next
/// frame does not follow its frame (a stitching jump, or replay wrapping),
/// the state's bulk mass per cell differs from the next frame's alpha_s.
/// How it is carried is a registered kind (rcfd/carry_kind.hpp):
///  - column (default): in every vertical column the fractions keep their
///    order by height: each fraction's mass is handed to the next frame's
///    cells by cumulative bulk mass from the bottom (monotone transport);
///    solid a column gains or loses crosses between columns at their tops.
///    The bulk then matches the next frame's to round-off.  Needs a box mesh
///    with gravity along one of its axes; -carry_column_bed takes the whole
///    bed as one column (cells by height).
///  - remap: every cell keeps its composition (mass shares of the
///    fractions; a cell that was empty takes its neighbours') and takes the
///    next frame's bulk mass; one factor per fraction, the same in every
///    cell, then restores each fraction's total exactly.
///  - level: sweeps move mixture from over- to under-filled neighbours
///    (strictly local, but it cannot move mass far: bubbles in other places
///    leave a large mismatch).
/// All keep every fraction's total and never make a mass negative.
/// Options (prefix carry_): -carry_type column|remap|level|<registered kind>,
/// -carry_sweeps (level, per jump, default 20), -carry_sweeps_per_step
/// (level), -carry_view [viewer].  See docs/paths.md.
class CarryOperator : public SwapOperator {
public:
  /// Knows the built-in kinds.
  CarryOperator();
  /// Knows the given kinds (e.g. an OperatorRegistry's carryKinds()).
  explicit CarryOperator(CarryKindRegistry kinds);
  ~CarryOperator() override;
  std::string type() const override { return "carry"; }
  /// Collective.  Reads -carry_type, then the kind's own options.
  PetscErrorCode setFromOptions(MPI_Comm comm) override;
  bool needed(const RunContext &ctx) const override;
  PetscErrorCode apply(const StepInfo &step, FractionState &state) override;
  PetscErrorCode view(PetscViewer viewer) const override;
  /// Whether its kind carries the scalars (the built-in kinds do).
  bool carriesScalars() const override { return kind && kind->carriesScalars(); }
  /// Collective on `comm`.  Chooses the kind by name, before setUp
  /// (setFromOptions reads -carry_type over it).
  PetscErrorCode setKind(MPI_Comm comm, const std::string &name);
  const std::string &kindName() const { return name; }

private:
  CarryKindRegistry known;
  std::string name = "column";
  std::unique_ptr<CarryKind> kind;
};

} // namespace rcfd
