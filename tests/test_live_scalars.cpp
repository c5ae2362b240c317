// A live file drives the scalars' sources (docs/live.md, docs/scalars.md), on the small database
// along a stitched path:
//  - constant spray_rate, gas_temperature and u_sup columns give the bits of the options
//    (-scalar_spray_rate, -scalar_gas_temperature, -superficial_velocity), with Gunn's exchange and
//    the gas well mixed or in plug flow;
//  - a step of the gas temperature (300 K, then 450 K from 0.15 s) relaxes a well-mixed bed of one
//    class toward the new temperature as exp(-t / tau), tau = rho_s c_p d / (6 h), to 1e-12;
//  - a spray rate that changes (0, 0.05, 0.1 kg/s from 0, 0.1, 0.2 s; -scalar_spray_rate 0 and
//    the file's first rate 0 at set-up) sprays its integral, and sprayed = held + dried, to 1e-12;
//  - a step of u_sup (1.1, then 1.5 m/s from 0.15 s) changes Gunn's coefficients from that step on:
//    the heat from the gas lies strictly between the runs held at 1.1 and at 1.5 m/s;
//  - a run stopped by its stop file and restarted from its checkpoint gives the uninterrupted bits;
//  - the ranks of the test equal one rank to 1e-12.
// Runs at 1 and 2 ranks.  usage: test_live_scalars DIR -db SMALL.h5
#include "check.hpp"
#include "scalar_run.hpp"
#include "base/petsc_compat.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

using namespace rcfd;

namespace {

const std::string kBed = " -fractions_diameters 1.459e-3,4.075e-3 -fractions_mass_shares 0.564,0.436"
                         " -pipeline shift,drift,carry -path_type random -path_seed 5 -mass_check_every 1"
                         " -zones spray -zone_spray_box 0.06,0.14,0,0.05,0.15,0.25 -scalars temperature,moisture"
                         " -scalar_temperature_initial 300 -scalar_exchange_model gunn"
                         " -scalar_gas_humidity_deficit 0.02 -scalar_heat_of_evaporation 2.26e6 -status 0";

using Outcome = test::ScalarOutcome;
constexpr auto &runCase = test::runScalarCase;

// A live file of `text` at `path`, written by rank 0 before any rank reads it.
void writeLive(const std::string &path, const std::string &text) {
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0) std::ofstream(path) << text;
  MPI_Barrier(PETSC_COMM_WORLD);
}

std::string live(const std::string &file, double end) {
  return " -live " + file + " -live_end " + std::to_string(end) + " -live_poll 0.01";
}

using test::scalarTotal;

} // namespace

