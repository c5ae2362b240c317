#include "markov/zone_passages.hpp"
#include "markov/chain_block.hpp"
#include "base/petsc_compat.hpp"

#include <algorithm>
#include <cmath>

namespace rcfd {

std::vector<int> evenFrames(int K, int count) {
  std::vector<int> frames;
  count = std::max(1, std::min(count, K));
  for (int j = 0; j < count; ++j) frames.push_back(static_cast<int>(static_cast<long long>(j) * K / count));
  return frames;
}

namespace {

// One followed crossing: a column of the block vector.
struct Cohort {
  size_t zone = 0;
  bool away = false; // left the zone (absorbed back in it) or entered it (absorbed outside)
  int departure = 0; // the frame whose step it crossed in
  double weight = 0.0;
  double absorbed = 0.0;
  std::vector<double> f;
  bool done = false;
};

} // namespace

PetscErrorCode zonePassages(const FrameChain &chain, const std::vector<const Zone *> &zones,
                            const PassageSettings &settings, std::vector<ZonePassages> *out,
                            const std::vector<ChainStep *> &steps) {
  const Layout &layout = chain.database().layout();
  const MPI_Comm comm = layout.comm();
  // The block holds the chain's cells only (the others hold no solid and
  // receive none): chain cell k is the local cell cells[k].
  const std::vector<PetscInt> &cells = chain.chainCells();
  const PetscInt ncells = chain.numChainCells();
  PetscFunctionBeginUser;
  out->clear();
  std::vector<Cohort> cohorts;
  std::vector<std::vector<char>> inside(zones.size()); // per chain cell
  for (size_t z = 0; z < zones.size(); ++z) {
    inside[z] = chain.chainMask(zones[z]->localCells());
    for (bool away : {false, true})
      for (int k : settings.departures) {
        Cohort h;
        h.zone = z;
        h.away = away;
        h.departure = k;
        cohorts.push_back(std::move(h));
      }
    ZonePassages p;
    p.zone = zones[z]->name();
    const PetscScalar *pm;
    PetscCall(VecGetArrayRead(chain.meanShare(), &pm));
    for (PetscInt i : zones[z]->localCells()) p.databaseShare += pm[i];
    PetscCall(VecRestoreArrayRead(chain.meanShare(), &pm));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &p.databaseShare, 1, MPI_DOUBLE, MPI_SUM, comm));
    out->push_back(std::move(p));
  }
  if (cohorts.empty()) PetscFunctionReturn(PETSC_SUCCESS);
  // The block vector holds one column per cohort still followed: column c is
  // cohort column[c].  When half of the columns are done (a departure whose
  // tail fell below the tolerance, most of the residences within a second or
  // two) the block is rebuilt without them, so the long followings (the time
  // away) do not carry the finished ones; what a dropped column still holds
  // is its `left`.  Done columns are not absorbed any more, so dropping them
  // changes nothing but the work.
  std::vector<size_t> column(cohorts.size());
  for (size_t c = 0; c < cohorts.size(); ++c) column[c] = c;
  std::vector<double> left(cohorts.size(), 0.0);
  ChainBlock x;
  PetscCall(x.setUp(chain, static_cast<PetscInt>(cohorts.size()), steps));
  OwnedVec source, moved;
  // Keeps the cohorts in `keep`, the rest's content counted as their `left`.
  auto rebuild = [&](const std::vector<size_t> &keep) -> PetscErrorCode {
    PetscFunctionBeginUser;
    const PetscInt bs = x.columns();
    std::vector<double> dropped(cohorts.size(), 0.0);
    std::vector<char> kept(cohorts.size(), 0);
    for (size_t h : keep) kept[h] = 1;
    std::vector<PetscInt> from;
    for (size_t h : keep) from.push_back(static_cast<PetscInt>(std::find(column.begin(), column.end(), h) - column.begin()));
    PetscCall(x.getArrays());
    for (PetscInt i = 0; i < ncells; ++i)
      for (PetscInt c = 0; c < bs; ++c)
        if (!kept[column[static_cast<size_t>(c)]]) dropped[column[static_cast<size_t>(c)]] += x.at(i, c);
    PetscCall(x.restoreArrays());
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, dropped.data(), static_cast<int>(dropped.size()), MPI_DOUBLE, MPI_SUM, comm));
    for (PetscInt c = 0; c < bs; ++c) {
      const size_t h = column[static_cast<size_t>(c)];
      if (!kept[h]) left[h] = dropped[h];
    }
    PetscCall(x.keepColumns(from));
    column = keep;
    PetscFunctionReturn(PETSC_SUCCESS);
  };
  PetscCall(chain.chainVector(source.put()));
  PetscCall(VecDuplicate(source, moved.put()));
  const long long horizon = std::max<long long>(1, std::llround(settings.horizon / chain.dt()));
  const int lastDeparture = *std::max_element(settings.departures.begin(), settings.departures.end());
  std::vector<double> sums;
  // Per column, for the absorption: the zone's cells (or none, when the
  // column is not absorbed this step) and the side that absorbs.
  std::vector<const char *> mask;
  std::vector<char> side;
  for (long long s = 0;; ++s) {
    // Move every cohort from t_s to t_{s+1}; the ones not yet started are empty.
    PetscCall(x.step(s));
    const PetscInt bs = x.columns();
    // Absorb: what reached the side it left ends its duration, n = s - departure steps.
    mask.assign(static_cast<size_t>(bs), nullptr);
    side.assign(static_cast<size_t>(bs), 0);
    for (PetscInt c = 0; c < bs; ++c) {
      const Cohort &h = cohorts[column[static_cast<size_t>(c)]];
      if (h.departure >= s || h.done) continue;
      mask[static_cast<size_t>(c)] = inside[h.zone].data();
      side[static_cast<size_t>(c)] = h.away;
    }
    PetscCall(x.getArrays());
    sums.assign(static_cast<size_t>(bs), 0.0);
    // Cell by cell, the columns in memory order (a column at a time would
    // stride through the whole block vector once per column).
    for (PetscInt i = 0; i < ncells; ++i)
      for (PetscInt c = 0; c < bs; ++c) {
        const char *in = mask[static_cast<size_t>(c)];
        if (in && in[i] == side[static_cast<size_t>(c)]) {
          sums[static_cast<size_t>(c)] += x.at(i, c);
          x.at(i, c) = 0.0;
        }
      }
    PetscCall(x.restoreArrays());
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums.data(), static_cast<int>(bs), MPI_DOUBLE, MPI_SUM, comm));
    bool open = s < lastDeparture;
    PetscInt finished = 0;
    for (PetscInt c = 0; c < bs; ++c) {
      Cohort &h = cohorts[column[static_cast<size_t>(c)]];
      if (h.departure >= s || h.done) {
        finished += h.done;
        continue;
      }
      h.f.push_back(sums[static_cast<size_t>(c)]);
      h.absorbed += sums[static_cast<size_t>(c)];
      h.done = 1.0 - h.absorbed < settings.tail || static_cast<long long>(h.f.size()) >= horizon || h.weight == 0;
      finished += h.done;
      open = open || !h.done;
    }
    // Start the cohorts that cross during frame s: the solid on one side at
    // t_s found on the other at t_{s+1}, as a distribution.
    for (PetscInt c = 0; c < bs; ++c) {
      Cohort &h = cohorts[column[static_cast<size_t>(c)]];
      if (h.departure != s) continue;
      const std::vector<char> &in = inside[h.zone];
      const PetscScalar *pm;
      PetscScalar *pv;
      PetscCall(VecGetArrayRead(chain.massShare(s), &pm));
      PetscCall(VecGetArrayWrite(source, &pv));
      for (PetscInt i = 0; i < ncells; ++i) pv[i] = static_cast<bool>(in[i]) == h.away ? pm[cells[i]] : 0.0;
      PetscCall(VecRestoreArrayWrite(source, &pv));
      PetscCall(VecRestoreArrayRead(chain.massShare(s), &pm));
      PetscCall(MatMult(chain.transfer(s), source, moved));
      for (ChainStep *step : steps) PetscCall(step->apply(s, moved, 1));
      double w = 0.0;
      PetscCall(VecGetArray(moved, &pv));
      for (PetscInt i = 0; i < ncells; ++i) {
        if (static_cast<bool>(in[i]) == h.away) pv[i] = 0.0; // stayed on its side
        w += pv[i];
      }
      PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &w, 1, MPI_DOUBLE, MPI_SUM, comm));
      h.weight = w;
      PetscCall(x.getArrays());
      for (PetscInt i = 0; i < ncells; ++i) x.at(i, c) = w > 0 ? pv[i] / w : 0.0;
      PetscCall(x.restoreArrays());
      PetscCall(VecRestoreArray(moved, &pv));
      open = open || w > 0;
    }
    if (!open) break;
    if (2 * finished >= bs) {
      std::vector<size_t> keep;
      for (size_t h : column)
        if (!cohorts[h].done) keep.push_back(h);
      PetscCall(rebuild(keep));
    }
  }
  PetscCall(rebuild({})); // what the last columns hold is their `left`
  // Mix the departures, weighted by the mass that crossed.
  for (size_t z = 0; z < zones.size(); ++z)
    for (bool away : {false, true}) {
      PassageDistribution &d = away ? (*out)[z].away : (*out)[z].residence;
      double total = 0.0;
      for (const Cohort &h : cohorts)
        if (h.zone == z && h.away == away) total += h.weight;
      d.flux = total / settings.departures.size();
      for (const Cohort &h : cohorts) {
        if (h.zone != z || h.away != away || h.weight == 0) continue;
        // Left unabsorbed: the remaining mass, counted directly.
        if (d.probability.size() < h.f.size()) d.probability.resize(h.f.size(), 0.0);
        for (size_t n = 0; n < h.f.size(); ++n) d.probability[n] += h.weight / total * h.f[n];
        d.tail += h.weight / total * (1.0 - h.absorbed);
      }
      double absorbed = 0.0, first = 0.0;
      for (size_t n = 0; n < d.probability.size(); ++n) {
        absorbed += d.probability[n];
        first += (n + 1) * chain.dt() * d.probability[n];
      }
      d.mean = absorbed > 0 ? first / absorbed : 0.0;
    }
  // Conservation: absorbed plus what is left in the block vector is 1 for every cohort.
  for (size_t c = 0; c < cohorts.size(); ++c) {
    const Cohort &h = cohorts[c];
    if (h.weight == 0) continue;
    PassageDistribution &d = h.away ? (*out)[h.zone].away : (*out)[h.zone].residence;
    d.conservation = std::max(d.conservation, std::fabs(h.absorbed + left[c] - 1.0));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
