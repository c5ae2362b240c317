// A simulation run: database + fractions + operator pipeline + frame path,
// stepped in time with monitors and outputs.
#pragma once

#include "rcfd/database.hpp"
#include "rcfd/fractions.hpp"
#include "rcfd/mass_ledger.hpp"
#include "rcfd/observables.hpp"
#include "rcfd/operator.hpp"

#include <memory>
#include <string>
#include <vector>

namespace rcfd {

class Run {
public:
  /// The registry supplies the operators named by -pipeline; it must outlive the run.
  Run(MPI_Comm comm, const OperatorRegistry &registry);
  ~Run();

  /// Reads the run's options (see `rcfd run -help`).
  PetscErrorCode setFromOptions();
  /// Loads the database, builds the pipeline and the initial state (collective).
  PetscErrorCode setUp();
  /// Steps to the end time, writing monitors and fields (collective).
  PetscErrorCode solve();
  PetscErrorCode view(PetscViewer viewer) const;

  const Database &database() const { return *db; }
  const FractionSet &fractions() const { return set; }
  const FractionState &state() const { return fstate; }
  FractionState &state() { return fstate; }
  Pipeline &pipeline() { return ops; }
  /// Samples taken by the monitor (every -monitor_every steps).
  const std::vector<BedSample> &history() const { return samples; }
  long numSteps() const { return steps; }

private:
  PetscErrorCode initialState();
  PetscErrorCode monitor(const StepInfo &step, double time);
  PetscErrorCode progress(long step, double time, bool last);

  MPI_Comm comm;
  const OperatorRegistry &registry;
  std::unique_ptr<Database> db;
  FractionSet set;
  FractionState fstate;
  Pipeline ops;
  CentreOfGravity cog;
  MassLedger ledger;
  FieldWriter fields;
  std::unique_ptr<CsvSeries> csv;
  std::vector<BedSample> samples;

  // Options.
  std::string dbPath, outputDir = "rcfd-output", initKind = "mixed", initFile;
  std::string pipelineSpec = "shift,drift";
  double tEnd = -1.0, fieldsEvery = 0.0, progressInterval = 2.0, solidDensity = -1.0;
  PetscInt monitorEvery = 1, csvDigits = 10;
  long steps = 0;
  PetscBool quiet = PETSC_FALSE, writeFields = PETSC_TRUE;
  DatabaseLoadOptions loadOptions;
  double wallStart = 0.0, lastProgress = 0.0;
};

} // namespace rcfd
