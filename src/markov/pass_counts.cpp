#include "markov/pass_counts.hpp"
#include "markov/chain_block.hpp"
#include "base/petsc_compat.hpp"

#include <algorithm>
#include <cmath>

namespace rcfd {

PetscErrorCode passCounts(const FrameChain &chain, const std::vector<const Zone *> &zones,
                          const PassCountSettings &settings, std::vector<PassCounts> *out,
                          const std::vector<ChainStep *> &after) {
  const Layout &layout = chain.database().layout();
  const MPI_Comm comm = layout.comm();
  // The block holds the chain's cells only: chain cell k is local cell cells[k].
  const std::vector<PetscInt> &cells = chain.chainCells();
  const PetscInt ncells = chain.numChainCells();
  PetscFunctionBeginUser;
  out->clear();
  const PetscInt J = settings.maxPasses + 1; // counters 0 .. maxPasses
  const long long steps = std::max<long long>(1, std::llround(settings.time / chain.dt()));
  const std::vector<int> &dep = settings.departures;
  if (zones.empty() || dep.empty()) PetscFunctionReturn(PETSC_SUCCESS);
  // Columns: (zone z, departure d, counter j) at z D J + d J + j, doubled:
  // the first half holds the solid outside the zone, the second the solid in
  // it, so that one MatMult moves both and what came from outside is known.
  const PetscInt D = static_cast<PetscInt>(dep.size()), Z = static_cast<PetscInt>(zones.size());
  const PetscInt C = Z * D * J, bs = 2 * C;
  std::vector<std::vector<char>> inside(zones.size()); // per chain cell
  for (size_t z = 0; z < zones.size(); ++z) inside[z] = chain.chainMask(zones[z]->localCells());
  ChainBlock x;
  PetscCall(x.setUp(chain, bs, after));
  const int first = *std::min_element(dep.begin(), dep.end());
  const int last = *std::max_element(dep.begin(), dep.end());
  std::vector<std::vector<double>> result(static_cast<size_t>(Z * D));
  std::vector<double> sums(static_cast<size_t>(C));
  for (long long s = first; s <= last + steps; ++s) {
    // Start the departures of frame s: the mass share of frame s at counter 0.
    for (PetscInt d = 0; d < D; ++d) {
      if (dep[static_cast<size_t>(d)] != s) continue;
      const PetscScalar *pm;
      PetscCall(VecGetArrayRead(chain.massShare(s), &pm));
      PetscCall(x.getArrays());
      for (PetscInt z = 0; z < Z; ++z)
        for (PetscInt i = 0; i < ncells; ++i) x.at(i, inside[z][i] * C + z * D * J + d * J) = pm[cells[i]];
      PetscCall(x.restoreArrays());
      PetscCall(VecRestoreArrayRead(chain.massShare(s), &pm));
    }
    // Read the departures whose time is up: at t_{dep + steps}.
    std::fill(sums.begin(), sums.end(), 0.0);
    bool reading = false;
    for (PetscInt d = 0; d < D; ++d) reading = reading || dep[static_cast<size_t>(d)] + steps == s;
    if (reading) {
      PetscCall(x.getArrays());
      for (PetscInt i = 0; i < ncells; ++i)
        for (PetscInt c = 0; c < C; ++c) sums[static_cast<size_t>(c)] += x.at(i, c) + x.at(i, C + c);
      PetscCall(x.restoreArrays());
      PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums.data(), static_cast<int>(C), MPI_DOUBLE, MPI_SUM, comm));
      for (PetscInt z = 0; z < Z; ++z)
        for (PetscInt d = 0; d < D; ++d)
          if (dep[static_cast<size_t>(d)] + steps == s)
            result[static_cast<size_t>(z * D + d)].assign(sums.begin() + z * D * J + d * J,
                                                          sums.begin() + z * D * J + (d + 1) * J);
    }
    if (s == last + steps) break;
    PetscCall(x.step(s));
    // Sort the moved solid by side at t_{s+1}, in place: what entered the
    // zone (from the outside half into a zone cell) passes to the next counter.
    PetscCall(x.getArrays());
    for (PetscInt i = 0; i < ncells; ++i)
      for (PetscInt z = 0; z < Z; ++z) {
        const bool in = inside[z][i];
        for (PetscInt d = 0; d < D; ++d) {
          const PetscInt o = z * D * J + d * J;
          if (!in) {
            // Outside now, whichever side it came from.
            for (PetscInt j = 0; j < J; ++j) {
              x.at(i, o + j) += x.at(i, C + o + j);
              x.at(i, C + o + j) = 0.0;
            }
            continue;
          }
          // In the zone: what was in stays at j; what came from outside
          // enters, j -> j + 1 (the last counter keeps its own).
          x.at(i, C + o + J - 1) += x.at(i, o + J - 1);
          for (PetscInt j = J - 1; j > 0; --j) x.at(i, C + o + j) += x.at(i, o + j - 1);
          for (PetscInt j = 0; j < J; ++j) x.at(i, o + j) = 0.0;
        }
      }
    PetscCall(x.restoreArrays());
  }
  for (PetscInt z = 0; z < Z; ++z) {
    PassCounts p;
    p.zone = zones[static_cast<size_t>(z)]->name();
    p.steps = static_cast<int>(steps);
    p.probability.assign(static_cast<size_t>(J), 0.0);
    for (PetscInt d = 0; d < D; ++d) {
      const std::vector<double> &r = result[static_cast<size_t>(z * D + d)];
      double total = 0.0;
      for (PetscInt j = 0; j < J; ++j) {
        p.probability[static_cast<size_t>(j)] += r[static_cast<size_t>(j)] / D;
        total += r[static_cast<size_t>(j)];
      }
      p.conservation = std::max(p.conservation, std::fabs(total - 1.0));
    }
    for (PetscInt j = 0; j < J; ++j) p.mean += j * p.probability[static_cast<size_t>(j)];
    out->push_back(std::move(p));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
