// Scalars through the granulator and with sources (docs/scalars.md, slice 2),
// on the small database along a stitched path:
//  - growth (closed and open top, the transfer and number readings), feed and
//    discharge keep a uniform scalar uniform to round-off (1e-12) when the
//    feed brings the same value, and the product's value (product.csv) is that
//    value; a tracer brought by the feed alone closes its ledger (the run
//    checks it every step at 1e-12 and would stop) and is never negative;
//  - a well-mixed bed (one class) relaxes to the gas temperature as
//    exp(-t / tau) with tau = rho_s c_p d / (6 h), to 1e-12;
//  - falling-rate drying (-scalar_critical_moisture) of a well-mixed bed: the constant rate down to X_c,
//    then X_c exp(-r (t - t_1) / X_c), to 1e-12;
//  - sprayed liquid = liquid held + liquid dried, to 1e-12 of the sprayed,
//    with the heat of evaporation taken from the temperature; no negative
//    amount; a bed dried out ends with exactly zero moisture, all of it dried;
//  - the bottom layer's u_mf raised by its moisture (-moisture_umf_coefficient): u_mf (1 + kappa X) in
//    bottom.csv, and the de-fluidized flag following it;
//  - the plug-flow gas (-scalar_gas_model plug): one layer against the closed-form implicit exchange;
//    over several layers of random particles the gas never overshoots (each layer's gas between its
//    inlet and its particles' temperatures), the heat the gas gives equals what the particles take to
//    round-off, its humidity never passes the saturation at the wettest surface; the saturation law
//    against tabulated water; a run's gas balance equals its particles' heat to round-off;
//  - the ranks of the test equal one rank to 1e-12 (granulator and sources);
//  - a run restarted from its mid-run checkpoint ends with the same bits, and
//    the same product.csv and scalars.csv, with scalars and sources.
// Runs at 1 and 2 ranks.  usage: test_scalar_sources DIR -db SMALL.h5
#include "check.hpp"
#include "scalar_run.hpp"
#include "base/csv.hpp"
#include "base/petsc_compat.hpp"
#include "state/scalar_sources.hpp"

#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

using namespace rcfd;

namespace {

const std::string kChamber =
    " -fractions_diameters 1.459e-3,2.0e-3,2.8e-3,4.075e-3 -fractions_mass_shares 0.25,0.25,0.25,0.25"
    " -pipeline shift,drift,carry,growth,feed,discharge -zones spray,feed,discharge"
    " -zone_spray_box 0.06,0.14,0,0.05,0.15,0.25 -zone_feed_box 0,0.04,0,0.05,0,0.07"
    " -zone_discharge_box 0.16,0.2,0,0.05,0,0.07 -growth_rate 5 -feed_rate 0.5 -discharge_rate 0.5"
    " -feed_mass_shares 0.7,0.1,0.1,0.1 -discharge_sample_interval 0.05 -path_type random -path_seed 5"
    " -mass_check_every 1 -monitor_digits 17 -scalars temperature,tracer -scalar_temperature_initial 300"
    " -feed_scalar_temperature 300 -feed_scalar_tracer 1";

const std::string kSpray =
    " -fractions_diameters 1.459e-3,4.075e-3 -fractions_mass_shares 0.564,0.436 -pipeline shift,drift,carry"
    " -path_type random -path_seed 5 -mass_check_every 1 -monitor_digits 17 -zones spray"
    " -zone_spray_box 0.06,0.14,0,0.05,0.15,0.25 -scalars temperature,moisture -scalar_temperature_initial 300"
    " -scalar_spray_rate 0.05 -scalar_exchange_model constant -scalar_exchange_h 100 -scalar_exchange_beta 0.05"
    " -scalar_gas_temperature 330 -scalar_gas_humidity_deficit 0.02 -scalar_heat_of_evaporation 2.26e6";

using Outcome = test::ScalarOutcome;
constexpr auto &runCase = test::runScalarCase;

using test::fileBytes;

// The last row's value of a CSV column (NaN when there is none).
double lastValue(const std::string &path, const std::string &column) {
  std::istringstream text(fileBytes(path));
  std::string header, line, last;
  std::getline(text, header);
  while (std::getline(text, line))
    if (!line.empty()) last = line;
  std::istringstream names(header), values(last);
  std::string name, value;
  while (std::getline(names, name, ',') && std::getline(values, value, ','))
    if (name == column) return std::stod(value);
  return std::nan("");
}

// Largest relative departure of scalar s's value from `value` in cells where a
// fraction holds more than a trace; and the smallest amount of any scalar.
void valueSpread(const Outcome &o, int s, double value, double *worst, double *lowest) {
  const int w = o.nf * o.ns;
  double largest = 0.0;
  for (double m : o.masses) largest = std::fmax(largest, m);
  *worst = 0.0;
  *lowest = 0.0;
  for (std::size_t c = 0; c < o.masses.size() / o.nf; ++c)
    for (int i = 0; i < o.nf; ++i) {
      for (int k = 0; k < o.ns; ++k) *lowest = std::fmin(*lowest, o.amounts[c * w + k * o.nf + i]);
      const double m = o.masses[c * o.nf + i];
      if (m > 1e-9 * largest) *worst = std::fmax(*worst, std::fabs(o.amounts[c * w + s * o.nf + i] / m / value - 1.0));
    }
}

using test::scalarTotal;

// A well-mixed bed (its first scalar at `expected` in every cell holding more than a trace, to 1e-12, and
// its total mass x expected); returns the bed's mass.
double checkWellMixed(const Outcome &o, double expected) {
  double worst, lowest, mass = 0.0;
  valueSpread(o, 0, expected, &worst, &lowest);
  RCFD_CHECK_CLOSE(worst, 0.0, 1e-12);
  for (double m : o.masses) mass += m;
  RCFD_CHECK_CLOSE(scalarTotal(o, 0) / (mass * expected), 1.0, 1e-12);
  return mass;
}

} // namespace

