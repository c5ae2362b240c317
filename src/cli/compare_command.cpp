// rcfd compare: the answers of rcfd runs (or ensembles) against a reference
// (rcfd reference, or another run): Delta z(t) with the paper's Eq. 7 over
// one or more windows and the RMS of the whole curve over the reference's
// peak; the bottom layer's d32(t); vertical profiles; the halves' size
// distributions; and the database distance between two bed dynamics.  The
// scoring and the files it writes are rcfd::Comparison's (rcfd/study.hpp);
// this file reads options, prints and draws.
#include "cli/commands.hpp"
#include "base/petsc_compat.hpp"

#include "analysis/segregation_score.hpp"
#include "base/checked_options.hpp"
#include "base/collective.hpp"
#include "base/atomic_file.hpp"
#include "cli/figures.hpp"
#include "rcfd/study.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace rcfd::cli {
namespace {

constexpr int kMaxSeries = 1024; // runs, labels and windows compared at once

struct Window {
  double begin = 0.0, end = 0.0; // s
};

struct CompareOptions {
  std::string reference, output, scores, png, title;
  std::vector<std::string> runs, labels, distance;
  std::vector<Window> windows{{0.5, 1.5}};
  double offset = 0.0;
};

/// path's name with its extension replaced: delta_z.png -> delta_z-scores.csv.
std::string sibling(const std::string &path, const std::string &suffix) {
  std::filesystem::path p(path);
  return (p.parent_path() / (p.stem().string() + suffix)).string();
}

PetscErrorCode readCompareOptions(MPI_Comm comm, CompareOptions *o) {
  char ref[PETSC_MAX_PATH_LEN] = "", out[PETSC_MAX_PATH_LEN] = "", scores[PETSC_MAX_PATH_LEN] = "",
       png[PETSC_MAX_PATH_LEN] = "", title[256] = "";
  PetscInt nwindow = 2 * kMaxSeries;
  std::vector<PetscReal> window(2 * kMaxSeries, 0.0);
  window[0] = 0.5;
  window[1] = 1.5;
  PetscBool setRef = PETSC_FALSE, setRuns = PETSC_FALSE, setLabels = PETSC_FALSE, setOut = PETSC_FALSE,
            setScores = PETSC_FALSE, setWindow = PETSC_FALSE, setPng = PETSC_FALSE, setDistance = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, nullptr, "rcfd compare: runs against a reference, and database distances", "rcfd");
  PetscCall(PetscOptionsString("-reference", "Reference file: cog.csv, profiles.csv or halves.csv of rcfd "
                               "reference (or any file a run writes)", "", "", ref, sizeof ref, &setRef));
  PetscCall(checkedStringArray(PetscOptionsObject, "-rcfd", "Files of one or more runs, comma-separated, of the reference's kind "
                        "(cog.csv or ensemble.csv, bottom.csv, profiles.csv, halves.csv)", kMaxSeries, &o->runs, &setRuns));
  PetscCall(checkedStringArray(PetscOptionsObject, "-labels", "A name for each run (default: its file)", kMaxSeries, &o->labels, &setLabels));
  PetscCall(PetscOptionsReal("-rcfd_time_offset",
                             "Added to the runs' times: the physical time of the database's frame 0 [s]",
                             "", o->offset, &o->offset, nullptr));
  PetscCall(checkedRealArray(PetscOptionsObject, "-score_window",
                             "Windows t0,t1[,t0,t1...] [s] of the window means (Eq. 7)", window.data(),
                             &nwindow, &setWindow));
  PetscCall(checkedStringArray(PetscOptionsObject, "-db_distance", "Two bed dynamics A,B (a database .h5, a cog.csv or bed_dynamics.csv): "
                        "Delta DB = |Delta z_CoG,A - Delta z_CoG,B| / Delta z_CoG,B", kMaxSeries, &o->distance, &setDistance));
  PetscCall(PetscOptionsString("-o", "Write the curves over time at the reference's times to this CSV", "", "",
                               out, sizeof out, &setOut));
  PetscCall(PetscOptionsString("-scores", "Write the scores to this CSV (default: the -o or -png name with "
                               "-scores.csv)", "", "", scores, sizeof scores, &setScores));
  PetscCall(PetscOptionsString("-png", "Draw the comparison into this PNG file", "", "", png, sizeof png, &setPng));
  PetscCall(PetscOptionsString("-title", "Title of the PNG figure", "", title, title, sizeof title, nullptr));
  PetscOptionsEnd();
  if (helpRequested()) PetscFunctionReturn(PETSC_SUCCESS);
  if (setDistance) {
    PetscCheck(o->distance.size() == 2, comm, PETSC_ERR_USER_INPUT,
               "-db_distance takes two bed dynamics A,B (a database .h5, a cog.csv or a bed_dynamics.csv), not %d",
               (int)o->distance.size());
    PetscCheck(!setRef && !setRuns && !setOut && !setPng, comm, PETSC_ERR_USER_INPUT,
               "-db_distance is a comparison of its own: give -reference, -rcfd, -o and -png in another call");
  } else {
    PetscCheck(setRef, comm, PETSC_ERR_USER_INPUT,
               "No reference given: pass -reference REF/cog.csv (made by rcfd reference), or -db_distance A,B");
    PetscCheck(!o->runs.empty(), comm, PETSC_ERR_USER_INPUT,
               "No run given: pass -rcfd RUN/cog.csv (several: comma-separated)");
  }
  PetscCheck(!setLabels || o->labels.size() == o->runs.size(), comm, PETSC_ERR_USER_INPUT,
             "-labels has %d names but -rcfd has %d files", (int)o->labels.size(), (int)o->runs.size());
  if (setWindow) {
    PetscCheck(nwindow % 2 == 0 && nwindow > 0, comm, PETSC_ERR_USER_INPUT,
               "-score_window takes pairs of times t0,t1[,t0,t1...] [s], not %d numbers", (int)nwindow);
    o->windows.clear();
    for (PetscInt i = 0; i < nwindow; i += 2) {
      PetscCheck(window[i] < window[i + 1], comm, PETSC_ERR_USER_INPUT,
                 "-score_window: window %d, [%s, %s] s, does not have t0 < t1", (int)(i / 2 + 1),
                 exactNumber(window[i]).c_str(), exactNumber(window[i + 1]).c_str());
      o->windows.push_back({window[i], window[i + 1]});
    }
  }
  o->reference = ref;
  o->title = title;
  if (setPng) o->png = png;
  if (setOut) o->output = out;
  if (setScores) o->scores = scores;
  else if (!o->output.empty()) o->scores = sibling(o->output, "-scores.csv");
  else if (!o->png.empty()) o->scores = sibling(o->png, "-scores.csv");
  if (o->labels.empty())
    for (const auto &r : o->runs) o->labels.push_back(r);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/// Delta z in the table rcfd compare has always printed (scripts read its
/// columns 2-5: mean Delta z, Delta_seg, RMS, RMS/peak), one line per window.
void printDeltaZScores(const std::string &reference, const std::vector<Comparison::Score> &scores) {
  std::printf("Delta z = z_cog(smallest) - z_cog(largest) against %s: mean", reference.c_str());
  for (const Comparison::Score &c : scores) // the reference's mean over each window, once
    if (c.run == scores.front().run)
      std::printf("%s %.4g mm over [%s, %s] s (%zu samples)", &c == &scores.front() ? "" : ",",
                  1e3 * c.agreement.meanReference, exactNumber(c.agreement.windowBegin).c_str(),
                  exactNumber(c.agreement.windowEnd).c_str(), c.agreement.samplesReference);
  std::printf(", peak |Delta z| %.4g mm\n", 1e3 * scores.front().agreement.peakReference);
  std::printf("%-28s %14s %14s %10s %10s %-16s %s\n", "run", "mean dz [mm]", "Delta_seg [%]", "RMS [mm]",
              "RMS/peak", "window [s]", "curve");
  for (const Comparison::Score &c : scores) {
    const CurveAgreement &s = c.agreement;
    std::printf("%-28s %14.4f %14.1f %10.4f %10.3f %-16s %s-%s s, %zu samples\n", c.run.c_str(), 1e3 * s.meanRun,
                s.segregationError, 1e3 * s.rms, s.rmsRelative,
                (exactNumber(s.windowBegin) + "-" + exactNumber(s.windowEnd)).c_str(),
                exactNumber(s.overlapBegin).c_str(), exactNumber(s.overlapEnd).c_str(), s.overlapSamples);
  }
}

/// Any other curve (d32 of the bottom layer and of zones), in mm.
void printCurveScores(const std::string &reference, const std::vector<Comparison::Score> &scores) {
  std::printf("Against %s (values in mm):\n", reference.c_str());
  std::printf("%-24s %-14s %-14s %11s %11s %11s %10s %10s  %s\n", "run", "curve", "window [s]", "mean ref",
              "mean run", "diff [%]", "RMS", "RMS/peak", "curve");
  for (const Comparison::Score &c : scores) {
    const CurveAgreement &s = c.agreement;
    std::printf("%-24s %-14s %-14s %11.5f %11.5f %11.2f %10.5f %10.4f  %s-%s s, %zu samples\n", c.run.c_str(),
                c.curve.c_str(), (exactNumber(s.windowBegin) + "-" + exactNumber(s.windowEnd)).c_str(),
                1e3 * s.meanReference, 1e3 * s.meanRun, s.segregationError, 1e3 * s.rms, s.rmsRelative,
                exactNumber(s.overlapBegin).c_str(), exactNumber(s.overlapEnd).c_str(), s.overlapSamples);
  }
}

/// Each class's z_CoG,i - z_CoG,bed against the reference's, then the
/// poly-disperse number of each run and the notes (classes not scored).
/// Printed before the Delta z table, and no line starts with a run's label:
/// scripts read the Delta z row as the last line, or as the line starting
/// with the label.
void printClassScores(const Comparison &comparison) {
  if (!comparison.classScores().empty()) {
    std::printf("Each class: z_cog,i - z_cog,bed against the reference (RMS over the run / the reference's peak "
                "|z_cog,i - z_cog,bed|; means over the window, in mm):\n");
    std::printf("%-16s %-28s %-12s %10s %10s %10s %10s %10s %10s\n", "class", "run", "window [s]", "mean ref",
                "mean run", "diff", "RMS", "peak ref", "RMS/peak");
    for (const Comparison::Score &c : comparison.classScores()) {
      const CurveAgreement &s = c.agreement;
      std::printf("%-16s %-28s %-12s %10.4f %10.4f %10.4f %10.4f %10.4f %10.3f\n", c.curve.c_str(), c.run.c_str(),
                  (exactNumber(s.windowBegin) + "-" + exactNumber(s.windowEnd)).c_str(), 1e3 * s.meanReference,
                  1e3 * s.meanRun, 1e3 * (s.meanRun - s.meanReference), 1e3 * s.rms, 1e3 * s.peakReference,
                  s.rmsRelative);
    }
  }
  for (const Comparison::Polydisperse &p : comparison.polydisperse()) {
    std::printf("Poly-disperse, %s: sqrt(sum w_i RMS_i^2) = %.4f mm = %.3f of the peak %.4f mm of %s; w_i",
                p.run.c_str(), 1e3 * p.rms, p.rmsRelative, 1e3 * p.peakLargest, p.largestClass.c_str());
    for (double w : p.weights) std::printf(" %.4g", w);
    std::printf(" (mass shares of %s)\n", p.weightsFrom.c_str());
  }
  for (const std::string &note : comparison.notes()) std::printf("Note: %s\n", note.c_str());
}

/// A legend for each run's class curves (with its poly-disperse number),
/// when the classes CSV was written; else none.
std::vector<std::string> classLegends(const CompareOptions &o, const Comparison &comparison) {
  std::vector<std::string> legends;
  if (comparison.classScores().empty() || o.output.empty()) return legends; // no classes CSV, no class panel
  for (std::size_t i = 0; i < o.labels.size(); ++i) {
    legends.push_back(o.labels[i]);
    for (const Comparison::Polydisperse &p : comparison.polydisperse())
      if (p.runIndex == i) {
        char text[200];
        std::snprintf(text, sizeof text, "%s: poly-disperse %.2f of the largest class's peak", o.labels[i].c_str(),
                      p.rmsRelative);
        legends.back() = text;
      }
  }
  return legends;
}

/// Delta z(t) of the reference and every run from the curves CSV, each run's
/// legend carrying its scores over the first window; beside it each class's
/// z_CoG,i - z_CoG,bed when the classes CSV was written.
PetscErrorCode drawDeltaZ(MPI_Comm comm, const CompareOptions &o, const Comparison &comparison) {
  PetscFunctionBeginUser;
  const Window &w = o.windows.front();
  std::vector<std::string> args{o.output, "-o", o.png, "--title", o.title, "--window",
                                exactNumber(w.begin) + "," + exactNumber(w.end)};
  const std::vector<std::string> legends = classLegends(o, comparison);
  if (!legends.empty()) args.insert(args.end(), {"--classes", Comparison::classCurvesFile(o.output)});
  for (const auto &text : legends) args.insert(args.end(), {"--class-legend", text});
  for (const auto &label : o.labels) {
    char text[200] = "";
    for (const Comparison::Score &c : comparison.scores())
      if (c.run == label && c.curve == "delta_z" && c.agreement.windowBegin == w.begin &&
          c.agreement.windowEnd == w.end)
        std::snprintf(text, sizeof text, "%s: $\\Delta_\\mathrm{seg}$ = %.0f %%, RMS/peak = %.2f", label.c_str(),
                      c.agreement.segregationError, c.agreement.rmsRelative);
    args.insert(args.end(), {"--legend", text});
  }
  PetscCall(drawFigure(comm, "compare.py", args));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/// The reference's and the runs' files given to a figure script as they are.
PetscErrorCode drawFiles(MPI_Comm comm, const CompareOptions &o, const char *script) {
  PetscFunctionBeginUser;
  std::vector<std::string> args{o.reference};
  args.insert(args.end(), o.runs.begin(), o.runs.end());
  args.insert(args.end(), {"-o", o.png, "--title", o.title});
  for (const auto &label : o.labels) args.insert(args.end(), {"--label", label});
  PetscCall(drawFigure(comm, script, args));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/// Rank 0: the tables of vertical profiles.
void printProfileScores(const std::string &reference, const std::vector<Comparison::ProfileScore> &rows) {
  std::printf("Vertical profiles against %s (alpha: volume fraction, over the layers holding solid):\n",
              reference.c_str());
  std::printf("%-24s %-18s %7s %12s %12s %12s %10s\n", "run", "curve", "layers", "RMS diff", "max |diff|",
              "peak ref", "RMS/peak");
  for (const auto &d : rows)
    std::printf("%-24s %-18s %7zu %12.4g %12.4g %12.4g %10.3f\n", d.run.c_str(), d.curve.c_str(), d.layers, d.rms,
                d.maxAbs, d.peakReference, d.rmsRelative);
}

/// Rank 0: the table of the halves' size distributions.
void printHalvesScores(const std::string &reference, const std::vector<Comparison::HalvesScore> &rows) {
  std::printf("Size distributions of the bottom and top halves against %s (mass fractions; d32 in mm):\n",
              reference.c_str());
  std::printf("%-24s %-10s %10s %10s %10s %10s %10s %10s\n", "run", "class", "bottom ref", "bottom run", "diff",
              "top ref", "top run", "diff");
  for (const auto &d : rows) {
    const double f = d.diameter == 0.0 ? 1e3 : 1.0; // the d32 row in mm
    std::printf("%-24s %-10s %10.4f %10.4f %10.4f %10.4f %10.4f %10.4f\n", d.run.c_str(), d.label.c_str(),
                f * d.bottomReference, f * d.bottomRun, f * (d.bottomRun - d.bottomReference), f * d.topReference,
                f * d.topRun, f * (d.topRun - d.topReference));
  }
}

/// Collective: Delta DB between two bed dynamics.
PetscErrorCode databaseDistanceCommand(MPI_Comm comm, const CompareOptions &o) {
  PetscMPIInt rank;
  Comparison::DatabaseDistance d;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(Comparison::databaseDistance(comm, o.distance[0], o.distance[1], &d));
  const double dyn[2] = {d.dynamicsA, d.dynamicsB};
  const std::size_t frames[2] = {d.framesA, d.framesB};
  PetscCall(collectively(comm, [&] {
    if (rank != 0) return;
    for (int i = 0; i < 2; ++i)
      std::printf("Delta z_CoG %c = %.6g mm  (%s%s)\n", 'A' + i, 1e3 * dyn[i], o.distance[i].c_str(),
                  frames[i] ? (", " + std::to_string(frames[i]) + " frames").c_str() : "");
    std::printf("Delta DB = |A - B| / B = %.6g (%.4g %%)\n", d.distance, 100.0 * d.distance);
    if (!o.scores.empty()) {
      const std::filesystem::path p(o.scores);
      if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path());
      writeTextAtomically(o.scores, "# database distance: |Delta z_CoG,a - Delta z_CoG,b| / Delta z_CoG,b, b the "
                                    "second named\na,b,delta_z_cog_a_m,delta_z_cog_b_m,database_distance\n" +
                                        o.distance[0] + "," + o.distance[1] + "," + csvNumber(dyn[0]) + "," +
                                        csvNumber(dyn[1]) + "," + csvNumber(d.distance) + "\n");
    }
  }, PETSC_ERR_USER_INPUT));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/// Why this command cannot do what its options ask with files of this kind,
/// or "".
std::string refusal(const CompareOptions &o, Comparison::Kind kind) {
  const char *what = kind == Comparison::Kind::profiles ? "profiles file" : "halves file";
  if ((kind == Comparison::Kind::profiles || kind == Comparison::Kind::halves) && !o.output.empty())
    return "-o writes curves over time, which the " + std::string(what) + " '" + o.reference +
           "' does not hold: use -scores.";
  if (kind == Comparison::Kind::bottomLayer && !o.png.empty())
    return "-png draws Delta z, profiles and halves, not the bottom-layer file '" + o.reference +
           "': plot the -o CSV.";
  return "";
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
  if (!o.distance.empty()) {
    PetscCall(databaseDistanceCommand(comm, o));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  Comparison comparison(comm);
  PetscCall(comparison.setReference(o.reference));
  for (std::size_t i = 0; i < o.runs.size(); ++i) PetscCall(comparison.addRun(o.runs[i], o.labels[i]));
  std::vector<double> windows;
  for (const Window &w : o.windows) windows.insert(windows.end(), {w.begin, w.end});
  PetscCall(comparison.setWindows(windows));
  comparison.setTimeOffset(o.offset);
  PetscCall(comparison.setUp());
  const Comparison::Kind k = comparison.kind();
  const std::string refused = refusal(o, k);
  PetscCheck(refused.empty(), comm, PETSC_ERR_USER_INPUT, "%s", refused.c_str());
  // The Delta z figure is drawn from the curves CSV: by default the PNG's name with .csv.
  if (k == Comparison::Kind::centresOfGravity && o.output.empty() && !o.png.empty())
    o.output = sibling(o.png, ".csv");
  PetscCall(comparison.solve());
  const bool curves = k == Comparison::Kind::centresOfGravity || k == Comparison::Kind::bottomLayer;
  if (rank == 0) {
    if (curves) {
      printClassScores(comparison);
      if (k == Comparison::Kind::centresOfGravity) printDeltaZScores(o.reference, comparison.scores());
      else printCurveScores(o.reference, comparison.scores());
    }
    if (k == Comparison::Kind::profiles) printProfileScores(o.reference, comparison.profileScores());
    if (k == Comparison::Kind::halves) printHalvesScores(o.reference, comparison.halvesScores());
  }
  if (curves && !o.output.empty()) {
    PetscCall(comparison.writeCurves(o.output));
    if (rank == 0) std::printf("Wrote %s\n", o.output.c_str());
    if (rank == 0 && !comparison.classScores().empty())
      std::printf("Wrote %s\n", Comparison::classCurvesFile(o.output).c_str());
  }
  if (!o.scores.empty()) {
    PetscCall(comparison.writeScores(o.scores));
    if (rank == 0) std::printf("Wrote %s\n", o.scores.c_str());
  }
  if (o.png.empty()) PetscFunctionReturn(PETSC_SUCCESS);
  if (k == Comparison::Kind::centresOfGravity) PetscCall(drawDeltaZ(comm, o, comparison));
  if (k == Comparison::Kind::profiles) PetscCall(drawFiles(comm, o, "compare_profiles.py"));
  if (k == Comparison::Kind::halves) PetscCall(drawFiles(comm, o, "compare_halves.py"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
