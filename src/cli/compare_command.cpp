// rcfd compare: score the segregation curves Delta z(t) of rcfd runs against
// a reference (rcfd reference's cog.csv): the paper's Eq. 7 error over a
// window and the RMS difference of the whole curve relative to the
// reference's peak.
#include "cli/commands.hpp"
#include "base/petsc_compat.hpp"

#include "analysis/segregation_score.hpp"
#include "plot/png_plot.hpp"
#include "base/collective.hpp"

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
  PetscCall(PetscOptionsString("-png", "Draw the Delta z(t) curves into this PNG file", "", "", png,
                               sizeof png, &setPng));
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
  if (setOut) o->output = out;
  if (setPng) o->png = png;
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

/// Delta z(t) in mm of the reference and every run, each run's label
/// carrying its scores.
void plotCurves(const CompareOptions &o, const DeltaZSeries &ref,
                const std::vector<DeltaZSeries> &runs, const std::vector<DeltaZScore> &scores) {
  plot::Figure fig;
  fig.title = o.title.empty() ? "Segregation: Delta z = z_CoG(small) - z_CoG(large)" : o.title;
  fig.xLabel = "time [s]";
  fig.yLabel = "Delta z [mm]";
  auto curve = [](const std::string &label, const DeltaZSeries &s) {
    plot::Series c;
    c.label = label;
    c.x = s.time;
    for (double dz : s.deltaZ) c.y.push_back(1e3 * dz);
    return c;
  };
  fig.series.push_back(curve("reference (CFD-DEM)", ref));
  for (std::size_t i = 0; i < runs.size(); ++i) {
    char text[160];
    std::snprintf(text, sizeof text, "%s: Delta_seg %.0f %%, RMS/peak %.2f", o.labels[i].c_str(),
                  scores[i].segregationError, scores[i].rmsRelative);
    fig.series.push_back(curve(text, runs[i]));
  }
  if (std::filesystem::path(o.png).has_parent_path())
    std::filesystem::create_directories(std::filesystem::path(o.png).parent_path());
  plot::writePng(o.png, fig);
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
  PetscCall(collectively(comm, [&] {
    if (rank != 0) return;
    const DeltaZSeries ref = readDeltaZCsv(o.reference);
    std::vector<DeltaZSeries> runs;
    std::vector<DeltaZScore> scores;
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
    if (!o.png.empty()) {
      plotCurves(o, ref, runs, scores);
      std::printf("Wrote %s\n", o.png.c_str());
    }
  }));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
