// Checkpoints: everything a run needs to continue bit-identically, in one
// HDF5 file written atomically (temporary name, then rename), so that a
// crash while writing leaves the previous checkpoint intact.
//
//   /masses            [cells, fractions]  natural cell order, kg
//   /path_state        uint64 words of the frame path (position, sequence, PRNG)
//   /frames_used       frame of every step so far
//   /samples           [rows, 2 nf + 5]    the monitor's samples so far
//   /ledger_reference  the mass ledger's reference totals
//   /monitors/<name>   each monitor's saved state (Monitor::saveState), when not empty
//   root attributes    format = "rcfd-checkpoint", step, num_fractions, num_cells, database
#include "path/frame_path.hpp"
#include "base/petsc_compat.hpp"
#include "run/run_impl.hpp"
#include "base/atomic_file.hpp"
#include "base/collective.hpp"
#include "base/h5.hpp"

#include <petscviewerhdf5.h>

#include <cstdio>
#include <memory>

namespace rcfd {

PetscErrorCode Run::Impl::writeCheckpoint(long step) const {
  // The masses are gathered on rank 0, which writes the file (as the fields
  // are written): a failed write then stops every rank with its reason
  // instead of leaving the others in a collective HDF5 call.
  const int nf = set.size();
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  std::unique_ptr<AtomicFile> out; // removes the temporary if anything below fails
  if (rank == 0) PetscCallCXX(out = std::make_unique<AtomicFile>(checkpointFile));
  OwnedVec natural, onZero;
  OwnedScatter scatter, toZero;
  PetscCall(db->layout().naturalScatter(nf, fstate.masses(), natural.put(), scatter.put()));
  PetscCall(VecScatterBegin(scatter, fstate.masses(), natural, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(scatter, fstate.masses(), natural, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterCreateToZero(natural, toZero.put(), onZero.put()));
  PetscCall(VecScatterBegin(toZero, natural, onZero, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(toZero, natural, onZero, INSERT_VALUES, SCATTER_FORWARD));
  PetscInt gathered;
  const PetscScalar *masses = nullptr;
  PetscCall(VecGetLocalSize(onZero, &gathered));
  PetscCall(VecGetArrayRead(onZero, &masses));
  std::vector<std::pair<std::string, std::vector<double>>> states; // the same on every rank
  for (const auto &e : monitors) {
    states.emplace_back(e.name, e.monitor->saveState());
    for (std::size_t k = 0; k + 1 < states.size(); ++k)
      PetscCheck(states.back().second.empty() || states[k].first != e.name || states[k].second.empty(), comm,
                 PETSC_ERR_ARG_WRONG, "Two monitors named '%s' keep state for checkpoints; give them different names",
                 e.name.c_str());
  }
  const PetscErrorCode written = collectively(comm, [&] {
    if (rank != 0) return;
    {
      h5::File f = h5::File::create(*out);
      // As PETSc's VecView writes a vector of block size nf (VecLoad reads it).
      f.write("/masses", std::vector<double>(masses, masses + gathered), nf > 1 ? static_cast<hsize_t>(nf) : 0);
      f.writeAttr("/", "format", std::string("rcfd-checkpoint"));
      f.writeAttr("/", "step", static_cast<long long>(step));
      f.writeAttr("/", "num_fractions", static_cast<long long>(nf));
      f.writeAttr("/", "num_cells", static_cast<long long>(db->mesh().numCells()));
      f.writeAttr("/", "database", dbPath);
      const auto words = path->saveState();
      f.write("/path_state", std::vector<int64_t>(words.begin(), words.end()));
      f.write("/frames_used", std::vector<int32_t>(frames.begin(), frames.end()));
      std::vector<double> flat;
      for (const auto &s : cog->samples()) {
        const auto row = s.flatten();
        flat.insert(flat.end(), row.begin(), row.end());
      }
      f.write("/samples", flat, static_cast<hsize_t>(BedSample::flatSize(nf)));
      f.write("/ledger_reference", ledger.reference());
      f.createGroup("/monitors");
      for (const auto &e : states)
        if (!e.second.empty()) f.write("/monitors/" + e.first, e.second);
      f.close();
    }
    out->commit();
  });
  PetscCall(VecRestoreArrayRead(onZero, &masses));
  PetscCall(written);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Run::Impl::readCheckpoint() {
  const int nf = set.size();
  long long step = 0;
  std::vector<int64_t> words;
  std::vector<int32_t> used;
  std::vector<double> flat, reference;
  std::vector<std::vector<double>> states(monitors.size());
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
        step = f.readAttrInt("/", "step");
        words = f.read<int64_t>("/path_state");
        used = f.read<int32_t>("/frames_used");
        flat = f.read<double>("/samples");
        reference = f.read<double>("/ledger_reference", nf);
        path->restoreState(std::vector<std::uint64_t>(words.begin(), words.end()));
        for (std::size_t m = 0; m < monitors.size(); ++m) {
          const std::string name = "/monitors/" + monitors[m].name;
          if (f.exists("/monitors") && f.exists(name)) states[m] = f.read<double>(name);
          else if (!monitors[m].monitor->saveState().empty()) // e.g. window sums: they would start from nothing
            throw h5::Error("-restart '" + restartFile + "' holds no state of the monitor " + monitors[m].name +
                            ": ask for the same answers as the run that wrote the checkpoint");
        }
        if (step > steps)
          throw h5::Error("-restart '" + restartFile + "' is at step " + std::to_string(step) +
                          ", beyond this run's " + std::to_string(steps) + " steps (-t_end)");
      },
      PETSC_ERR_USER_INPUT));
  OwnedVec natural;
  OwnedScatter scatter;
  OwnedViewer v;
  PetscCall(db->layout().naturalScatter(nf, fstate.masses(), natural.put(), scatter.put()));
  PetscCall(PetscObjectSetName((PetscObject)natural.get(), "masses"));
  PetscCall(PetscViewerHDF5Open(comm, restartFile.c_str(), FILE_MODE_READ, v.put()));
  PetscCall(VecLoad(natural, v));
  PetscCall(VecScatterBegin(scatter, natural, fstate.masses(), INSERT_VALUES, SCATTER_REVERSE));
  PetscCall(VecScatterEnd(scatter, natural, fstate.masses(), INSERT_VALUES, SCATTER_REVERSE));
  startStep = static_cast<long>(step);
  frames.assign(used.begin(), used.end());
  const int width = BedSample::flatSize(nf);
  std::vector<BedSample> samples;
  for (size_t r = 0; r + width <= flat.size(); r += width)
    samples.push_back(BedSample::unflatten(flat.data() + r, nf));
  cog->restore(std::move(samples));
  ledger.restore(reference);
  for (std::size_t m = 0; m < monitors.size(); ++m) PetscCall(monitors[m].monitor->restoreState(states[m]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Run::Impl::writePath() const {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(collectively(comm, [&] {
    if (rank == 0)
      writePathFile(outputDir + "/path.txt", frames,
                    "frame of each step of this run; replay it with -path_type recorded -path_file FILE; " +
                        path->describe());
  }));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
