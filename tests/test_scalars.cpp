// Scalars carried with the fractions (-scalars, docs/scalars.md), on the small
// database along a stitched path (random sequences joined by jumps) through
// shift, drift, dispersion and the column carry:
//  - a uniform scalar stays uniform to round-off (1e-12 relative) in every
//    cell and fraction holding mass, and its total is value x mass;
//  - a scalar hot in the bottom layers only stays within its initial bounds
//    (a swapped mass carries its sender's value) and its total is kept to
//    1e-12 (the ledger closes);
//  - the field files hold each scalar's value per fraction and cell;
//  - a first-order decay's total is exp(-k t) times its start, to 1e-12;
//  - the run on the ranks of the test equals the same run on one rank
//    (PETSC_COMM_SELF) to 1e-12, masses and amounts (as rcfd's masses do);
//  - profiles.csv and halves.csv gain each scalar's value per layer and per
//    class and half (the uniform one's 300, the zone's scalar_profiles.csv's);
//  - a run restarted from its mid-run checkpoint ends with the same bits, and
//    writes the same scalars.csv, profiles.csv and halves.csv, byte for byte;
//  - initial values from a file (a value per cell and fraction) give amount =
//    mass x value exactly;
//  - a negative or NaN initial value
//    (given or in a file), a file of another shape are refused with one sentence.
// Runs at 1 and 2 ranks.  usage: test_scalars DIR -db SMALL.h5 [run options]
#include "check.hpp"
#include "scoped_options.hpp"
#include "state_access.hpp"
#include "scalar_run.hpp"
#include "base/petsc_compat.hpp"
#include "base/csv.hpp"
#include "base/h5.hpp"
#include "rcfd/run.hpp"

#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

using namespace rcfd;

