// Checkpoints: everything a run needs to continue bit-identically, in one
// HDF5 file written atomically (temporary name, then rename), so that a
// crash while writing leaves the previous checkpoint intact.  Its size does
// not grow with the run's length: the time series are in the output files,
// which the run flushes right before it writes a checkpoint and which a
// restart cuts back to the lengths recorded here.
//
//   /masses            [cells, fractions]  natural cell order, kg
//   /path_state        uint64 words of the frame path (position, sequence, PRNG)
//   /ledger_reference  the mass ledger's reference totals
//   /scalar_amounts    [cells, scalars x fractions] with -scalars (docs/scalars.md): the amounts
//   /scalar_ledger_reference  the scalars' ledger's totals at step 0 (with -scalars)
//   /monitors/<name>   each monitor's saved state (Monitor::saveState), when not empty
//   /operators/<type>  each operator's saved state (Operator::saveState), when not empty (the
//                      group is absent from an rcfd before the granulation operators)
//   /physics           attributes: what the physics was made with (database, diameters,
//                      mass_shares, solid_density, pipeline, path, options_<operator>);
//                      a restart refuses a run that differs in any of them
//   root attributes    format = "rcfd-checkpoint", version = 2, step, num_fractions,
//                      num_cells, database (its path), output_dir (absolute),
//                      path_txt_bytes (length of OUTPUT_DIR/path.txt at the step),
//                      jumps_csv_bytes (of OUTPUT_DIR/jumps.csv, -1 before its first row;
//                      absent from an rcfd that wrote jumps.csv at the run's end),
//                      checksums = "fletcher32" (every dataset and HDF5 record checksummed,
//                      docs/database-format.md "Checksums"; absent from an rcfd before them)
// Version 1 (before the time series left the checkpoint) is refused with a sentence.
#include "path/frame_path.hpp"
#include "base/petsc_compat.hpp"
#include "run/run_impl.hpp"
#include "base/atomic_file.hpp"
#include "base/collective.hpp"
#include "base/h5.hpp"

#include <petscviewerhdf5.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <sstream>

