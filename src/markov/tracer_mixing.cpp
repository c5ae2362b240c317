#include "markov/tracer_mixing.hpp"
#include "markov/chain_block.hpp"
#include "base/petsc_compat.hpp"

#include "rcfd/zone.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rcfd {

std::vector<int> mixingStarts(const Mesh &mesh, const Vec3 &gravity, const std::vector<double> &alpha0,
                              double alphaMin, bool all, int stride) {
  std::vector<int> starts;
  if (all || !mesh.isBox()) {
    for (int c = 0; c < mesh.numCells(); ++c)
      if (alpha0[c] >= alphaMin) starts.push_back(c);
    return starts;
  }
  int vertical;
  bool upward;
  verticalAxis(gravity, &vertical, &upward);
  const BoxSpec &b = mesh.boxSpec();
  const int n[3] = {b.nx, b.ny, b.nz};
  int centre[3] = {b.nx / 2, b.ny / 2, b.nz / 2};
  for (int l = 0; l < n[vertical]; ++l) {
    const int layer = upward ? l : n[vertical] - 1 - l;
    centre[vertical] = layer;
    const int c = b.cellIndex(centre[0], centre[1], centre[2]);
    if (alpha0[c] >= alphaMin && l % std::max(1, stride) == 0) starts.push_back(c);
  }
  return starts;
}

PetscErrorCode tracerMixing(const FrameChain &chain, const MixingSettings &settings, MixingResult *out,
                            const std::vector<ChainStep *> &steps) {
  const Database &db = chain.database();
  const Layout &layout = db.layout();
  const MPI_Comm comm = layout.comm();
  const PetscInt cellStarts = static_cast<PetscInt>(settings.starts.size());
  const PetscInt s = cellStarts + (settings.zoneStart ? 1 : 0);
  const PetscInt bs = s + 1; // column 0: the bulk; 1..s: the tracers
  const std::vector<PetscInt> &cells = chain.chainCells(); // the block's cells (local indices)
  const PetscInt ncells = chain.numChainCells();
  PetscFunctionBeginUser;
  out->time.assign(s, std::numeric_limits<double>::quiet_NaN());
  out->meanDeviation.clear();
  out->worstDeviation.clear();
  out->zoneDeviation.clear();
  out->confirm = chain.numFrames();
  if (s == 0) PetscFunctionReturn(PETSC_SUCCESS);
  ChainBlock x;
  PetscCall(x.setUp(chain, bs, steps));
  {
    const PetscScalar *pm;
    PetscCall(x.getArrays());
    PetscCall(VecGetArrayRead(chain.massShare(0), &pm));
    for (PetscInt k = 0; k < ncells; ++k) x.at(k, 0) = pm[cells[k]];
    PetscCall(VecRestoreArrayRead(chain.massShare(0), &pm));
    int outside = -1; // a start that is none of the chain's cells (it never holds solid)
    for (PetscInt c = 0; c < cellStarts; ++c) {
      const PetscInt row = layout.petscRow(settings.starts[c]);
      if (row < layout.rowStart() || row >= layout.rowEnd()) continue;
      const auto k = std::lower_bound(cells.begin(), cells.end(), row - layout.rowStart());
      if (k == cells.end() || *k != row - layout.rowStart()) outside = std::max(outside, settings.starts[c]);
      else x.at(k - cells.begin(), 1 + c) = 1.0;
    }
    if (settings.zoneStart) { // the zone's share of the solid, as one distribution
      const std::vector<char> in = chain.chainMask(settings.startZone);
      double share = 0.0;
      for (PetscInt k = 0; k < ncells; ++k) share += in[k] ? x.at(k, 0) : 0.0;
      PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &share, 1, MPI_DOUBLE, MPI_SUM, comm));
      PetscCheck(share > 0, comm, PETSC_ERR_USER_INPUT,
                 "Database '%s': the tracer's start zone holds no solid at frame 0", db.path().c_str());
      for (PetscInt k = 0; k < ncells; ++k) x.at(k, s) = in[k] ? x.at(k, 0) / share : 0.0;
    }
    PetscCall(x.restoreArrays());
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &outside, 1, MPI_INT, MPI_MAX, comm));
    PetscCheck(outside < 0, comm, PETSC_ERR_USER_INPUT,
               "Database '%s': the tracer start cell %d holds no solid in any frame and exchanges none, so no "
               "tracer can start there",
               db.path().c_str(), outside);
  }
  // The bulk's share y_i holds alpha y_i S / V_i, S the solid volume of frame 0.
  double solid = 0.0;
  {
    const PetscScalar *pa;
    PetscCall(VecGetArrayRead(db.alphaS(0), &pa));
    for (PetscInt i = 0; i < layout.numLocal(); ++i) solid += pa[i] * db.localVolumes()[i];
    PetscCall(VecRestoreArrayRead(db.alphaS(0), &pa));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &solid, 1, MPI_DOUBLE, MPI_SUM, comm));
  }
  const long long horizon = std::max<long long>(1, std::llround(settings.horizon / chain.dt()));
  std::vector<long long> within(s, -1); // first step of the current run within the tolerance
  std::vector<double> deviation(s);
  PetscInt open = s;
  for (long long n = 1; n <= horizon && open > 0; ++n) {
    PetscCall(x.step(n - 1));
    // Deviation at t_n, over the cells where the propagated bulk holds alpha_s >= alphaMin.
    PetscCall(x.getArrays());
    std::fill(deviation.begin(), deviation.end(), 0.0);
    // (The other cells hold no bulk: alphaMin > 0 leaves them out.)
    for (PetscInt k = 0; k < ncells; ++k) {
      const PetscInt i = cells[k];
      const double bulk = x.at(k, 0);
      if (bulk * solid < settings.alphaMin * db.localVolumes()[i]) continue;
      if (!settings.excluded.empty() && settings.excluded[i]) continue;
      for (PetscInt c = 0; c < s; ++c) deviation[c] = std::max(deviation[c], std::fabs(x.at(k, 1 + c) / bulk - 1.0));
    }
    PetscCall(x.restoreArrays());
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, deviation.data(), static_cast<int>(s), MPI_DOUBLE, MPI_MAX, comm));
    double mean = 0.0, worst = 0.0;
    for (PetscInt c = 0; c < s; ++c) {
      if (c < cellStarts) {
        mean += deviation[c] / cellStarts;
        worst = std::max(worst, deviation[c]);
      } else {
        out->zoneDeviation.push_back(deviation[c]);
      }
      if (!std::isnan(out->time[c])) continue;
      if (deviation[c] > settings.tolerance) {
        within[c] = -1;
        continue;
      }
      if (within[c] < 0) within[c] = n;
      if (n - within[c] + 1 >= out->confirm) {
        out->time[c] = within[c] * chain.dt();
        --open;
      }
    }
    if (cellStarts > 0) {
      out->meanDeviation.push_back(mean);
      out->worstDeviation.push_back(worst);
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
