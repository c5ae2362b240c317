#include "run/status_monitor.hpp"
#include "base/petsc_compat.hpp"

#include "base/checked_options.hpp"
#include "base/collective.hpp"
#include "base/input_file.hpp"
#include "observable/answers.hpp"
#include "observable/cog_monitor.hpp"
#include "run/forecast_monitor.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rcfd {
namespace fs = std::filesystem;
namespace {

// JSON has no NaN: a number not known (an empty bottom layer, no forecast warning) is null.
std::string number(double v) {
  if (!std::isfinite(v)) return "null";
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", v);
  return text;
}

// Only the page's own sentences go in here: quotes and backslashes escaped, nothing else to escape.
std::string jsonString(const std::string &s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string format(const char *fmt, double a, double b = 0.0, double c = 0.0, double d = 0.0) {
  char text[256];
  std::snprintf(text, sizeof text, fmt, a, b, c, d);
  return text;
}

} // namespace

std::string statusPageSource() {
  if (const char *chosen = std::getenv("RCFD_STATUS_PAGE"); chosen && *chosen) return chosen;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path installed = (exe.parent_path() / ".." / "share" / "rcfd" / "status" / "status.html").lexically_normal();
    if (fs::is_regular_file(installed, ec)) return installed;
  }
  return RCFD_SOURCE_STATUS_PAGE; // the build tree's program
}

