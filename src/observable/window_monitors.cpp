// Monitors averaged over a time window: vertical profiles and the halves'
// size distributions, written in the layout of rcfd reference's files
// (src/analysis/particle_reference.cpp) so that rcfd compare can diff them.
#include "observable/answers.hpp"
#include "observable/scalar_profiles_monitor.hpp"
#include "base/petsc_compat.hpp"

#include <cmath>
#include <cstdio>

namespace rcfd {
namespace {

std::string formatNumber(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", v);
  return text;
}

// State layout of both: {count, sums...}.
PetscErrorCode restoreSums(const std::vector<double> &state, const char *name, double *count,
                           std::vector<std::vector<double> *> sums) {
  std::size_t n = 1;
  for (auto *s : sums) n += s->size();
  PetscFunctionBeginUser;
  PetscCheck(state.size() == n, PETSC_COMM_SELF, PETSC_ERR_FILE_UNEXPECTED,
             "The checkpoint's %s state holds %zu numbers, this run needs %zu (another mesh or fractions?)", name,
             state.size(), n);
  *count = state[0];
  std::size_t at = 1;
  for (auto *s : sums)
    for (double &v : *s) v = state[at++];
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

PetscErrorCode ProfilesMonitor::setUp(const RunContext &run, const FractionState &, const std::string &dir) {
  PetscFunctionBeginUser;
  comm = run.db.layout().comm();
  fractions = &run.fractions;
  rho = run.solidDensity;
  path = dir + "/profiles.csv";
  sums.assign(static_cast<std::size_t>(sampler->geometry().numLayers()) * fractions->size(), 0.0);
  scalars = run.scalarNames ? *run.scalarNames : std::vector<std::string>{};
  amountSums.assign(static_cast<std::size_t>(sampler->geometry().numLayers()) * scalars.size(), 0.0);
  count = 0.0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ProfilesMonitor::sample(const MonitorContext &ctx) {
  PetscFunctionBeginUser;
  if (!window.contains(ctx.time)) PetscFunctionReturn(PETSC_SUCCESS);
  const std::vector<double> *perLayer;
  PetscCall(sampler->masses(ctx, &perLayer));
  for (std::size_t k = 0; k < sums.size(); ++k) sums[k] += (*perLayer)[k];
  if (!scalars.empty()) {
    const std::vector<double> *amounts;
    PetscCall(sampler->amounts(ctx, &amounts));
    const std::size_t nf = fractions->size();
    for (std::size_t k = 0; k < amountSums.size(); ++k) // k = l * ns + s
      for (std::size_t i = 0; i < nf; ++i) amountSums[k] += (*amounts)[k * nf + i];
  }
  count += 1.0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ProfilesMonitor::flush() {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank != 0 || count == 0.0) PetscFunctionReturn(PETSC_SUCCESS);
  const int nf = fractions->size();
  const HorizontalLayers &g = sampler->geometry();
  char line[256];
  std::snprintf(line, sizeof line,
                "# SI units: z [m] layer centre; alpha = solid volume of the fraction in the layer / layer volume, "
                "mean over %.0f samples in [%g, %g] s\nz",
                count, window.begin, window.end);
  std::string text = line;
  for (int i = 0; i < nf; ++i) text += ",alpha_" + fractions->label(i);
  text += ",alpha_total";
  for (const std::string &name : scalars) text += "," + name; // mass-weighted over the classes and the window
  text += "\n";
  const std::size_t ns = scalars.size();
  for (int l = 0; l < g.numLayers(); ++l) {
    text += formatNumber(g.height(l));
    double total = 0.0, mass = 0.0;
    for (int i = 0; i < nf; ++i) {
      const double alpha = sums[static_cast<std::size_t>(l) * nf + i] / count / (rho * g.volume(l));
      total += alpha;
      mass += sums[static_cast<std::size_t>(l) * nf + i];
      text += "," + formatNumber(alpha);
    }
    text += "," + formatNumber(total);
    for (std::size_t s = 0; s < ns; ++s) text += "," + formatNumber(mass > 0.0 ? amountSums[l * ns + s] / mass : std::nan(""));
    text += "\n";
  }
  PetscCall(writeFileAtomically(path, text));
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::vector<double> ProfilesMonitor::saveState() const {
  std::vector<double> state{count};
  state.insert(state.end(), sums.begin(), sums.end());
  state.insert(state.end(), amountSums.begin(), amountSums.end()); // none without scalars
  return state;
}

PetscErrorCode ProfilesMonitor::restoreState(const std::vector<double> &state) {
  return restoreSums(state, "profiles.csv", &count, {&sums, &amountSums});
}

PetscErrorCode HalvesMonitor::setUp(const RunContext &run, const FractionState &, const std::string &dir) {
  PetscFunctionBeginUser;
  comm = run.db.layout().comm();
  fractions = &run.fractions;
  path = dir + "/halves.csv";
  bottomSum.assign(fractions->size(), 0.0);
  topSum.assign(fractions->size(), 0.0);
  scalars = run.scalarNames ? *run.scalarNames : std::vector<std::string>{};
  const std::size_t withScalars = scalars.empty() ? 0 : fractions->size();
  bottomMass.assign(withScalars, 0.0);
  topMass.assign(withScalars, 0.0);
  bottomAmount.assign(withScalars * scalars.size(), 0.0);
  topAmount.assign(withScalars * scalars.size(), 0.0);
  count = 0.0;
  if (!std::isnan(splitHeight)) { // the last layer whose centre is at or below the height
    const HorizontalLayers &g = sampler->geometry();
    const double low = g.height(0), high = g.height(g.numLayers() - 1);
    PetscCheck(splitHeight >= std::min(low, high) && splitHeight <= std::max(low, high), comm,
               PETSC_ERR_USER_INPUT, "-halves_split %s m is outside the layer centres %s to %s m of the mesh",
               plain(splitHeight).c_str(), plain(std::min(low, high)).c_str(), plain(std::max(low, high)).c_str());
    const bool upward = high > low;
    fixedSplit = -1;
    for (int l = 0; l < g.numLayers(); ++l)
      if (upward ? g.height(l) <= splitHeight : g.height(l) >= splitHeight) fixedSplit = l;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode HalvesMonitor::sample(const MonitorContext &ctx) {
  PetscFunctionBeginUser;
  if (!window.contains(ctx.time)) PetscFunctionReturn(PETSC_SUCCESS);
  const std::vector<double> *perLayer;
  PetscCall(sampler->masses(ctx, &perLayer));
  const int nf = fractions->size();
  const int split = std::isnan(splitHeight) ? layers::medianLayer(*perLayer, nf) : fixedSplit;
  std::vector<double> bottom, top;
  layers::halves(*perLayer, nf, split, &bottom, &top);
  // As rcfd reference: an empty half adds nothing, the sample still counts.
  for (int i = 0; i < nf; ++i) {
    if (std::isfinite(bottom[i])) bottomSum[i] += bottom[i];
    if (std::isfinite(top[i])) topSum[i] += top[i];
  }
  if (!scalars.empty()) { // the halves' masses and amounts, for the classes' values in each
    const std::vector<double> *amounts;
    PetscCall(sampler->amounts(ctx, &amounts));
    const int na = static_cast<int>(scalars.size()) * nf, nl = static_cast<int>(perLayer->size()) / nf;
    for (int l = 0; l < nl; ++l) {
      const bool low = l <= split;
      for (int i = 0; i < nf; ++i) (low ? bottomMass : topMass)[i] += (*perLayer)[l * nf + i];
      for (int k = 0; k < na; ++k) (low ? bottomAmount : topAmount)[k] += (*amounts)[l * na + k];
    }
  }
  count += 1.0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode HalvesMonitor::flush() {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank != 0 || count == 0.0) PetscFunctionReturn(PETSC_SUCCESS);
  const double d32 = fractions->inventorySauterDiameter();
  char line[320];
  std::snprintf(line, sizeof line,
                "# mass fractions of each size class below (up to and with the split layer) / above the %s, "
                "mean over %.0f samples in [%g, %g] s; diameter [m]; d_over_d32: diameter / inventory d32 = %.6g m\n",
                std::isnan(splitHeight) ? "bed's mass-median layer" : "layer of -halves_split", count, window.begin,
                window.end, d32);
  std::string text = std::string(line) + "class,diameter,bottom_mass_fraction,top_mass_fraction,d_over_d32";
  for (const std::string &name : scalars) text += ",bottom_" + name + ",top_" + name; // mass-weighted, the window
  text += "\n";
  const int nf = fractions->size();
  const auto value = [](double amount, double mass) { return formatNumber(mass > 0.0 ? amount / mass : std::nan("")); };
  for (int i = 0; i < nf; ++i) {
    text += fractions->label(i) + "," + formatNumber(fractions->diameter(i)) + "," +
            formatNumber(bottomSum[i] / count) + "," + formatNumber(topSum[i] / count) + "," +
            formatNumber(fractions->diameter(i) / d32);
    for (std::size_t s = 0; s < scalars.size(); ++s)
      text += "," + value(bottomAmount[s * nf + i], bottomMass[i]) + "," + value(topAmount[s * nf + i], topMass[i]);
    text += "\n";
  }
  PetscCall(writeFileAtomically(path, text));
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::vector<double> HalvesMonitor::saveState() const {
  std::vector<double> state{count};
  state.insert(state.end(), bottomSum.begin(), bottomSum.end());
  state.insert(state.end(), topSum.begin(), topSum.end());
  for (const auto *sum : {&bottomMass, &topMass, &bottomAmount, &topAmount}) // none without scalars
    state.insert(state.end(), sum->begin(), sum->end());
  return state;
}

PetscErrorCode HalvesMonitor::restoreState(const std::vector<double> &state) {
  return restoreSums(state, "halves.csv", &count, {&bottomSum, &topSum, &bottomMass, &topMass, &bottomAmount, &topAmount});
}

PetscErrorCode ScalarProfilesMonitor::setUp(const RunContext &run, const FractionState &, const std::string &dir) {
  PetscFunctionBeginUser;
  comm = run.db.layout().comm();
  fractions = &run.fractions;
  path = dir + "/scalar_profiles.csv";
  PetscCall(layers.setUp(run.db));
  const std::size_t nl = layers.numLayers(), nf = fractions->size();
  massSums.assign(nl * nf, 0.0);
  amountSums.assign(nl * names.size() * nf, 0.0);
  count = 0.0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

// Two passes over the cells and two reductions per sample in the window.
PetscErrorCode ScalarProfilesMonitor::sample(const MonitorContext &ctx) {
  PetscFunctionBeginUser;
  if (!window.contains(ctx.time)) PetscFunctionReturn(PETSC_SUCCESS);
  std::vector<double> masses, amounts;
  PetscCall(layers.fractionMasses(ctx.state, &masses));
  PetscCall(layers.fractionMasses(ctx.state.amounts(), static_cast<int>(names.size()) * fractions->size(), &amounts));
  for (std::size_t k = 0; k < massSums.size(); ++k) massSums[k] += masses[k];
  for (std::size_t k = 0; k < amountSums.size(); ++k) amountSums[k] += amounts[k];
  count += 1.0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ScalarProfilesMonitor::flush() {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank != 0 || count == 0.0) PetscFunctionReturn(PETSC_SUCCESS);
  const int nf = fractions->size(), ns = static_cast<int>(names.size());
  char line[256];
  std::snprintf(line, sizeof line,
                "# z [m] layer centre; mass_ [kg] mean per layer and class; NAME_ the scalar's value (amount / mass), "
                "mass-weighted over %.0f samples in [%g, %g] s\nz",
                count, window.begin, window.end);
  std::string text = line;
  for (int i = 0; i < nf; ++i) text += ",mass_" + fractions->label(i);
  for (const std::string &n : names) {
    for (int i = 0; i < nf; ++i) text += "," + n + "_" + fractions->label(i);
    text += "," + n + "_all";
  }
  text += "\n";
  for (int l = 0; l < layers.numLayers(); ++l) {
    text += formatNumber(layers.height(l));
    double solid = 0.0;
    for (int i = 0; i < nf; ++i) {
      solid += massSums[l * nf + i];
      text += "," + formatNumber(massSums[l * nf + i] / count);
    }
    for (int s = 0; s < ns; ++s) {
      double all = 0.0;
      for (int i = 0; i < nf; ++i) {
        const double m = massSums[l * nf + i], a = amountSums[(static_cast<std::size_t>(l) * ns + s) * nf + i];
        all += a;
        text += "," + formatNumber(m > 0.0 ? a / m : std::nan(""));
      }
      text += "," + formatNumber(solid > 0.0 ? all / solid : std::nan(""));
    }
    text += "\n";
  }
  PetscCall(writeFileAtomically(path, text));
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::vector<double> ScalarProfilesMonitor::saveState() const {
  std::vector<double> state{count};
  state.insert(state.end(), massSums.begin(), massSums.end());
  state.insert(state.end(), amountSums.begin(), amountSums.end());
  return state;
}

PetscErrorCode ScalarProfilesMonitor::restoreState(const std::vector<double> &state) {
  return restoreSums(state, "scalar_profiles.csv", &count, {&massSums, &amountSums});
}

} // namespace rcfd
