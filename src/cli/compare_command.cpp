// rcfd compare: score the segregation curves Delta z(t) of rcfd runs against
// a reference (rcfd reference's cog.csv): the paper's Eq. 7 error over a
// window and the RMS difference of the whole curve relative to the
// reference's peak.
#include "cli/commands.hpp"
#include "base/petsc_compat.hpp"

#include "analysis/segregation_score.hpp"
#include "base/collective.hpp"
#include "cli/figures.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace rcfd::cli {
namespace {

constexpr int kMaxSeries = 16;

struct CompareOptions {
  std::string reference, output, png, title;
  std::vector<std::string> runs, labels;
  double offset = 0.0, windowBegin = 0.5, windowEnd = 1.5;
};

PetscErrorCode readCompareOptions(MPI_Comm comm, CompareOptions *o) {
  char ref[PETSC_MAX_PATH_LEN] = "", out[PETSC_MAX_PATH_LEN] = "", png[PETSC_MAX_PATH_LEN] = "",
       title[256] = "";
  char *runs[kMaxSeries] = {}, *labels[kMaxSeries] = {};
  PetscInt nruns = kMaxSeries, nlabels = kMaxSeries, nwindow = 2;
  PetscReal window[2] = {o->windowBegin, o->windowEnd};
  PetscBool setRef = PETSC_FALSE, setRuns = PETSC_FALSE, setLabels = PETSC_FALSE,
            setOut = PETSC_FALSE, setWindow = PETSC_FALSE, setPng = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, nullptr, "rcfd compare: score Delta z(t) of runs against a reference", "rcfd");
  PetscCall(PetscOptionsString("-reference", "Reference cog.csv (rcfd reference)", "", "", ref,
                               sizeof ref, &setRef));
  PetscCall(PetscOptionsStringArray("-rcfd", "cog.csv of one or more rcfd runs, comma-separated", "",
                                    runs, &nruns, &setRuns));
  PetscCall(PetscOptionsStringArray("-labels", "A name for each run (default: its file)", "", labels,
                                    &nlabels, &setLabels));
  PetscCall(PetscOptionsReal("-rcfd_time_offset",
                             "Added to the runs' times: the physical time of the database's frame 0 [s]",
                             "", o->offset, &o->offset, nullptr));
  PetscCall(PetscOptionsRealArray("-score_window", "Window t0,t1 [s] of the Eq. 7 means", "", window,
                                  &nwindow, &setWindow));
  PetscCall(PetscOptionsString("-o", "Write the curves at the reference's times to this CSV", "", "",
                               out, sizeof out, &setOut));
  PetscCall(PetscOptionsString("-png", "Draw the Delta z(t) curves into this PNG file (from the -o CSV, "
                               "by default the PNG's name with .csv)", "", "", png, sizeof png, &setPng));
  PetscCall(PetscOptionsString("-title", "Title of the PNG figure", "", title, title, sizeof title,
                               nullptr));
  PetscOptionsEnd();
  for (PetscInt i = 0; i < (setRuns ? nruns : 0); ++i) {
    o->runs.emplace_back(runs[i]);
    PetscCall(PetscFree(runs[i]));
  }
  for (PetscInt i = 0; i < (setLabels ? nlabels : 0); ++i) {
    o->labels.emplace_back(labels[i]);
    PetscCall(PetscFree(labels[i]));
  }
  if (helpRequested()) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCheck(setRef, comm, PETSC_ERR_USER_INPUT,
             "No reference given: pass -reference REF/cog.csv (made by rcfd reference)");
  PetscCheck(!o->runs.empty(), comm, PETSC_ERR_USER_INPUT,
             "No run given: pass -rcfd RUN/cog.csv (several: comma-separated)");
  PetscCheck(!setLabels || o->labels.size() == o->runs.size(), comm, PETSC_ERR_USER_INPUT,
             "-labels has %d names but -rcfd has %d files", (int)o->labels.size(), (int)o->runs.size());
  PetscCheck(!setWindow || (nwindow == 2 && window[0] < window[1]), comm, PETSC_ERR_USER_INPUT,
             "-score_window takes two times t0,t1 [s] with t0 < t1");
  o->reference = ref;
  if (setPng) o->png = png;
  if (setOut) o->output = out;
  else if (setPng) o->output = std::filesystem::path(o->png).replace_extension(".csv").string(); // the figure's numbers
  o->title = title;
  o->windowBegin = window[0];
  o->windowEnd = window[1];
  if (o->labels.empty())
    for (const auto &r : o->runs) o->labels.push_back(r);
  PetscFunctionReturn(PETSC_SUCCESS);
}

