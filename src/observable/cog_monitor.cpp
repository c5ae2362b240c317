#include "observable/cog_monitor.hpp"
#include "base/checked_options.hpp"
#include "base/petsc_compat.hpp"

#include <sstream>

namespace rcfd {

std::string formatCsvRow(const BedSample &s, int digits) {
  std::ostringstream row;
  row.precision(digits);
  row << s.time << ',' << s.zCogBed;
  for (double z : s.zCog) row << ',' << z;
  row << ',' << s.deltaZ;
  for (double m : s.mass) row << ',' << m;
  row << ',' << s.minMass << ',' << s.bulkMismatch;
  return row.str();
}

PetscErrorCode CogMonitor::setFromOptions(MPI_Comm comm) {
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, nullptr, "Centre-of-gravity monitor (cog.csv)", "rcfd");
  PetscCall(checkedInt(PetscOptionsObject, "-monitor_every",
                       "Steps between rows of cog.csv", &monitorEvery, 1, PETSC_MAX_INT));
  PetscCall(checkedInt(PetscOptionsObject, "-monitor_digits",
                       "Significant digits in cog.csv", &csvDigits, 1, 17));
  PetscOptionsEnd();
  PetscCheck(monitorEvery >= 1, comm, PETSC_ERR_USER_INPUT, "-monitor_every must be at least 1");
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::string CogMonitor::header(const FractionSet &set) const {
  std::string header = "time_s,z_cog_bed_m";
  for (int i = 0; i < set.size(); ++i) header += ",z_cog_" + set.label(i) + "_m";
  header += ",delta_z_m";
  for (int i = 0; i < set.size(); ++i) header += ",mass_" + set.label(i) + "_kg";
  return header + ",min_cell_mass_kg,bulk_mismatch";
}

PetscErrorCode CogMonitor::setUp(const RunContext &run, const FractionState &,
                                 const std::string &outputDirectory) {
  PetscFunctionBeginUser;
  PetscCall(cog.setUp(run.db, run.fractions));
  csv = std::make_unique<CsvSeries>(run.db.layout().comm(), outputDirectory + "/cog.csv",
                                    header(run.fractions));
  history.clear();
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode CogMonitor::sample(const MonitorContext &ctx) {
  PetscFunctionBeginUser;
  BedSample s;
  PetscCall(cog.measure(ctx.time, ctx.state.masses(), ctx.run.db.alphaS(ctx.frame),
                        ctx.run.solidDensity, &s));
  latestDeltaZ = s.deltaZ;
  latestZCogBed = s.zCogBed;
  if (keep_) history.push_back(s);
  PetscCall(csv->add(formatCsvRow(s, static_cast<int>(csvDigits))));
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::vector<double> CogMonitor::saveState() const {
  std::vector<double> state = csv->state();
  state.push_back(latestDeltaZ);
  state.push_back(latestZCogBed);
  return state;
}

PetscErrorCode CogMonitor::restoreState(const std::vector<double> &state) {
  PetscFunctionBeginUser;
  if (state.empty()) PetscFunctionReturn(PETSC_SUCCESS); // not in the checkpoint's run: starts anew
  // Checkpoints before the signals hold the file's length only.
  PetscCheck(state.size() == 1 || state.size() == 3, PETSC_COMM_SELF, PETSC_ERR_FILE_UNEXPECTED,
             "The checkpoint's cog.csv state holds %zu numbers, expected 3 (the file's length, the latest "
             "delta_z and z_cog_bed)", state.size());
  PetscCall(csv->resume(state[0]));
  if (state.size() == 3) {
    latestDeltaZ = state[1];
    latestZCogBed = state[2];
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

double CogMonitor::signal(const std::string &name) const {
  if (name == "delta_z") return latestDeltaZ;
  if (name == "z_cog_bed") return latestZCogBed;
  return Monitor::signal(name);
}

PetscErrorCode FieldMonitor::setUp(const RunContext &run, const FractionState &state,
                                  const std::string &outputDirectory) {
  PetscFunctionBeginUser;
  PetscCall(writer.setUp(run.db, run.fractions, run.solidDensity, outputDirectory, state.masses()));
  if (state.numScalars() > 0) PetscCall(writer.setUpScalars(run.db, state.scalarNames(), state.amounts()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