int main(int argc, char **argv) {
  return test::rankTestMain(argc, argv, "scalar_sources", [&](const std::string &dir) -> PetscErrorCode {
    PetscFunctionBeginUser;
    PetscMPIInt rank;
    PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));

    // The granulator: a uniform temperature stays uniform, whatever the growth's reading.
    Outcome chamber;
    const std::string full = kChamber + " -t_end 0.4";
    PetscCall(runCase(PETSC_COMM_WORLD, full, dir + "/chamber", &chamber));
    for (const std::string &variant : {std::string(""), std::string(" -growth_top open"),
                                       std::string(" -growth_mass number"), std::string(" -feed_keep_bulk 0 "
                                                                                       "-discharge_keep_bulk 0")}) {
      Outcome o;
      if (variant.empty()) o = chamber;
      else PetscCall(runCase(PETSC_COMM_WORLD, full + variant, dir + "/variant", &o));
      double worst, lowest;
      valueSpread(o, 0, 300.0, &worst, &lowest);
      if (!(worst <= 1e-12)) test::fail(__FILE__, __LINE__, "uniform temperature departs by " + std::to_string(worst) + " with" + variant);
      RCFD_CHECK(lowest >= 0.0);
      RCFD_CHECK(scalarTotal(o, 1) > 0.0); // the feed brought its tracer
    }
    if (rank == 0) RCFD_CHECK_CLOSE(lastValue(dir + "/chamber/product.csv", "product_temperature"), 300.0, 1e-9);
    if (rank == 0) {
      const double tracer = lastValue(dir + "/chamber/product.csv", "product_tracer");
      RCFD_CHECK(tracer > 0.0 && tracer < 1.0); // the product holds some of the feed's tracer, diluted
    }

    // A well-mixed bed of one class relaxes to the gas temperature: T - T_g = (T0 - T_g) exp(-t / tau).
    {
      const double rho = 1440.0, cp = 800.0, d = 2e-3, h = 500.0, t = 0.3;
      Outcome o;
      PetscCall(runCase(PETSC_COMM_WORLD,
                        " -fractions_diameters 2e-3 -fractions_mass_shares 1 -pipeline shift,carry -path_type random"
                        " -path_seed 5 -scalars temperature -scalar_temperature_initial 400 -scalar_exchange_model "
                        "constant -scalar_exchange_h 500 -scalar_gas_temperature 300 -scalar_solid_heat_capacity 800"
                        " -solid_density 1440 -t_end 0.3",
                        dir + "/relax", &o));
      const double tau = rho * cp * d / (6.0 * h), expected = 300.0 + 100.0 * std::exp(-t / tau);
      const double mass = checkWellMixed(o, expected);
      RCFD_CHECK(expected < 380.0); // a visible relaxation: t is a few tenths of tau
      // The heat from the gas is what the temperature lost, times c_p.
      RCFD_CHECK_CLOSE(o.account[3] / (mass * cp * (expected - 400.0)), 1.0, 1e-12);
    }

    // Falling-rate drying of a well-mixed bed (one class, constant beta): the constant rate
    // r = beta rho_g (Y_s - Y_g) 6 / (rho_s d) down to X_c, reached at t_1 = (X_0 - X_c) / r, then
    // X = X_c exp(-r (t - t_1) / X_c); to 1e-12 in every cell, and the liquid dried is what the bed lost.
    {
      const double rho = 1440.0, d = 2e-3, beta = 1.0, rhoG = 1.2, deficit = 0.02, X0 = 0.05, Xc = 0.04, t = 0.5;
      const double r = beta * rhoG * deficit * 6.0 / (rho * d), t1 = (X0 - Xc) / r;
      const double expected = Xc * std::exp(-r * (t - t1) / Xc);
      Outcome o;
      PetscCall(runCase(PETSC_COMM_WORLD,
                        " -fractions_diameters 2e-3 -fractions_mass_shares 1 -pipeline shift,carry -path_type random"
                        " -path_seed 5 -scalars moisture -scalar_moisture_initial 0.05 -scalar_exchange_model constant"
                        " -scalar_exchange_beta 1 -gas_density 1.2 -scalar_gas_humidity_deficit 0.02"
                        " -scalar_critical_moisture 0.04 -solid_density 1440 -t_end 0.5",
                        dir + "/falling", &o));
      const double mass = checkWellMixed(o, expected);
      RCFD_CHECK_CLOSE(o.account[2] / (mass * (X0 - expected)), 1.0, 1e-12);
      RCFD_CHECK(t1 > 0.1 && t1 < t - 0.1 && expected < 0.75 * Xc); // both periods, the falling one visibly
      // The closed form itself, step by step against one step: the same to round-off, from above and below X_c.
      for (const double start : {X0, 0.03}) {
        double X = start;
        for (int k = 0; k < 100; ++k) X = dryingRemains(X, r, t / 100, Xc);
        RCFD_CHECK_CLOSE(X / dryingRemains(start, r, t, Xc), 1.0, 1e-13);
      }
      RCFD_CHECK_CLOSE(dryingRemains(0.03, r, t, Xc) / (0.03 * std::exp(-r * t / Xc)), 1.0, 1e-15);
      RCFD_CHECK(dryingRemains(0.0, r, t, Xc) == 0.0 && dryingRemains(0.06, r, 0.1, Xc) == 0.06 - r * 0.1);
    }

    // A hot batch in the bottom layers mixes: its spread over the bed (scalar_mixing.csv) starts at 1
    // and falls; a tracer's likewise.
    {
      Outcome o;
      PetscCall(runCase(PETSC_COMM_WORLD,
                        kSpray + " -scalar_spray_rate 0 -scalar_exchange_model none -scalars temperature,tracer"
                                 " -zones hot -zone_hot_layers 0,3 -scalar_temperature_zones hot"
                                 " -scalar_temperature_zone_values 400 -scalar_tracer_zones hot"
                                 " -scalar_tracer_zone_values 1 -scalar_mixing -t_end 1",
                        dir + "/mixing", &o));
      if (rank == 0) {
        std::istringstream text(fileBytes(dir + "/mixing/scalar_mixing.csv"));
        std::string header, first;
        std::getline(text, header);
        std::getline(text, first);
        RCFD_CHECK(header == "time_s,spread_temperature,spread_tracer");
        RCFD_CHECK(first.rfind("0,1,1", 0) == 0);
        const double last = lastValue(dir + "/mixing/scalar_mixing.csv", "spread_temperature");
        RCFD_CHECK(last < 0.9 && last >= 0.0);
        RCFD_CHECK_CLOSE(last, lastValue(dir + "/mixing/scalar_mixing.csv", "spread_tracer"), 1e-9);
      }
    }

    // Spray and dry: sprayed = held + dried, to the ledger's tolerance; no negative amounts.
    Outcome spray;
    PetscCall(runCase(PETSC_COMM_WORLD, kSpray + " -t_end 0.3", dir + "/spray", &spray));
    {
      const double sprayed = spray.account[0], dried = spray.account[2], held = scalarTotal(spray, 1);
      RCFD_CHECK_CLOSE(sprayed, 0.05 * 0.3, 1e-12 * sprayed);
      RCFD_CHECK(dried > 0.0 && held > 0.0);
      RCFD_CHECK_CLOSE((held + dried) / sprayed, 1.0, 1e-12);
      RCFD_CHECK(spray.account[4] > 0.0); // evaporation cooled the solid
      double worst, lowest;
      valueSpread(spray, 0, 300.0, &worst, &lowest);
      RCFD_CHECK(lowest >= 0.0);
    }
    // The bottom layer's moisture (bottom.csv), sprayed into the bottom layers: the liquid there over its solid.
    {
      Outcome o;
      PetscCall(runCase(PETSC_COMM_WORLD,
                        kSpray + " -zones wet -zone_wet_layers 0,1 -scalar_spray_zone wet -scalar_exchange_model none -bottom_layer"
                                 " -moisture_warning 1e-3 -moisture_warning_umf_share 0.01 -superficial_velocity 1.1"
                                 " -moisture_umf_coefficient 50 -t_end 0.2",
                        dir + "/wet", &o));
      if (rank == 0) {
        const double wet = lastValue(dir + "/wet/bottom.csv", "moisture_bottom");
        RCFD_CHECK(wet > 1e-3); // above the warning's threshold
        // Nothing dries: the bed holds all that was sprayed.
        RCFD_CHECK_CLOSE(scalarTotal(o, 1) / (0.05 * 0.2), 1.0, 1e-12);
        // The moisture raises u_mf: u_mf,wet = u_mf (1 + 50 X) in every row (to the 10 digits printed), and the
        // de-fluidized flag follows it, here from a row where u_mf by size alone stays below u_sup.
        const csv::Table bottom = csv::Table::read(dir + "/wet/bottom.csv");
        const int umf = bottom.find({"umf_m_s"}), usup = bottom.find({"usup_m_s"}), flag = bottom.find({"defluidized"}),
                  X = bottom.find({"moisture_bottom"}), umfWet = bottom.find({"umf_wet_m_s"});
        int wrong = 0, wetOnly = 0;
        for (std::size_t r = 0; r < bottom.numRows(); ++r) {
          const double raised = bottom.number(r, umf) * (1.0 + 50.0 * bottom.number(r, X));
          wrong += !(std::fabs(bottom.number(r, umfWet) / raised - 1.0) < 1e-9);
          wrong += (bottom.number(r, flag) == 1.0) != (bottom.number(r, umfWet) >= bottom.number(r, usup));
          wetOnly += bottom.number(r, flag) == 1.0 && bottom.number(r, umf) < bottom.number(r, usup);
        }
        RCFD_CHECK(umfWet > 0 && wrong == 0 && wetOnly > 10);
      }
    }

    // Dried out: a bed with a little moisture and strong drying ends at exactly zero, all of it dried.
    {
      Outcome o;
      PetscCall(runCase(PETSC_COMM_WORLD,
                        kSpray + " -scalar_spray_rate 0 -scalar_moisture_initial 1e-4 -scalar_exchange_beta 5 -t_end 0.1",
                        dir + "/dry", &o));
      double mass = 0.0, lowest = 0.0;
      for (double m : o.masses) mass += m;
      for (double a : o.amounts) lowest = std::fmin(lowest, a);
      RCFD_CHECK(scalarTotal(o, 1) == 0.0 && lowest >= 0.0);
      RCFD_CHECK_CLOSE(o.account[2] / (1e-4 * mass), 1.0, 1e-12);
    }

    // The plug-flow gas, one layer and one particle group: the implicit exchange solves
    //   F (T_in - T_g) = U (T_g - T_p'),  C (T_p' - T_p) = U (T_g - T_p')   (F = G c_p,g dt, U = h S dt)
    // which Cramer's rule gives in closed form.
    {
      const double F = 50.0, C = 200.0, U = 80.0, Tin = 360.0, Tp = 300.0, det = (F + U) * (C + U) - U * U;
      const double Tg = (F * Tin * (C + U) + U * C * Tp) / det, Tp1 = ((F + U) * C * Tp + U * F * Tin) / det;
      const double g = gas_layer::share(U, C);
      std::vector<double> T, Y;
      gas_layer::sweep(Tin, 0.005, F, 0.01, {g, g * Tp, 0.02, 0.02 * 0.05}, &T, &Y);
      RCFD_CHECK_CLOSE(T[0] / Tg, 1.0, 1e-14);
      RCFD_CHECK_CLOSE((Tp + g * (T[0] - Tp) / C) / Tp1, 1.0, 1e-14);
      RCFD_CHECK_CLOSE(0.01 * (Y[0] - 0.005), 0.02 * (0.05 - Y[0]), 1e-17); // the layer's vapour balance
      // Water's saturation (Antoine) against the steam tables' 2.339 kPa at 20 C and 19.946 kPa at 60 C.
      RCFD_CHECK_CLOSE(gas_layer::saturationHumidity(293.15, 101325.0) / (0.622 * 2339.0 / (101325.0 - 2339.0)), 1.0, 5e-3);
      RCFD_CHECK_CLOSE(gas_layer::saturationHumidity(333.15, 101325.0) / (0.622 * 19946.0 / (101325.0 - 19946.0)), 1.0, 5e-3);
    }
    // Several layers of random particle groups: no overshoot, the energy balance, humidity below saturation.
    {
      unsigned long seed = 7;
      const auto uniform = [&seed]() {
        seed = seed * 6364136223846793005UL + 1442695040888963407UL;
        return static_cast<double>(seed >> 11) / 9007199254740992.0;
      };
      const int nl = 6, groups = 5;
      const double F = 40.0, Fv = 0.01, Tin = 340.0, Yin = 0.004;
      std::vector<double> sums(4 * nl, 0.0), Tk(nl * groups), Ck(nl * groups), gk(nl * groups);
      double hottest = 0.0;
      for (int l = 0; l < nl; ++l)
        for (int k = 0; k < groups; ++k) {
          const int j = l * groups + k;
          Tk[j] = 280.0 + 100.0 * uniform(); // some hotter than the gas, some colder
          Ck[j] = 10.0 + 500.0 * uniform();
          gk[j] = gas_layer::share(1000.0 * uniform(), Ck[j]);
          const double kv = 0.05 * uniform(), Ys = gas_layer::saturationHumidity(Tk[j], 101325.0);
          hottest = std::fmax(hottest, Tk[j]);
          double *x = sums.data() + 4 * l;
          x[0] += gk[j], x[1] += gk[j] * Tk[j], x[2] += kv, x[3] += kv * Ys;
        }
      std::vector<double> T, Y;
      gas_layer::sweep(Tin, Yin, F, Fv, sums, &T, &Y);
      double taken = 0.0, inlet = Tin;
      for (int l = 0; l < nl; ++l) {
        double low = inlet, high = inlet;
        for (int k = 0; k < groups; ++k) {
          const int j = l * groups + k;
          low = std::fmin(low, Tk[j]), high = std::fmax(high, Tk[j]);
          const double after = Tk[j] + gk[j] * (T[l] - Tk[j]) / Ck[j];
          RCFD_CHECK((after - Tk[j]) * (T[l] - after) >= 0.0); // a particle moves toward the gas, never past it
          taken += Ck[j] * (after - Tk[j]);
        }
        RCFD_CHECK(T[l] >= low && T[l] <= high); // the gas between its inlet and its particles
        RCFD_CHECK(Y[l] <= gas_layer::saturationHumidity(hottest, 101325.0) && Y[l] >= 0.0);
        inlet = T[l];
      }
      RCFD_CHECK_CLOSE(taken / (F * (Tin - T[nl - 1])), 1.0, 1e-12); // heat given by the gas = taken
    }
    // A run with the plug-flow gas: its own balance gave what the particles took, to round-off (the
    // ledger checks the amounts every step); sprayed = held + dried; the gas gives less than the gas
    // well mixed at its inlet state, which never cools.
    Outcome plug;
    const std::string plugOptions = kSpray + " -scalar_gas_model plug -scalar_gas_humidity 0.005 -t_end 0.3";
    PetscCall(runCase(PETSC_COMM_WORLD, plugOptions, dir + "/plug", &plug));
    {
      RCFD_CHECK(plug.account[3] > 0.0);
      RCFD_CHECK_CLOSE(plug.account[5] / plug.account[3], 1.0, 1e-12);
      RCFD_CHECK(plug.account[3] < spray.account[3]);
      const double sprayed = plug.account[0], dried = plug.account[2], held = scalarTotal(plug, 1);
      RCFD_CHECK(dried > 0.0);
      RCFD_CHECK_CLOSE((held + dried) / sprayed, 1.0, 1e-12);
      double worst, lowest;
      valueSpread(plug, 0, 300.0, &worst, &lowest);
      RCFD_CHECK(lowest >= 0.0);
      // With a critical moisture above what the bed holds, its drying falls with its moisture: it dries
      // less, and its balances close as before.
      Outcome falling;
      PetscCall(runCase(PETSC_COMM_WORLD, plugOptions + " -scalar_critical_moisture 0.1", dir + "/plug_falling", &falling));
      RCFD_CHECK(falling.account[2] > 0.0 && falling.account[2] < 0.5 * dried);
      RCFD_CHECK_CLOSE((scalarTotal(falling, 1) + falling.account[2]) / falling.account[0], 1.0, 1e-12);
      RCFD_CHECK_CLOSE(falling.account[5] / falling.account[3], 1.0, 1e-12);
    }

    // The ranks of the test equal one rank to 1e-12 (granulator, spray and dry, plug-flow gas).
    for (const auto &[options, outcome] : {std::make_pair(full, &chamber), std::make_pair(kSpray + " -t_end 0.3", &spray),
                                           std::make_pair(plugOptions, &plug)}) {
      Outcome alone;
      PetscCall(runCase(PETSC_COMM_SELF, options, dir + "/alone" + std::to_string(rank), &alone));
      double worstRanks = 0.0, largest = 0.0;
      for (double a : outcome->amounts) largest = std::fmax(largest, std::fabs(a));
      for (std::size_t k = 0; k < outcome->amounts.size(); ++k)
        worstRanks = std::fmax(worstRanks, std::fabs(alone.amounts[k] - outcome->amounts[k]) / largest);
      RCFD_CHECK_CLOSE(worstRanks, 0.0, 1e-12);
    }

    // Restarted at half time: the same bits, product.csv and scalars.csv (granulator; spray and dry).
    for (const auto &[options, outcome, name] :
         {std::make_tuple(kChamber, &chamber, std::string("chamber")),
          std::make_tuple(kSpray, &spray, std::string("spray"))}) {
      const double t = name == "chamber" ? 0.4 : 0.3;
      Outcome first, second;
      PetscCall(runCase(PETSC_COMM_WORLD, options + " -t_end " + std::to_string(t / 2) + " -checkpoint_every " +
                                              std::to_string(t / 2), dir + "/first_" + name, &first));
      PetscCall(runCase(PETSC_COMM_WORLD, options + " -t_end " + std::to_string(t) + " -restart " + dir + "/first_" +
                                              name + "/checkpoint.h5", dir + "/first_" + name, &second));
      RCFD_CHECK(second.masses == outcome->masses);
      RCFD_CHECK(second.amounts == outcome->amounts);
      RCFD_CHECK(second.account == outcome->account);
      if (rank == 0) {
        for (const char *file : {"/scalars.csv", "/product.csv"}) {
          const std::string a = fileBytes(dir + "/" + name + file), b = fileBytes(dir + "/first_" + name + file);
          RCFD_CHECK(a == b);
        }
      }
    }
    PetscFunctionReturn(PETSC_SUCCESS);
  });
}
