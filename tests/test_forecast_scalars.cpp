// Forecasts that carry the run's scalars (docs/live.md, "Forecasts"): a live spray-dry bed on the
// small database (Gunn's exchange, a spray zone at the bottom, a discharge, a tracer at 1) with a
// forecast every 0.1 s of 2 members 0.1 s ahead:
//  - the forecasts change no bit of the live state (masses, amounts, the sources' account, bottom.csv);
//  - a what-if schedule equal to the held conditions (u_sup, spray_rate, gas_temperature) gives
//    forecast.csv byte for byte as none;
//  - a what-if that stops the spray forecasts a drier bottom layer and product than holding it;
//  - the product's tracer (1 everywhere) is 1 in every forecast, to 1e-12;
//  - the wet-bottom warning's forecast (-moisture_warning) in forecast.csv and, in words, status.json
//    (with the run's own wet-bottom warning);
//  - a run stopped by its stop file and restarted writes the uninterrupted forecast.csv byte for byte;
//  - the ranks of the test write one rank's forecast.csv (1e-10).
// Runs at 1 and 2 ranks.  usage: test_forecast_scalars DIR -db SMALL.h5
#include "check.hpp"
#include "scalar_run.hpp"
#include "base/petsc_compat.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace rcfd;

namespace {

const std::string kBed = " -fractions_diameters 1.459e-3,4.075e-3 -fractions_mass_shares 0.564,0.436"
                         " -pipeline shift,drift,carry,discharge -path_type random -path_seed 5 -mass_check_every 1"
                         " -zones spray,discharge -zone_spray_box 0,0.2,0,0.05,0,0.05"
                         " -zone_discharge_box 0.18,0.2,0,0.05,0,0.03 -discharge_rate 0.1"
                         " -scalars temperature,moisture,tracer -scalar_tracer_initial 1"
                         " -scalar_temperature_initial 300 -scalar_exchange_model gunn"
                         " -scalar_gas_model plug -scalar_gas_humidity 0.005 -scalar_heat_of_evaporation 2.26e6"
                         " -bottom_layer -moisture_warning 0.03 -moisture_warning_umf_share 0.5 -monitor_digits 17"
                         " -status 0 -live_poll 0.01";
const std::string kForecast = " -forecast_every 0.1 -forecast_horizon 0.1 -forecast_members 2";

using Outcome = test::ScalarOutcome;
constexpr auto &runCase = test::runScalarCase;

void writeText(const std::string &path, const std::string &text) { // rank 0, before any rank reads it
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0) std::ofstream(path) << text;
  MPI_Barrier(PETSC_COMM_WORLD);
}

std::string readText(const std::string &path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// forecast.csv's column `name`, one value per row.
std::vector<double> column(const std::string &file, const std::string &name) {
  std::ifstream in(file);
  std::string line, cell;
  std::getline(in, line);
  std::stringstream header(line);
  int k = -1;
  for (int at = 0; std::getline(header, cell, ','); ++at)
    if (cell == name) k = at;
  std::vector<double> out;
  while (k >= 0 && std::getline(in, line)) {
    std::stringstream row(line);
    for (int at = 0; std::getline(row, cell, ','); ++at)
      if (at == k) out.push_back(std::strtod(cell.c_str(), nullptr));
  }
  return out;
}

/// Every number of two CSV files of the same shape within `tol` relative to the larger (NaN = NaN); a
/// spread (a column ..._spread after its ..._mean) relative to its mean: the members' round-off.
bool sameNumbers(const std::string &a, const std::string &b, double tol) {
  std::ifstream x(a), y(b);
  std::string p, q, u, v, name;
  std::getline(x, p), std::getline(y, q);
  if (p != q || p.empty()) return false;
  std::vector<bool> spread;
  for (std::stringstream h(p); std::getline(h, name, ',');)
    spread.push_back(name.size() > 7 && name.compare(name.size() - 7, 7, "_spread") == 0);
  while (std::getline(x, p)) {
    if (!std::getline(y, q)) return false;
    std::stringstream r(p), s(q);
    double mean = 0.0;
    for (std::size_t k = 0; std::getline(r, u, ','); ++k) {
      if (!std::getline(s, v, ',')) return false;
      const double m = std::strtod(u.c_str(), nullptr), n = std::strtod(v.c_str(), nullptr);
      if (std::isnan(m) != std::isnan(n)) return false;
      const double scale = std::fmax(std::fmax(std::fabs(m), std::fabs(n)), k < spread.size() && spread[k] ? mean : 0.0);
      if (!std::isnan(m) && std::fabs(m - n) > tol * scale + 1e-15) return false;
      mean = std::fabs(m);
    }
  }
  return !std::getline(y, q);
}

} // namespace