namespace rcfd {
namespace {

constexpr long long kCheckpointVersion = 2;

std::string joinNumbers(const std::vector<double> &values) {
  std::string text;
  char number[32];
  for (double v : values) {
    for (int digits = 15; digits <= 17; ++digits) { // the shortest text that reads back exactly:
      std::snprintf(number, sizeof number, "%.*g", digits, v); // a difference in the last bit counts
      if (std::strtod(number, nullptr) == v) break;
    }
    text += (text.empty() ? "" : ",") + std::string(number);
  }
  return text;
}

/// The options given under `prefix` ("-drift_kd 2000 -drift_model A"), sorted,
/// without the viewers (-<prefix>view...), which do not change the physics.
std::string optionsUnder(const std::string &prefix) {
  char *all = nullptr;
  if (PetscOptionsGetAll(nullptr, &all) != 0 || !all) return "";
  std::istringstream in(all);
  PetscFree(all);
  std::vector<std::string> found;
  std::string token;
  bool keep = false;
  while (in >> token) {
    const bool isName = token.size() > 1 && token[0] == '-' && std::isalpha(static_cast<unsigned char>(token[1]));
    if (isName) {
      keep = token.compare(1, prefix.size(), prefix) == 0 && token.find("view", 1 + prefix.size()) == std::string::npos;
      if (keep) found.push_back(token);
    } else if (keep && !found.empty()) {
      found.back() += " " + token;
    }
  }
  std::sort(found.begin(), found.end());
  std::string text;
  for (const auto &f : found) text += (text.empty() ? "" : " ") + f;
  return text.empty() ? "(defaults)" : text;
}

/// "another database", "other options of the drift operator", ... for an entry of the physics record.
std::string differenceIn(const std::string &entry) {
  if (entry.rfind("options_", 0) == 0) return "other options of the " + entry.substr(8) + " operator";
  if (entry == "diameters") return "another set of diameters";
  if (entry == "mass_shares") return "another set of mass shares";
  if (entry == "solid_density") return "another solid density";
  if (entry == "scalars") return "other scalars or scalar options";
  return "another " + entry;
}

// Collective.  A cell Vec of block size bs in natural order on rank 0 (empty elsewhere).
PetscErrorCode gatherOnZero(const Layout &layout, int bs, Vec v, std::vector<double> *out) {
  OwnedVec natural, onZero;
  OwnedScatter scatter, toZero;
  PetscFunctionBeginUser;
  PetscCall(layout.naturalScatter(bs, v, natural.put(), scatter.put()));
  PetscCall(VecScatterBegin(scatter, v, natural, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(scatter, v, natural, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterCreateToZero(natural, toZero.put(), onZero.put()));
  PetscCall(VecScatterBegin(toZero, natural, onZero, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(toZero, natural, onZero, INSERT_VALUES, SCATTER_FORWARD));
  PetscInt gathered;
  const PetscScalar *x;
  PetscCall(VecGetLocalSize(onZero, &gathered));
  PetscCall(VecGetArrayRead(onZero, &x));
  out->assign(x, x + gathered);
  PetscCall(VecRestoreArrayRead(onZero, &x));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// Collective.  Dataset `name` of the checkpoint (natural order, block size bs) into v.
PetscErrorCode loadFromCheckpoint(const Layout &layout, int bs, const std::string &file, const char *name, Vec v) {
  OwnedVec natural;
  OwnedScatter scatter;
  OwnedViewer viewer;
  PetscFunctionBeginUser;
  PetscCall(layout.naturalScatter(bs, v, natural.put(), scatter.put()));
  PetscCall(PetscObjectSetName((PetscObject)natural.get(), name));
  PetscCall(PetscViewerHDF5Open(layout.comm(), file.c_str(), FILE_MODE_READ, viewer.put()));
  PetscCall(VecLoad(natural, viewer));
  PetscCall(VecScatterBegin(scatter, natural, v, INSERT_VALUES, SCATTER_REVERSE));
  PetscCall(VecScatterEnd(scatter, natural, v, INSERT_VALUES, SCATTER_REVERSE));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

// What the physics of this run was made with, as (name, text) pairs; a
// restart compares them with the checkpoint's.  Run control (-t_end, the
// outputs, progress, the monitors' intervals) is not among them.
std::vector<std::pair<std::string, std::string>> Run::Impl::physicsRecord() const {
  std::vector<double> diameters, shares;
  for (int i = 0; i < set.size(); ++i) {
    diameters.push_back(set.diameter(i));
    shares.push_back(set.massShare(i));
  }
  std::string pipeline;
  for (const auto &op : ops.operators()) pipeline += (pipeline.empty() ? "" : ",") + op->type();
  std::vector<std::pair<std::string, std::string>> record{
      {"database", db->identity() + ", frames " + std::to_string(loadOptions.firstFrame) + " to " +
                       std::to_string(loadOptions.firstFrame + db->numFrames() - 1)},
      {"diameters", joinNumbers(diameters)},
      {"mass_shares", joinNumbers(shares)},
      {"solid_density", joinNumbers({solidDensity})},
      {"pipeline", pipeline},
      {"path", path->describe()}};
  if (switching) { // the set and its rule, not the database active when the checkpoint was written
    record.front().second = switching->set().identity() + ", frames " + std::to_string(loadOptions.firstFrame) +
                            " to " + std::to_string(loadOptions.firstFrame + pathFrames - 1); // the path's frames
    std::string options = optionsUnder("db_switch_");
    if (const std::string pairing = optionsUnder("db_blend_"); !pairing.empty()) options += " " + pairing;
    record.emplace_back("switching", switching->rule().describe() + " " + options);
  }
  for (const auto &op : ops.operators())
    record.emplace_back("options_" + op->type(), optionsUnder(op->optionsPrefix()));
  if (scalars.size() > 0) { // names, initial values and sources (a checkpoint without scalars has no entry)
    std::string text;
    for (int s = 0; s < scalars.size(); ++s) text += (s ? "," : "") + scalars.name(s);
    record.emplace_back("scalars", text + " " + optionsUnder("scalar_"));
  }
  return record;
}

PetscErrorCode Run::Impl::writeCheckpoint(long step) const {
  namespace fs = std::filesystem;
  // The masses are gathered on rank 0, which writes the file (as the fields
  // are written): a failed write then stops every rank with its reason
  // instead of leaving the others in a collective HDF5 call.
  const int nf = set.size();
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  std::unique_ptr<AtomicFile> out; // removes the temporary if anything below fails
  if (rank == 0) PetscCallCXX(out = std::make_unique<AtomicFile>(checkpointFile));
  std::vector<double> masses, amounts;
  PetscCall(gatherOnZero(db->layout(), nf, fstate.masses(), &masses));
  const int na = nf * scalars.size();
  if (na > 0) PetscCall(gatherOnZero(db->layout(), na, fstate.amounts(), &amounts));
  std::vector<std::pair<std::string, std::vector<double>>> states; // the same on every rank
  for (const auto &e : monitors) {
    states.emplace_back(e.name, e.monitor->saveState());
    for (std::size_t k = 0; k + 1 < states.size(); ++k)
      PetscCheck(states.back().second.empty() || states[k].first != e.name || states[k].second.empty(), comm,
                 PETSC_ERR_ARG_WRONG, "Two monitors named '%s' keep state for checkpoints; give them different names",
                 e.name.c_str());
  }
  std::vector<std::pair<std::string, std::vector<double>>> operatorStates;
  for (const auto &op : ops.operators()) operatorStates.emplace_back(op->type(), op->saveState());
  const auto physics = physicsRecord();
  const std::vector<double> switchingState = switching ? switching->saveState() : std::vector<double>{};
  const PetscErrorCode written = collectively(comm, [&] {
    if (rank != 0) return;
    {
      h5::File f = h5::File::create(*out, h5::Checksums::fletcher32); // a damaged checkpoint is refused
      // As PETSc's VecView writes a vector of block size nf (VecLoad reads it).
      f.write("/masses", masses, nf > 1 ? static_cast<hsize_t>(nf) : 0);
      if (na > 0) {
        f.write("/scalar_amounts", amounts, na > 1 ? static_cast<hsize_t>(na) : 0);
        f.write("/scalar_ledger_reference", scalars.ledgerState());
        if (scalars.sources().any()) f.write("/scalar_sources", scalars.sources().account());
      }
      f.writeAttr("/", "format", std::string("rcfd-checkpoint"));
      f.writeAttr("/", "version", kCheckpointVersion);
      f.writeAttr("/", "step", static_cast<long long>(step));
      f.writeAttr("/", "num_fractions", static_cast<long long>(nf));
      f.writeAttr("/", "num_cells", static_cast<long long>(db->mesh().numCells()));
      f.writeAttr("/", "database", dbPath);
      f.writeAttr("/", "output_dir", fs::absolute(outputDir).lexically_normal().string());
      f.writeAttr("/", "path_txt_bytes", static_cast<long long>(pathFile->mark()));
      f.writeAttr("/", "jumps_csv_bytes", static_cast<long long>(jumps->mark()));
      f.createGroup("/physics");
      for (const auto &[name, text] : physics) f.writeAttr("/physics", name, text);
      const auto words = path->saveState();
      f.write("/path_state", std::vector<int64_t>(words.begin(), words.end()));
      f.write("/ledger_reference", ledger.reference());
      f.createGroup("/monitors");
      for (const auto &e : states)
        if (!e.second.empty()) f.write("/monitors/" + e.first, e.second);
      if (switching) f.write("/switching", switchingState); // [0]: the active database
      f.createGroup("/operators");
      for (const auto &e : operatorStates)
        if (!e.second.empty()) f.write("/operators/" + e.first, e.second);
      f.close();
    }
    out->commit();
  });
  PetscCall(written);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Run::Impl::readCheckpoint() {
  const int nf = set.size();
  long long step = 0, pathBytes = 0, jumpsBytes = -1;
  bool jumpsRecorded = false;
  std::string previousDirectory;
  std::vector<int64_t> words;
  std::vector<double> reference, switchingState, scalarReference, sourceAccount;
  const int na = nf * scalars.size();
  std::vector<std::vector<double>> states(monitors.size()), operatorStates(ops.operators().size());
  PetscFunctionBeginUser;
  PetscCall(collectively(
      comm,
      [&] {
        h5::File f = h5::File::openRead(restartFile, MPI_COMM_NULL);
        if (!f.hasAttribute("/", "format") || f.readAttrString("/", "format") != "rcfd-checkpoint")
          throw h5::Error("-restart '" + restartFile + "' is not an rcfd checkpoint");
        const long long cells = f.readAttrInt("/", "num_cells"), fr = f.readAttrInt("/", "num_fractions");
        if (cells != db->mesh().numCells() || fr != nf)
          throw h5::Error("-restart '" + restartFile + "' holds " + std::to_string(cells) + " cells x " +
                          std::to_string(fr) + " fractions, but this run has " +
                          std::to_string(db->mesh().numCells()) + " x " + std::to_string(nf));
        if (!f.hasAttribute("/", "version"))
          throw h5::Error("-restart '" + restartFile + "' was written by an older rcfd (checkpoint version 1, which "
                          "holds the time series but no record of the physics); rerun from the start");
        if (f.readAttrInt("/", "version") != kCheckpointVersion)
          throw h5::Error("-restart '" + restartFile + "' has checkpoint version " +
                          std::to_string(f.readAttrInt("/", "version")) + ", this rcfd reads version " +
                          std::to_string(kCheckpointVersion));
        if (f.exists("/scalar_amounts") != (na > 0)) // before the physics: its entry is there only with scalars
          throw h5::Error("-restart '" + restartFile + "' continues a run " +
                          (na > 0 ? std::string("without scalars; a restart cannot add -scalars")
                                  : std::string("that carried scalars; give the same -scalars")));
        for (const auto &[name, text] : physicsRecord()) {
          if (!f.hasAttribute("/physics", name)) // every rcfd writing version 2 recorded these for its run
            throw h5::Error("-restart '" + restartFile + "' holds no record of the physics entry '" + name +
                            "' (an attribute of /physics), so it cannot be compared with this run; the file "
                            "is damaged or was not written by rcfd run");
          const std::string saved = f.readAttrString("/physics", name);
          if (saved != text) {
            throw h5::Error("-restart '" + restartFile + "' continues a run made with " + differenceIn(name) + " (" + saved +
                            " there, " + text + " here); a restart may change only run control such as -t_end, "
                            "the outputs and progress");
          }
        }
        // Here, not in VecLoad, whose message names neither the file nor the checkpoint.
        std::size_t masses = 1;
        for (hsize_t extent : f.extents("/masses")) masses *= extent;
        if (masses != static_cast<std::size_t>(cells * nf))
          throw h5::Error("-restart '" + restartFile + "' holds " + std::to_string(masses) +
                          " masses in /masses, expected " + std::to_string(cells) + " cells x " +
                          std::to_string(nf) + " fractions");
        // Read here too, so that their checksums are compared and a damaged
        // chunk is refused with this sentence (VecLoad below reads them again).
        if (f.checksums() == h5::Checksums::fletcher32) f.read<double>("/masses");
        step = f.readAttrInt("/", "step");
        pathBytes = f.readAttrInt("/", "path_txt_bytes");
        jumpsRecorded = f.hasAttribute("/", "jumps_csv_bytes");
        if (jumpsRecorded) jumpsBytes = f.readAttrInt("/", "jumps_csv_bytes");
        previousDirectory = f.readAttrString("/", "output_dir");
        words = f.read<int64_t>("/path_state");
        reference = f.read<double>("/ledger_reference", nf);
        if (na > 0) {
          std::size_t held = 1;
          for (hsize_t extent : f.extents("/scalar_amounts")) held *= extent;
          if (held != static_cast<std::size_t>(cells * na))
            throw h5::Error("-restart '" + restartFile + "' holds " + std::to_string(held) +
                            " scalar amounts, expected " + std::to_string(cells) + " cells x " + std::to_string(na));
          if (f.checksums() == h5::Checksums::fletcher32) f.read<double>("/scalar_amounts");
          scalarReference = f.read<double>("/scalar_ledger_reference", na + scalars.size());
          if (scalars.sources().any()) { // 5 numbers before the plug-flow gas's two
            sourceAccount = f.read<double>("/scalar_sources");
            if (sourceAccount.size() != 5 && sourceAccount.size() != 7)
              throw h5::Error("-restart '" + restartFile + "' holds " + std::to_string(sourceAccount.size()) +
                              " numbers in /scalar_sources, expected 7 (or 5 from before the plug-flow gas)");
          }
        }
        restorePathState(*path, std::vector<std::uint64_t>(words.begin(), words.end()));
        for (std::size_t m = 0; m < monitors.size(); ++m) {
          const std::string name = "/monitors/" + monitors[m].name;
          if (f.exists("/monitors") && f.exists(name)) states[m] = f.read<double>(name);
          else if (!monitors[m].monitor->saveState().empty()) // e.g. window sums: they would start from nothing
            throw h5::Error("-restart '" + restartFile + "' holds no state of the monitor " + monitors[m].name +
                            ": ask for the same answers as the run that wrote the checkpoint");
        }
        for (std::size_t k = 0; k < ops.operators().size(); ++k) {
          const Operator &op = *ops.operators()[k];
          const std::string name = "/operators/" + op.type();
          if (f.exists("/operators") && f.exists(name)) operatorStates[k] = f.read<double>(name);
          else if (!op.saveState().empty()) // e.g. a feed's ledger: the balance would start over
            throw h5::Error("-restart '" + restartFile + "' holds no state of the operator " + op.type() +
                            ": use the same -pipeline as the run that wrote the checkpoint");
        }
        if (switching && !f.exists("/switching"))
          throw h5::Error("-restart '" + restartFile + "' holds no switching state; it was not written by a run on "
                          "several databases");
        if (switching) switchingState = f.read<double>("/switching");
        if (step > steps)
          throw h5::Error("-restart '" + restartFile + "' is at step " + std::to_string(step) +
                          ", beyond this run's " + std::to_string(steps) + " steps (-t_end)");
      },
      PETSC_ERR_USER_INPUT));
  PetscCall(loadFromCheckpoint(db->layout(), nf, restartFile, "masses", fstate.masses()));
  if (na > 0) {
    PetscCall(loadFromCheckpoint(db->layout(), na, restartFile, "scalar_amounts", fstate.amounts()));
    scalars.restoreLedger(scalarReference);
    if (scalars.sources().any()) scalars.sources().restoreAccount(sourceAccount);
  }
  startStep = static_cast<long>(step);
  frames.clear();
  ledger.restore(reference);
  PetscCall(adoptOutputsOf(previousDirectory));
  PetscCall(pathFile->resume(static_cast<double>(pathBytes)));
  PetscCall(jumps->resume(static_cast<double>(jumpsBytes)));
  if (!jumpsRecorded) PetscCall(jumpsFromPathFile());
  for (std::size_t m = 0; m < monitors.size(); ++m) PetscCall(monitors[m].monitor->restoreState(states[m]));
  for (std::size_t k = 0; k < ops.operators().size(); ++k) PetscCall(ops.operators()[k]->restoreState(operatorStates[k]));
  if (switching) { // the database active at the checkpoint; the state is already on it
    PetscCall(switching->restoreState(switchingState));
    const SwitchDecision active = DatabaseSwitcher::savedChoice(switchingState);
    PetscCheck(active.database >= 0 && active.database < switching->set().size() &&
                   active.partner < switching->set().size(),
               comm, PETSC_ERR_FILE_UNEXPECTED, "-restart '%s': the active database %d is not one of the %d of -db",
               restartFile.c_str(), active.database, switching->set().size());
    if (!active.sameAs(switching->active()))
      PetscCall(switchTo(active, path->frame(), startStep * db->metadata().dtRec, false));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

// A restart into another output directory continues the time series of the
// checkpoint's: their files (*.csv, path.txt) are copied here first, and the
// monitors cut them back to the checkpoint's step.
PetscErrorCode Run::Impl::adoptOutputsOf(const std::string &previousDirectory) const {
  namespace fs = std::filesystem;
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(collectively(comm, [&] {
    if (rank != 0) return;
    std::error_code ec;
    if (!fs::is_directory(previousDirectory) || fs::equivalent(previousDirectory, outputDir, ec)) return;
    for (const auto &entry : fs::directory_iterator(previousDirectory)) {
      const fs::path file = entry.path();
      if (!entry.is_regular_file() || (file.extension() != ".csv" && file.filename() != "path.txt")) continue;
      fs::copy_file(file, fs::path(outputDir) / file.filename(), fs::copy_options::overwrite_existing, ec);
      if (ec)
        throw std::runtime_error("Cannot copy '" + file.string() + "' of the checkpoint's run into -output_dir '" +
                                 outputDir + "': " + ec.message());
    }
  }, PETSC_ERR_FILE_WRITE));
  PetscFunctionReturn(PETSC_SUCCESS);
}

// A checkpoint of an rcfd that wrote jumps.csv at the run's end, from
// path.txt: the jumps before the checkpoint are the path's, found there as
// that rcfd found them (a step whose next frame is not its frame + 1), in the
// path's frames, without the database in use (which that rcfd did not record).
PetscErrorCode Run::Impl::jumpsFromPathFile() {
  std::vector<int> frames;
  PetscFunctionBeginUser;
  PetscCall(collectively(comm, [&] { frames = readPathFile(outputDir + "/path.txt"); }, PETSC_ERR_FILE_UNEXPECTED));
  frames.push_back(path->frame()); // the next step's, where the checkpoint's path stands
  const double dt = db->metadata().dtRec;
  for (std::size_t s = 0; s + 1 < frames.size(); ++s)
    if (frames[s + 1] != frames[s] + 1)
      PetscCall(jumps->add(static_cast<long>(s + 1), (s + 1) * dt, frames[s], frames[s + 1], "(not recorded)",
                                 nullptr, nullptr));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