void writeCurves(const std::string &path, const DeltaZSeries &ref,
                 const std::vector<DeltaZSeries> &runs, const std::vector<std::string> &labels) {
  if (std::filesystem::path(path).has_parent_path())
    std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write '" + path + "'.");
  f << "time_s,delta_z_reference_m";
  for (const auto &l : labels) f << ",delta_z_" << l << "_m";
  f << '\n';
  f.precision(9);
  for (std::size_t k = 0; k < ref.time.size(); ++k) {
    const double t = ref.time[k];
    f << t << ',' << ref.deltaZ[k];
    for (const auto &r : runs) {
      f << ',';
      if (t >= r.time.front() && t <= r.time.back()) f << interpolate(r, t);
    }
    f << '\n';
  }
  if (!f) throw std::runtime_error("writing '" + path + "' failed.");
}

/// Delta z(t) of the reference and every run from the curves CSV, each
/// run's legend carrying its scores.
PetscErrorCode drawCurves(MPI_Comm comm, const CompareOptions &o, const std::vector<DeltaZScore> &scores) {
  PetscFunctionBeginUser;
  std::vector<std::string> args{o.output, "-o", o.png, "--title", o.title, "--window",
                                std::to_string(o.windowBegin) + "," + std::to_string(o.windowEnd)};
  for (std::size_t i = 0; i < o.labels.size(); ++i) {
    char text[200] = "";
    if (i < scores.size()) // Eq. 7 error and RMS of the whole curve over the reference's peak
      std::snprintf(text, sizeof text, "%s: $\\Delta_\\mathrm{seg}$ = %.0f %%, RMS/peak = %.2f", o.labels[i].c_str(),
                    scores[i].segregationError, scores[i].rmsRelative);
    args.insert(args.end(), {"--legend", text});
  }
  PetscCall(drawFigure(comm, "compare.py", args));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

PetscErrorCode compareCommand(MPI_Comm comm) {
  CompareOptions o;
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(readCompareOptions(comm, &o));
  if (helpRequested()) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(rejectUnusedOptions(comm, "compare"));
  std::vector<DeltaZScore> scores; // rank 0's
  PetscCall(collectively(comm, [&] {
    if (rank != 0) return;
    const DeltaZSeries ref = readDeltaZCsv(o.reference);
    std::vector<DeltaZSeries> runs;
    for (const auto &path : o.runs) {
      runs.push_back(readDeltaZCsv(path, o.offset));
      scores.push_back(scoreDeltaZ(ref, runs.back(), o.windowBegin, o.windowEnd));
    }
    const DeltaZScore &s0 = scores.front();
    std::printf("Delta z = z_cog(smallest) - z_cog(largest) against %s: mean %.4g mm over "
                "[%g, %g] s (%zu samples), peak |Delta z| %.4g mm\n",
                o.reference.c_str(), 1e3 * s0.meanRef, o.windowBegin, o.windowEnd,
                s0.windowSamplesRef, 1e3 * s0.peakRef);
    std::printf("%-28s %14s %14s %10s %10s %s\n", "run", "mean dz [mm]", "Delta_seg [%]",
                "RMS [mm]", "RMS/peak", "curve");
    for (std::size_t i = 0; i < runs.size(); ++i) {
      const DeltaZScore &s = scores[i];
      std::printf("%-28s %14.4f %14.1f %10.4f %10.3f %.3g-%.3g s, %zu samples\n",
                  o.labels[i].c_str(), 1e3 * s.meanModel, s.segregationError, 1e3 * s.rms,
                  s.rmsRelative, s.overlapBegin, s.overlapEnd, s.curveSamples);
    }
    if (!o.output.empty()) {
      writeCurves(o.output, ref, runs, o.labels);
      std::printf("Wrote %s\n", o.output.c_str());
    }
  }));
  if (!o.png.empty()) PetscCall(drawCurves(comm, o, scores));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
