#include "markov/class_background.hpp"
#include "base/petsc_compat.hpp"

#include <algorithm>
#include <string>

namespace rcfd {

void ClassBackground::reset(const FrameChain &chain, int numClasses) {
  chain_ = &chain;
  classes_ = numClasses;
  mass_.assign(static_cast<size_t>(chain.numFrames()),
               std::vector<double>(static_cast<size_t>(chain.numChainCells()) * static_cast<size_t>(numClasses), 0.0));
}

PetscErrorCode ClassBackground::add(int i, double share, Vec atFrame0, const std::vector<ChainStep *> &steps) {
  const std::vector<PetscInt> &cells = chain_->chainCells();
  const size_t nf = static_cast<size_t>(classes_);
  PetscFunctionBeginUser;
  OwnedVec x, y;
  PetscCall(chain_->chainVector(x.put()));
  PetscCall(VecDuplicate(x, y.put()));
  {
    const PetscScalar *pa;
    PetscScalar *px;
    PetscCall(VecGetArrayRead(atFrame0, &pa));
    PetscCall(VecGetArrayWrite(x, &px));
    for (size_t c = 0; c < cells.size(); ++c) px[c] = pa[cells[c]];
    PetscCall(VecRestoreArrayWrite(x, &px));
    PetscCall(VecRestoreArrayRead(atFrame0, &pa));
  }
  const int K = chain_->numFrames();
  for (int k = 0; k < K; ++k) {
    PetscCall(MatMult(chain_->transfer(k), x, y));
    const PetscScalar *py;
    PetscCall(VecGetArrayRead(y, &py));
    std::vector<double> &m = mass_[static_cast<size_t>(k)];
    for (size_t c = 0; c < cells.size(); ++c) m[c * nf + static_cast<size_t>(i)] += share * py[c];
    PetscCall(VecRestoreArrayRead(y, &py));
    if (k + 1 == K) break; // frame 0's own is where the class started
    for (ChainStep *s : steps) PetscCall(s->apply(k, y, 1));
    std::swap(x, y);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::vector<std::vector<double>> ClassBackground::composition(const std::vector<double> &shares) const {
  const size_t nf = static_cast<size_t>(classes_);
  std::vector<std::vector<double>> w = mass_;
  for (std::vector<double> &frame : w)
    for (size_t c = 0; c < frame.size(); c += nf) {
      double total = 0.0;
      for (size_t f = 0; f < nf; ++f) total += frame[c + f];
      for (size_t f = 0; f < nf; ++f) frame[c + f] = total > 0.0 ? frame[c + f] / total : shares[f];
    }
  return w;
}

PetscErrorCode classSteps(const FrameChain &chain, ClassDrift &drift, int i, bool asMatrices, ChainStep *after,
                          DriftMatrices *matrices, std::vector<ChainStep *> *steps) {
  PetscFunctionBeginUser;
  drift.setClass(i);
  *steps = {&drift};
  if (asMatrices && drift.sameEveryPeriod()) {
    PetscCall(matrices->setUp(chain, drift));
    (*steps)[0] = matrices;
  }
  if (after) steps->push_back(after);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode findBackground(const FrameChain &chain, PeriodChain &period, ChainEigensolver &solver,
                              ClassDrift &drift, const FractionSet &fractions, bool asMatrices, ChainStep *after,
                              const BackgroundSettings &settings, BackgroundIterations *out) {
  const Database &db = chain.database();
  PetscFunctionBeginUser;
  *out = BackgroundIterations{};
  std::vector<double> inventory;
  for (int i = 0; i < fractions.size(); ++i) inventory.push_back(fractions.massShare(i));
  for (int round = 0; round < settings.iterations; ++round) {
    ClassBackground bed;
    bed.reset(chain, fractions.size());
    std::vector<double> centres;
    for (int i = 0; i < fractions.size(); ++i) {
      DriftMatrices matrices;
      std::vector<ChainStep *> steps;
      PetscCall(classSteps(chain, drift, i, asMatrices, after, &matrices, &steps));
      PeriodSpectrum p;
      const std::string what = "the period chain of size class " + fractions.label(i);
      PetscCall(period.solve(solver, steps, what.c_str(), &p));
      std::vector<double> share;
      PetscCall(db.layout().gatherToAll(1, p.stationary, &share));
      centres.push_back(centreHeight(db.mesh(), db.metadata().gravity, share));
      PetscCall(bed.add(i, inventory[static_cast<size_t>(i)], p.stationary, steps));
    }
    if (!out->centres.empty()) {
      out->lastChange = 0.0;
      for (size_t i = 0; i < centres.size(); ++i)
        out->lastChange = std::max(out->lastChange, std::abs(centres[i] - out->centres.back()[i]));
    }
    out->centres.push_back(centres);
    if (out->converged(settings)) break; // this background gives what the last did
    drift.setComposition(bed.composition(inventory));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