PetscErrorCode StatusMonitor::setFromOptions(MPI_Comm c) {
  PetscBool flag = on ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscOptionsBegin(c, nullptr, "Status page", "rcfd");
  PetscCall(PetscOptionsBool("-status", "Write status.json and status.html in the output directory (docs/live.md)",
                             "", flag, &flag, nullptr));
  PetscCall(checkedReal(PetscOptionsObject, "-status_every", "Wall seconds between rewrites of status.json", &every,
                        kNonNegative));
  PetscOptionsEnd();
  on = flag == PETSC_TRUE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode StatusMonitor::setUp(const RunContext &run, const FractionState &, const std::string &dir) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  comm = run.db.layout().comm();
  directory = dir;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscErrorCode status = PETSC_SUCCESS;
  if (rank == 0) {
    const std::string source = statusPageSource();
    std::string page;
    status = collectively(PETSC_COMM_SELF, [&] {
      requireRegularFile(source);
      std::ifstream in(source, std::ios::binary);
      std::stringstream text;
      text << in.rdbuf();
      page = text.str();
      if (!in || page.empty())
        throw std::runtime_error("-status: cannot read the status page '" + source +
                                 "'; install rcfd, set RCFD_STATUS_PAGE to the page, or give -status 0");
    }, PETSC_ERR_FILE_OPEN);
    if (status == PETSC_SUCCESS) status = writeFileAtomically(dir + "/status.html", page);
  }
  PetscCall(agreeOnStatus(comm, status));
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::string StatusMonitor::json(double t, long k, bool end) const {
  std::ostringstream j;
  std::vector<std::string> warnings;
  j << "{\n  \"time_s\": " << number(t) << ",\n  \"step\": " << k << ",\n  \"last\": " << (end ? "true" : "false");
  if (!databaseName.empty()) j << ",\n  \"database\": " << jsonString(databaseName);
  for (const Monitor *m : watched) {
    if (const auto *cog = dynamic_cast<const CogMonitor *>(m)) {
      j << ",\n  \"delta_z_m\": " << number(cog->signal("delta_z"));
    } else if (const auto *bottom = dynamic_cast<const BottomLayerMonitor *>(m)) {
      const std::vector<double> &r = bottom->latestRow(); // time, d32, u_mf, u_sup, de-fluidized
      if (r.size() < 5) continue;
      j << ",\n  \"d32_bottom_m\": " << number(r[1]) << ",\n  \"umf_m_s\": " << number(r[2])
        << ",\n  \"usup_m_s\": " << number(r[3]) << ",\n  \"umf_usup\": " << number(r[2] / r[3])
        << ",\n  \"defluidized\": " << (r[4] > 0.5 ? "true" : "false");
      const DefluidizationDetector &w = bottom->warning();
      if (w.fired()) {
        // The detector remembers that it fired; the bed may have recovered since (the gas back up).
        if (r[4] > 0.5)
          warnings.push_back(format("De-fluidization: the bottom layer's minimum fluidization velocity reached the gas "
                                    "velocity at t = %.6g s and is at or above it now (u_mf = %.4g m/s for u_sup = "
                                    "%.4g m/s, bottom d32 = %.4g mm).", w.firstTime(), r[2], r[3], 1e3 * r[1]));
        else
          warnings.push_back(format("De-fluidization from t = %.6g s, over now: the bottom layer's u_mf = %.4g m/s is "
                                    "below u_sup = %.4g m/s again (bottom d32 = %.4g mm).", w.firstTime(), r[2], r[3],
                                    1e3 * r[1]));
      }
      if (std::isfinite(bottom->wetSince())) // the wet-bottom warning (docs/scalars.md), once fired
        warnings.push_back(format("Wet bottom layer: its moisture passed %.4g kg/kg at t = %.6g s while u_mf was at "
                                  "least %.0f %% of u_sup (near de-fluidization by size).", bottom->wetThresholdValue(),
                                  bottom->wetSince(), 100.0 * bottom->wetUmfShare()));
    } else if (const auto *fc = dynamic_cast<const ForecastMonitor *>(m)) {
      const std::vector<double> &r = fc->latestRow(); // forecast.csv's columns (docs/live.md)
      if (r.size() < 12) continue;
      // A forecast under a what-if says so: its numbers are not those of the conditions held.
      const std::string whatIf = fc->whatIf().empty() ? "null" : jsonString(fc->whatIf());
      j << ",\n  \"forecast\": {\"time_s\": " << number(r[0]) << ", \"what_if\": " << whatIf << ", \"horizon_s\": " << number(r[1])
        << ", \"members\": " << number(r[2]) << ", \"delta_z_mean_m\": " << number(r[3])
        << ", \"delta_z_spread_m\": " << number(r[4]) << ", \"d32_bottom_mean_m\": " << number(r[5])
        << ", \"d32_bottom_spread_m\": " << number(r[6]) << ", \"umf_usup_mean\": " << number(r[7])
        << ", \"umf_usup_spread\": " << number(r[8]) << ", \"warning_members\": " << number(r[9])
        << ", \"warning_in_mean_s\": " << number(r[10]) << ", \"warning_in_first_s\": " << number(r[11]);
      const std::vector<std::string> &labels = fc->productLabels(); // the product over the horizon
      if (!labels.empty() && r.size() >= 14 + 2 * labels.size()) {
        j << ", \"product_mass_mean_kg\": " << number(r[12]) << ", \"product_mass_spread_kg\": " << number(r[13])
          << ", \"product_shares\": [";
        for (std::size_t i = 0; i < labels.size(); ++i)
          j << (i ? ", " : "") << "{\"label\": " << jsonString(labels[i]) << ", \"mean\": " << number(r[14 + 2 * i])
            << ", \"spread\": " << number(r[15 + 2 * i]) << "}";
        j << "]";
      }
      // With scalars: the product's values, the bottom layer's moisture and the wet-bottom warning.
      const auto at = [&](const std::string &name) {
        const int k = fc->column(name);
        return k >= 0 && k < static_cast<int>(r.size()) ? r[k] : std::nan("");
      };
      if (!fc->productScalars().empty()) {
        j << ", \"product_scalars\": [";
        for (std::size_t k = 0; k < fc->productScalars().size(); ++k) {
          const std::string &name = fc->productScalars()[k];
          j << (k ? ", " : "") << "{\"name\": " << jsonString(name) << ", \"mean\": "
            << number(at("product_" + name + "_mean")) << ", \"spread\": " << number(at("product_" + name + "_spread"))
            << "}";
        }
        j << "]";
      }
      const bool wet = fc->column("moisture_bottom_mean") >= 0, wetWarning = fc->column("wet_warning_members") >= 0;
      if (wet)
        j << ", \"moisture_bottom_mean\": " << number(at("moisture_bottom_mean"))
          << ", \"moisture_bottom_spread\": " << number(at("moisture_bottom_spread"));
      if (wetWarning)
        j << ", \"wet_warning_members\": " << number(at("wet_warning_members")) << ", \"wet_warning_in_mean_s\": "
          << number(at("wet_warning_in_mean_s")) << ", \"wet_warning_in_first_s\": " << number(at("wet_warning_in_first_s"));
      j << "}";
      const std::string issued = format("forecast issued at t = %.6g s", r[0]) +
                                 (fc->whatIf().empty() ? std::string(").") : ", under the what-if " + fc->whatIf() + ").");
      if (wetWarning && at("wet_warning_members") > 0)
        warnings.push_back(format("Forecast: %.0f of %.0f members' bottom layers get wet near de-fluidization within "
                                  "%.4g s", at("wet_warning_members"), r[2], r[1]) +
                           format(" (moisture above %.4g kg/kg while u_mf is at least %.0f %% of u_sup), in about "
                                  "%.4g s (", fc->moistureWarning(), 100.0 * fc->moistureWarningUmfShare(),
                                  at("wet_warning_in_mean_s")) + issued);
      if (r[9] > 0)
        warnings.push_back(format("Forecast: %.0f of %.0f members de-fluidize within %.4g s", r[9], r[2], r[1]) +
                           format(", in about %.4g s (", r[10]) + issued);
    }
  }
  j << ",\n  \"warnings\": [";
  for (std::size_t i = 0; i < warnings.size(); ++i) j << (i ? ", " : "") << jsonString(warnings[i]);
  j << "]\n}\n";
  return j.str();
}

// A write per step would cost the run: 1.2 to 4 ms each (a file synced and renamed) on a bed that
// steps in 0.02 ms.  The text is made only when written (the watched monitors keep their latest values).  So at most every -status_every wall seconds, but a new warning or forecast at once: people
// look at the page for them.  The warnings and the forecast are the same on every rank, the clocks
// are not: the slowest rank's decides, as for the run's periodic flush.
PetscErrorCode StatusMonitor::sample(const MonitorContext &ctx) {
  PetscFunctionBeginUser;
  time = ctx.time, step = ctx.step, last = ctx.last;
  if (database) databaseName = database();
  pending = true;
  double waited = MPI_Wtime() - lastWrite;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &waited, 1, MPI_DOUBLE, MPI_MAX, comm));
  if (news() != seen || databaseName != writtenDatabase || waited >= every) PetscCall(write()); // and at the end: flush()
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::vector<double> StatusMonitor::news() const {
  std::vector<double> now;
  for (const Monitor *m : watched) {
    if (const auto *bottom = dynamic_cast<const BottomLayerMonitor *>(m)) {
      now.push_back(bottom->warning().fired() ? bottom->warning().firstTime() : -1.0);
      now.push_back(std::isfinite(bottom->wetSince()) ? bottom->wetSince() : -1.0);
    }
    else if (const auto *fc = dynamic_cast<const ForecastMonitor *>(m))
      now.push_back(fc->latestRow().empty() ? -1.0 : fc->latestRow()[0]);
  }
  return now;
}

PetscErrorCode StatusMonitor::flush() {
  PetscFunctionBeginUser;
  if (pending) PetscCall(write());
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode StatusMonitor::write() {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  const PetscErrorCode status =
      rank == 0 ? writeFileAtomically(directory + "/status.json", json(time, step, last)) : PETSC_SUCCESS;
  PetscCall(agreeOnStatus(comm, status));
  pending = false;
  seen = news();
  writtenDatabase = databaseName;
  lastWrite = MPI_Wtime();
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