int main(int argc, char **argv) {
  return test::rankTestMain(argc, argv, "live_scalars", [&](const std::string &dir) -> PetscErrorCode {
    PetscFunctionBeginUser;
    PetscMPIInt rank;
    PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));

    // Constant columns: the options' bits (the file's gas temperature and u_sup replace the case's).
    writeLive(dir + "/constant.csv", "time_s,u_sup,spray_rate,gas_temperature\n0,1.25,0.05,330\n0.2,1.25,0.05,330\n");
    for (const std::string gas : {" -scalar_gas_model inlet", " -scalar_gas_model plug -scalar_gas_humidity 0.005"}) {
      Outcome given, followed;
      PetscCall(runCase(PETSC_COMM_WORLD,
                        kBed + gas + " -scalar_spray_rate 0.05 -scalar_gas_temperature 330 -superficial_velocity 1.25"
                                     " -t_end 0.2", dir + "/given", &given));
      PetscCall(runCase(PETSC_COMM_WORLD, kBed + gas + " -scalar_gas_temperature 290" + live(dir + "/constant.csv", 0.2),
                        dir + "/followed", &followed));
      RCFD_CHECK(given.masses == followed.masses);
      RCFD_CHECK(given.amounts == followed.amounts);
      RCFD_CHECK(given.account == followed.account);
      RCFD_CHECK(given.account[3] > 0.0 && given.account[0] > 0.0); // heated and sprayed
    }

    // A step of the gas temperature: T - T_g relaxes as exp(-t / tau) toward 300 K, then toward 450 K.
    {
      const double rho = 1440.0, cp = 800.0, d = 2e-3, h = 500.0, t1 = 0.15, t2 = 0.3;
      writeLive(dir + "/gas.csv", "time_s,gas_temperature\n0,300\n0.15,450\n0.3,450\n");
      Outcome o;
      PetscCall(runCase(PETSC_COMM_WORLD,
                        " -fractions_diameters 2e-3 -fractions_mass_shares 1 -pipeline shift,carry -path_type random"
                        " -path_seed 5 -scalars temperature -scalar_temperature_initial 400 -scalar_exchange_model "
                        "constant -scalar_exchange_h 500 -scalar_solid_heat_capacity 800 -solid_density 1440 -status 0" +
                          live(dir + "/gas.csv", t2),
                        dir + "/relax", &o));
      const double tau = rho * cp * d / (6.0 * h), first = 300.0 + 100.0 * std::exp(-t1 / tau);
      const double expected = 450.0 + (first - 450.0) * std::exp(-(t2 - t1) / tau);
      double mass = 0.0, worst = 0.0, largest = 0.0;
      for (double m : o.masses) mass += m, largest = std::fmax(largest, m);
      for (std::size_t c = 0; c < o.masses.size(); ++c)
        if (o.masses[c] > 1e-9 * largest) worst = std::fmax(worst, std::fabs(o.amounts[c] / o.masses[c] / expected - 1.0));
      RCFD_CHECK_CLOSE(worst, 0.0, 1e-12);
      RCFD_CHECK_CLOSE(scalarTotal(o, 0) / (mass * expected), 1.0, 1e-12);
      RCFD_CHECK(first < 400.0 && expected > first); // cooled toward the first gas, then heated toward the second
      RCFD_CHECK_CLOSE(o.account[3] / (mass * cp * (expected - 400.0)), 1.0, 1e-12); // the heat from the gas
    }

    // A spray that changes, none at set-up (its zone is set up all the same): its integral is sprayed;
    // sprayed = held + dried.
    const std::string varying = dir + "/varying.csv";
    writeLive(varying, "time_s,u_sup,spray_rate,gas_temperature\n0,1.1,0,330\n0.1,1.3,0.05,340\n0.2,1.5,0.1,320\n"
                       "0.3,1.5,0.1,320\n");
    const std::string varyingOptions = kBed + " -scalar_spray_rate 0" + live(varying, 0.3);
    Outcome spray;
    PetscCall(runCase(PETSC_COMM_WORLD, varyingOptions, dir + "/spray", &spray));
    {
      const double sprayed = spray.account[0], dried = spray.account[2], held = scalarTotal(spray, 1);
      RCFD_CHECK_CLOSE(sprayed / (0.05 * 0.1 + 0.1 * 0.1), 1.0, 1e-12);
      RCFD_CHECK(dried > 0.0 && held > 0.0);
      RCFD_CHECK_CLOSE((held + dried) / sprayed, 1.0, 1e-12);
      double lowest = 0.0;
      for (double a : spray.amounts) lowest = std::fmin(lowest, a);
      RCFD_CHECK(lowest >= 0.0);
    }

    // u_sup steps from 1.1 to 1.5 m/s at 0.15 s: Gunn's h grows with Re from that step on, so the heat
    // from the gas (at 330 K, the bed at 300 K) lies between the runs held at either velocity.
    {
      writeLive(dir + "/step.csv", "time_s,u_sup\n0,1.1\n0.15,1.5\n0.3,1.5\n");
      writeLive(dir + "/slow.csv", "time_s,u_sup\n0,1.1\n0.3,1.1\n");
      writeLive(dir + "/fast.csv", "time_s,u_sup\n0,1.5\n0.3,1.5\n");
      double heat[3];
      int k = 0;
      for (const char *name : {"slow", "step", "fast"}) {
        Outcome o;
        PetscCall(runCase(PETSC_COMM_WORLD, kBed + " -scalar_gas_temperature 330" + live(dir + "/" + name + ".csv", 0.3),
                          dir + "/" + name, &o));
        heat[k++] = o.account[3];
      }
      RCFD_CHECK(heat[0] > 0.0 && heat[0] < heat[1] && heat[1] < heat[2]);
      if (!(heat[0] < heat[1] && heat[1] < heat[2]))
        PetscCall(PetscPrintf(PETSC_COMM_WORLD, "heat from the gas at 1.1, stepped, 1.5 m/s: %.17g %.17g %.17g J\n",
                              heat[0], heat[1], heat[2]));
    }

    // Stopped by its stop file at 0.15 s and restarted from its checkpoint with the rest of the file:
    // the uninterrupted run's bits and sources' account.
    {
      const std::string part = dir + "/part.csv", stop = dir + "/stop";
      writeLive(part, "time_s,u_sup,spray_rate,gas_temperature\n0,1.1,0,330\n0.1,1.3,0.05,340\n0.15,1.3,0.05,340\n");
      writeLive(stop, "");
      Outcome first, second;
      PetscCall(runCase(PETSC_COMM_WORLD, kBed + " -scalar_spray_rate 0 -live " + part + " -live_stop_file " + stop +
                                              " -live_poll 0.01", dir + "/restarted", &first));
      if (rank == 0) {
        std::remove(stop.c_str());
        std::ofstream(part, std::ios::app) << "0.2,1.5,0.1,320\n0.3,1.5,0.1,320\n";
      }
      PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
      PetscCall(runCase(PETSC_COMM_WORLD, kBed + " -scalar_spray_rate 0" + live(part, 0.3) + " -restart " + dir +
                                              "/restarted/checkpoint.h5", dir + "/restarted", &second));
      RCFD_CHECK(first.account[0] > 0.0 && first.account[0] < spray.account[0]); // stopped part-way
      RCFD_CHECK(second.masses == spray.masses);
      RCFD_CHECK(second.amounts == spray.amounts);
      RCFD_CHECK(second.account == spray.account);
    }

    // The ranks of the test equal one rank to 1e-12.
    {
      Outcome alone;
      PetscCall(runCase(PETSC_COMM_SELF, varyingOptions, dir + "/alone" + std::to_string(rank), &alone));
      double worst = 0.0, largest = 0.0;
      for (double a : spray.amounts) largest = std::fmax(largest, std::fabs(a));
      for (std::size_t k = 0; k < spray.amounts.size(); ++k)
        worst = std::fmax(worst, std::fabs(alone.amounts[k] - spray.amounts[k]) / largest);
      RCFD_CHECK_CLOSE(worst, 0.0, 1e-12);
      RCFD_CHECK_CLOSE(alone.account[0] / spray.account[0], 1.0, 1e-12);
      RCFD_CHECK_CLOSE(alone.account[2] / spray.account[2], 1.0, 1e-12);
    }
    PetscFunctionReturn(PETSC_SUCCESS);
  });
}
