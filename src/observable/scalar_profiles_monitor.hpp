// scalar_profiles.csv: each scalar's value per size class and cell layer,
// averaged over a time window (docs/scalars.md, "Answers"): where the bed is
// wet or hot, and for which sizes.  Written with the window monitors
// (src/observable/window_monitors.cpp).
#pragma once

#include "observable/answers.hpp"
#include "state/layer_masses.hpp"

#include <string>
#include <vector>

namespace rcfd {

/// Over the samples in the window, per layer l and class i, the sums of the
/// class's mass M_l,i and of each scalar's amount A_l,s,i; the file holds
/// z, the mean mass per layer and class (mass_<label>), and the value
/// A / M per scalar and class (NAME_<label>) and over all classes (NAME_all):
/// mass-weighted time means.  A layer without a class's mass has NaN there.
class ScalarProfilesMonitor final : public Monitor {
public:
  ScalarProfilesMonitor(std::vector<std::string> names, TimeWindow window)
      : names(std::move(names)), window(window) {}
  std::string type() const override { return "scalar_profiles"; }
  PetscErrorCode setUp(const RunContext &run, const FractionState &, const std::string &dir) override;
  PetscErrorCode sample(const MonitorContext &ctx) override;
  PetscErrorCode flush() override;
  std::vector<double> saveState() const override;
  PetscErrorCode restoreState(const std::vector<double> &state) override;

private:
  std::vector<std::string> names;
  TimeWindow window;
  HorizontalLayers layers;
  MPI_Comm comm = MPI_COMM_NULL;
  const FractionSet *fractions = nullptr;
  std::string path;
  double count = 0.0;
  std::vector<double> massSums, amountSums; // [l][i], [l][s][i]
};

} // namespace rcfd