int main(int argc, char **argv) {
  return test::rankTestMain(argc, argv, "forecast_scalars", [&](const std::string &dir) -> PetscErrorCode {
    PetscFunctionBeginUser;
    PetscMPIInt rank, size;
    PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
    PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
    const std::string liveFile = dir + "/live.csv";
    writeText(liveFile, "time_s,u_sup,spray_rate,gas_temperature\n0,1.25,0.05,330\n0.3,1.25,0.05,330\n");
    const std::string live = kBed + " -live " + liveFile + " -live_end 0.3";

    // The live state with and without forecasts: the same bits.
    Outcome plain, held;
    PetscCall(runCase(PETSC_COMM_WORLD, live, dir + "/plain", &plain));
    PetscCall(runCase(PETSC_COMM_WORLD, live + kForecast + " -status 1", dir + "/held", &held));
    RCFD_CHECK(plain.masses == held.masses);
    RCFD_CHECK(plain.amounts == held.amounts);
    RCFD_CHECK(plain.account == held.account);
    RCFD_CHECK(readText(dir + "/plain/bottom.csv") == readText(dir + "/held/bottom.csv"));
    RCFD_CHECK(plain.account[0] > 0.0 && plain.account[2] > 0.0); // sprayed and dried
    const std::string heldCsv = dir + "/held/forecast.csv";
    RCFD_CHECK(column(heldCsv, "time_s").size() == 4);

    // A what-if equal to the held conditions: forecast.csv byte for byte.
    writeText(dir + "/same.csv", "time_s,u_sup,spray_rate,gas_temperature\n0,1.25,0.05,330\n");
    Outcome same;
    PetscCall(runCase(PETSC_COMM_WORLD, live + kForecast + " -forecast_schedule " + dir + "/same.csv", dir + "/same",
                      &same));
    RCFD_CHECK(readText(heldCsv) == readText(dir + "/same/forecast.csv"));

    // A what-if that stops the spray: a drier bottom layer and product in every forecast; the live state unchanged.
    writeText(dir + "/stop.csv", "time_s,spray_rate\n0,0\n");
    Outcome stopped;
    PetscCall(runCase(PETSC_COMM_WORLD, live + kForecast + " -forecast_schedule " + dir + "/stop.csv", dir + "/stop",
                      &stopped));
    RCFD_CHECK(stopped.amounts == plain.amounts);
    for (const char *name : {"moisture_bottom_mean", "product_moisture_mean"}) {
      const std::vector<double> wet = column(heldCsv, name), dry = column(dir + "/stop/forecast.csv", name);
      RCFD_CHECK(wet.size() == 4 && dry.size() == 4);
      for (std::size_t k = 0; k < wet.size() && k < dry.size(); ++k) RCFD_CHECK(dry[k] < wet[k]);
    }
    // The tracer, 1 in every particle, is 1 in every forecast's product.
    for (double v : column(heldCsv, "product_tracer_mean")) RCFD_CHECK_CLOSE(v, 1.0, 1e-12);
    // The wet-bottom warning: held, the bottom layer passes 0.03 kg/kg within 0.1 s from the forecast at
    // 0.2 s on; without the spray later or not at all.
    {
      const std::vector<double> wetIn = column(heldCsv, "wet_warning_in_first_s"),
                                dryIn = column(dir + "/stop/forecast.csv", "wet_warning_in_first_s");
      RCFD_CHECK(wetIn.size() == 4 && dryIn.size() == 4);
      for (std::size_t k = 0; k < wetIn.size() && k < dryIn.size(); ++k) RCFD_CHECK(!(dryIn[k] < wetIn[k]));
      RCFD_CHECK(wetIn.size() == 4 && std::isnan(wetIn[0]) && wetIn[3] >= 0.005 && wetIn[3] <= 0.1);
    }
    const std::string status = readText(dir + "/held/status.json");
    RCFD_CHECK(status.find("\"Forecast: 2 of 2 members' bottom layers get wet near de-fluidization within 0.1 s "
                           "(moisture above 0.03 kg/kg while u_mf is at least 50 % of u_sup), in about ") !=
               std::string::npos);
    // The run's own wet-bottom warning, once fired, in words too.
    RCFD_CHECK(status.find("\"Wet bottom layer: its moisture passed 0.03 kg/kg at t = ") != std::string::npos);
    if (status.find("bottom layers get wet") == std::string::npos)
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "status.json: %s\n", status.c_str()));

    // Stopped by its stop file at 0.15 s and restarted with the rest of the file: the uninterrupted forecast.csv.
    {
      const std::string part = dir + "/part.csv", stop = dir + "/stop";
      writeText(part, "time_s,u_sup,spray_rate,gas_temperature\n0,1.25,0.05,330\n0.15,1.25,0.05,330\n");
      writeText(stop, "");
      Outcome first, second;
      PetscCall(runCase(PETSC_COMM_WORLD, kBed + kForecast + " -live " + part + " -live_stop_file " + stop,
                        dir + "/restarted", &first));
      if (rank == 0) {
        std::remove(stop.c_str());
        std::ofstream(part, std::ios::app) << "0.3,1.25,0.05,330\n";
      }
      PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
      RCFD_CHECK(column(dir + "/restarted/forecast.csv", "time_s").size() == 2); // 0 and 0.1 s
      PetscCall(runCase(PETSC_COMM_WORLD, kBed + kForecast + " -live " + part + " -live_end 0.3 -restart " + dir +
                                              "/restarted/checkpoint.h5", dir + "/restarted", &second));
      RCFD_CHECK(readText(heldCsv) == readText(dir + "/restarted/forecast.csv"));
      RCFD_CHECK(second.amounts == plain.amounts);
    }

    // The ranks of the test write one rank's forecast.csv.
    if (size > 1) {
      Outcome alone;
      const std::string own = dir + "/alone" + std::to_string(rank);
      PetscCall(runCase(PETSC_COMM_SELF, live + kForecast, own, &alone));
      const bool equal = sameNumbers(heldCsv, own + "/forecast.csv", 1e-10);
      RCFD_CHECK(equal);
      if (!equal) std::printf("rank %d: %s\nagainst\n%s\n", rank, readText(own + "/forecast.csv").c_str(),
                              readText(heldCsv).c_str());
    }
    PetscFunctionReturn(PETSC_SUCCESS);
  });
}