namespace {

constexpr double kT = 0.6, kDecay = 1.7;
const std::string kScalars =
    " -scalars temperature,moisture,tracer -scalar_temperature_initial 300 -scalar_moisture_initial 0.1"
    " -zones hot -zone_hot_layers 0,3 -scalar_moisture_zones hot -scalar_moisture_zone_values 0.4"
    " -scalar_tracer_initial 2 -scalar_tracer_decay 1.7 -pipeline shift,drift,dispersion,carry"
    " -dispersion_coefficient 2e-4 -path_type random"
    " -path_seed 5 -monitor_digits 17 -profiles -halves -halves_split 0.1 -scalar_profiles";

using Outcome = test::ScalarOutcome;
using test::fileBytes;

PetscErrorCode runCase(MPI_Comm comm, const std::string &options, const std::string &dir, Outcome *out,
                       bool fields = false) {
  return test::runScalarCaseWith(comm, OperatorRegistry::withBuiltins(), options, dir, out, fields);
}

/// profiles.csv and halves.csv (rank 0): each scalar's value per layer and per half, mass-weighted over
/// the classes and the window: the uniform temperature 300 wherever there is solid (NaN elsewhere),
/// the moisture per layer scalar_profiles.csv's moisture_all, and per class and half the mass-weighted
/// mean of scalar_profiles.csv's values per layer below and above the split (z <= 0.1 m), to the
/// digits the files hold (9).
void checkProfilesAndHalves(const std::string &dir, const std::vector<std::string> &labels) {
  const csv::Table profiles = csv::Table::read(dir + "/profiles.csv"),
                   halves = csv::Table::read(dir + "/halves.csv"),
                   scalar = csv::Table::read(dir + "/scalar_profiles.csv");
  RCFD_CHECK(profiles.columns().back() == "tracer" && profiles.find({"alpha_total"}) + 4 ==
                                                          static_cast<int>(profiles.columns().size()));
  RCFD_CHECK(profiles.numRows() == scalar.numRows());
  int solid = 0, wrong = 0;
  for (std::size_t r = 0; r < profiles.numRows(); ++r) {
    const double T = profiles.numberOrNan(r, profiles.find({"temperature"}));
    const double X = profiles.numberOrNan(r, profiles.find({"moisture"}));
    const double all = scalar.numberOrNan(r, scalar.find({"moisture_all"}));
    if (!(profiles.number(r, profiles.find({"alpha_total"})) > 0.0)) {
      wrong += !std::isnan(T);
      continue;
    }
    ++solid;
    wrong += !(std::fabs(T / 300.0 - 1.0) < 1e-9) || !(std::fabs(X / all - 1.0) < 1e-8);
  }
  RCFD_CHECK(solid >= 5 && wrong == 0);
  for (std::size_t c = 0; c < labels.size(); ++c) {
    double mass[2] = {0.0, 0.0}, amount[2] = {0.0, 0.0}; // bottom, top
    for (std::size_t r = 0; r < scalar.numRows(); ++r) {
      const double m = scalar.number(r, scalar.find({"mass_" + labels[c]}));
      if (!(m > 0.0)) continue;
      const int half = scalar.number(r, 0) <= 0.1 ? 0 : 1;
      mass[half] += m;
      amount[half] += m * scalar.number(r, scalar.find({"moisture_" + labels[c]}));
    }
    RCFD_CHECK(halves.field(c, 0) == labels[c]);
    RCFD_CHECK_CLOSE(halves.number(c, halves.find({"bottom_moisture"})) / (amount[0] / mass[0]), 1.0, 1e-8);
    RCFD_CHECK_CLOSE(halves.number(c, halves.find({"top_moisture"})) / (amount[1] / mass[1]), 1.0, 1e-8);
    RCFD_CHECK(halves.number(c, halves.find({"bottom_moisture"})) > 0.15); // the wet zone is at the bottom
    RCFD_CHECK(halves.number(c, halves.find({"top_temperature"})) == 300.0);
  }
}

} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  {
    const std::string dir = test::rankCountDirectory(argc, argv, "scalars");
    PetscMPIInt rank;
    PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
    const std::string opts = kScalars + " -t_end " + std::to_string(kT);
    Outcome all;
    PetscCall(runCase(PETSC_COMM_WORLD, opts, dir + "/all", &all, true));
    const int nf = static_cast<int>(all.initialMass.size()), ns = 3, w = ns * nf;
    const std::size_t cells = all.masses.size() / nf;
    RCFD_CHECK(all.jumps >= 5);
    RCFD_CHECK(all.amounts.size() == cells * w);

    // Uniform stays uniform; the zone's values stay within their bounds; no negative amount; totals kept
    // (the tracer's: 2 x mass at the start, times exp(-k t)).
    test::checkScalarsCarried(all, kT, kDecay, true, "stitched");

    // The last field file: the uniform scalar's value per fraction and cell is
    // 300 where the fraction has mass (NaN elsewhere), the zone's within its bounds.
    if (rank == 0) {
      h5::File f = h5::File::openRead(dir + "/all/fields_000001.h5", MPI_COMM_NULL);
      int valued = 0, wrong = 0;
      for (const std::string &label : all.labels) {
        for (double v : f.read<double>("/temperature_" + label))
          if (!std::isnan(v)) ++valued, wrong += std::fabs(v / 300.0 - 1.0) > 1e-12;
        for (double v : f.read<double>("/moisture_" + label))
          if (!std::isnan(v)) wrong += v < 0.1 * (1.0 - 1e-12) || v > 0.4 * (1.0 + 1e-12);
      }
      RCFD_CHECK(valued > 100 && wrong == 0);
      RCFD_CHECK(f.read<double>("/tracer").size() == cells);
    }

    // The ranks of the test equal one rank to 1e-12, as the masses do in
    // rcfd (tests/test_rank_equivalence.sh): sums over the ranks (the
    // ledgers', the drift's limits) round in another order.
    Outcome alone;
    PetscCall(runCase(PETSC_COMM_SELF, opts, dir + "/alone" + std::to_string(rank), &alone));
    RCFD_CHECK_CLOSE(test::largestDifference(alone, all), 0.0, 1e-12);

    // Restarted at half time: the same bits and the same scalars.csv.
    Outcome first, second;
    PetscCall(runCase(PETSC_COMM_WORLD, kScalars + " -t_end " + std::to_string(kT / 2) + " -checkpoint_every " +
                                            std::to_string(kT / 2), dir + "/first", &first));
    PetscCall(runCase(PETSC_COMM_WORLD, opts + " -restart " + dir + "/first/checkpoint.h5", dir + "/first", &second));
    RCFD_CHECK(second.masses == all.masses);
    RCFD_CHECK(second.amounts == all.amounts);
    if (rank == 0)
      for (const std::string name : {"scalars.csv", "profiles.csv", "halves.csv"}) {
        const std::string a = fileBytes(dir + "/all/" + name), b = fileBytes(dir + "/first/" + name);
        RCFD_CHECK(!a.empty() && a == b);
      }
    if (rank == 0) checkProfilesAndHalves(dir + "/all", all.labels);

    auto refused = [&](const std::string &more, const std::string &sentence) {
      ErrorCapture capture;
      Outcome none;
      const PetscErrorCode status = runCase(PETSC_COMM_WORLD, opts + more, dir + "/refused", &none);
      RCFD_CHECK(status != 0);
      if (capture.message().find(sentence) == std::string::npos)
        test::fail(__FILE__, __LINE__, "expected '" + sentence + "', got '" + capture.message() + "'");
    };

    // Initial values from a file: a value per cell and fraction, amount = mass x value.
    auto valuesFile = [&](const std::string &name, std::vector<double> values, hsize_t cols) {
      const std::string path = dir + "/" + name + ".h5";
      if (rank == 0) {
        h5::File f = h5::File::create(path);
        f.write("/values", values, cols);
        f.close();
      }
      MPI_Barrier(PETSC_COMM_WORLD);
      return path;
    };
    std::vector<double> given(cells * nf);
    for (std::size_t c = 0; c < cells; ++c)
      for (int i = 0; i < nf; ++i) given[c * nf + i] = 10.0 + static_cast<double>(c % 7) + 0.5 * i;
    {
      ScopedOptions scoped(opts + " -scalar_moisture_initial_file " + valuesFile("values", given, nf) +
                           " -output_dir " + dir + "/file");
      const OperatorRegistry registry = OperatorRegistry::withBuiltins();
      Run run(PETSC_COMM_WORLD, registry);
      PetscCall(run.setFromOptions());
      run.setQuiet(true);
      run.setWriteFields(false);
      PetscCall(run.setUp());
      const std::vector<double> m = test::gatherNatural(run.database(), run.state().masses(), nf);
      const std::vector<double> a = test::gatherNatural(run.database(), run.state().amounts(), w);
      int wrong = 0, held = 0;
      for (std::size_t c = 0; c < cells; ++c)
        for (int i = 0; i < nf; ++i) {
          held += m[c * nf + i] > 0.0;
          wrong += a[c * w + nf + i] != m[c * nf + i] * given[c * nf + i]; // moisture: the file's
          wrong += a[c * w + i] != m[c * nf + i] * 300.0;                   // temperature: uniform
        }
      RCFD_CHECK(held > 100 && wrong == 0);
    }
    std::vector<double> negative = given;
    negative[3] = -1.0;
    refused(" -scalar_moisture_initial_file " + valuesFile("negative", negative, nf),
            "/values holds 1 negative or non-finite (NaN, inf) values; expected values >= 0");
    refused(" -scalar_moisture_initial_file " + valuesFile("short", std::vector<double>(given.begin(), given.end() - nf), nf),
            "/values should be " + std::to_string(cells) + " cells x " + std::to_string(nf) + " fractions");

    // Refusals, each with its sentence.
    refused(" -pipeline shift,drift,dispersion,carry,feed -feed_rate 1 -feed_zone hot",
            "-feed_scalar_temperature is not given; the feed needs the value of every scalar it brings");
    refused(" -restart " + dir + "/first/checkpoint.h5 -scalar_tracer_decay 1",
            "continues a run made with other scalars or scalar options");
    refused(" -scalar_temperature_initial -1", "-scalar_temperature_initial");
    refused(" -scalar_temperature_initial nan", "-scalar_temperature_initial");
    refused(" -scalar_moisture_zone_values -0.5", "-scalar_moisture_zone_values");
    refused(" -scalar_moisture_zone_values 0.2,0.3", "-scalar_moisture_zone_values has 2 values but");
  }
  const int failed = rcfd::test::globalFailures();
  PetscCall(PetscFinalize());
  return failed ? 1 : 0;
}
