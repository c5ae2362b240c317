// A simulation run: database + fractions + operator pipeline + frame path,
// stepped in time with monitors, outputs and checkpoints.
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

class FramePath;

class Run {
public:
  /// The registry supplies the operators named by -pipeline; it must outlive the run.
  Run(MPI_Comm comm, const OperatorRegistry &registry);
  ~Run();

  /// Reads the run's options (see `rcfd run -help`).
  PetscErrorCode setFromOptions();
  /// Use an already loaded database (e.g. shared by the members of an
  /// ensemble) instead of reading -db.
  void useDatabase(std::shared_ptr<Database> database) { db = std::move(database); }
  /// Loads the database (unless one was given), the frame path and the initial
  /// state (or the state of -restart FILE).  Collective.
  PetscErrorCode setUp();
  /// Steps to the end time, writing monitors, fields and checkpoints (collective).
  PetscErrorCode solve();
  PetscErrorCode view(PetscViewer viewer) const;

  const Database &database() const { return *db; }
  std::shared_ptr<Database> sharedDatabase() const { return db; }
  const FractionSet &fractions() const { return set; }
  const FractionState &state() const { return fstate; }
  FractionState &state() { return fstate; }
  Pipeline &pipeline() { return ops; }
  /// Samples taken by the monitor (every -monitor_every steps).
  const std::vector<BedSample> &history() const { return samples; }
  /// Frame used by each step so far.
  const std::vector<int> &framesUsed() const { return frames; }
  long numSteps() const { return steps; }

private:
  PetscErrorCode setUpPath();
  PetscErrorCode initialState();
  PetscErrorCode loadInitialMasses();
  PetscErrorCode monitor(double time, int frameOfState);
  PetscErrorCode progress(long step, double time, bool last);
  PetscErrorCode writeCheckpoint(long step) const;
  PetscErrorCode readCheckpoint();
  PetscErrorCode writePath() const;
  std::string csvHeader() const;

  MPI_Comm comm;
  const OperatorRegistry &registry;
  std::shared_ptr<Database> db;
  FractionSet set;
  FractionState fstate;
  Pipeline ops;
  CentreOfGravity cog;
  FieldWriter fields;
  MassLedger ledger;
  std::unique_ptr<CsvSeries> csv;
  std::vector<BedSample> samples;
  std::unique_ptr<FramePath> path;
  std::vector<int> frames;
  long startStep = 0;

  // Options.
  std::string dbPath, outputDir = "rcfd-output", initKind = "mixed", initFile;
  std::string pipelineSpec = "shift,drift,carry";
  std::string pathType = "replay", pathFile, recurrenceNorm = "sqrDiff";
  std::string checkpointFile, restartFile;
  PetscInt pathSeed = 1, pathMinLength = -1, pathMaxLength = -1, pathBand = -1, pathCandidates = 4;
  PetscInt pathStart = 0;
  PetscReal pathMeanInterval = -1.0;
  double tEnd = -1.0, fieldsEvery = 0.0, progressInterval = 2.0, solidDensity = -1.0;
  double checkpointEvery = 0.0;
  PetscInt monitorEvery = 1, csvDigits = 10;
  long steps = 0;
  PetscBool quiet = PETSC_FALSE, writeFields = PETSC_TRUE, plotResults = PETSC_TRUE;
  DatabaseLoadOptions loadOptions;
  double wallStart = 0.0, lastProgress = 0.0;
};

} // namespace rcfd
