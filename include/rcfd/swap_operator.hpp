// The base of operators that move mass across faces (drift, dispersion,
// carry): it does their common set-up (fractions, solid density,
// communicator, the FaceExchange over the faces the operator chooses) and
// keeps their step statistics, so that a derived operator holds only its
// physics.  A new face-swap operator derives from it, says which faces it
// swaps across (swapFaces()), reads its options, and writes apply() with
// exchange().sweep() (see rcfd/face_exchange.hpp).
#pragma once

#include "rcfd/face_exchange.hpp"
#include "rcfd/operator.hpp"

#include <memory>

namespace rcfd {

class SwapOperator : public Operator {
public:
  ~SwapOperator() override;
  /// Collective.  Records the case (numFractions(), solid density,
  /// communicator, database), builds the face exchange over swapFaces(),
  /// then calls setUpSwap() for the operator's own set-up.
  PetscErrorCode setUp(const RunContext &ctx) final;
  /// Steps in which the operator swapped, the sub-steps (sweeps) they took,
  /// and the most sub-steps of one step.
  long stepsTaken() const { return steps; }
  long substepsTaken() const { return substeps; }
  int maxSubsteps() const { return mostSubsteps; }

protected:
  SwapOperator();
  /// The faces an operator swaps across: those whose area vector has a
  /// component along `direction` above `minShare` of its area; a zero
  /// direction (the default) means every internal face.
  struct FaceChoice {
    Vec3 direction{0.0, 0.0, 0.0};
    double minShare = 0.0;
  };
  virtual FaceChoice swapFaces(const RunContext &ctx) const;
  /// The operator's own set-up, after the common one (nothing by default).
  virtual PetscErrorCode setUpSwap(const RunContext &ctx);
  /// Count a step that took `n` sub-steps.
  void countStep(int n);

  /// With scalars (RunContext::numScalars > 0): a second exchange over the
  /// same faces, for the ns x nf amounts per cell (FractionState::amounts());
  /// its gathered cells are numbered as exchange()'s.  Null without scalars.
  FaceExchange *amountExchange() { return amountFaces.get(); }
  FaceExchange &exchange() { return *faces; }
  const FaceExchange &exchange() const { return *faces; }
  bool isSetUp() const { return faces != nullptr; }
  /// The database the operator was set up with.
  const Database &database() const { return *db; }

  int nf = 0;              // number of fractions
  int ns = 0;              // number of scalars carried (docs/scalars.md)
  double rho = 0.0;        // solid density [kg/m^3]
  MPI_Comm comm = MPI_COMM_NULL; // the database's communicator, once set up

private:
  const Database *db = nullptr;
  std::unique_ptr<FaceExchange> faces, amountFaces;
  long steps = 0, substeps = 0;
  int mostSubsteps = 0;
};

} // namespace rcfd
