// rcfd compare: the answers of rcfd runs (or ensembles) against a reference
// (rcfd reference, or another run): Delta z(t) with the paper's Eq. 7 over
// one or more windows and the RMS of the whole curve over the reference's
// peak; the bottom layer's d32(t); vertical profiles; the halves' size
// distributions; and the database distance between two bed dynamics.  The
// scoring is in src/analysis (comparison.hpp, profile_comparison.hpp,
// halves_comparison.hpp); this file reads options, prints and draws.
#include "cli/commands.hpp"
#include "base/petsc_compat.hpp"

#include "base/checked_options.hpp"
#include "observable/bed_dynamics.hpp"
#include "analysis/class_scores.hpp"
#include "analysis/comparison.hpp"
#include "analysis/halves_comparison.hpp"
#include "analysis/profile_comparison.hpp"
#include "base/collective.hpp"
#include "cli/figures.hpp"
#include "rcfd/database.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace rcfd::cli {
namespace {

constexpr int kMaxSeries = 1024; // runs, labels and windows compared at once

struct CompareOptions {
  std::string reference, output, scores, png, title;
  std::vector<std::string> runs, labels, distance;
  std::vector<TimeSpan> windows{{0.5, 1.5}};
  double offset = 0.0;
};

/// path's name with its extension replaced: delta_z.png -> delta_z-scores.csv.
std::string sibling(const std::string &path, const std::string &suffix) {
  std::filesystem::path p(path);
  return (p.parent_path() / (p.stem().string() + suffix)).string();
}

/// The classes' curves beside the -o CSV: delta_z.csv -> delta_z-classes.csv.
std::string classesFile(const std::string &output) { return sibling(output, "-classes.csv"); }

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
void printDeltaZScores(const std::string &reference, const std::vector<CurveScore> &scores) {
  std::printf("Delta z = z_cog(smallest) - z_cog(largest) against %s: mean", reference.c_str());
  for (const CurveScore &c : scores) // the reference's mean over each window, once
    if (c.run == scores.front().run)
      std::printf("%s %.4g mm over [%s, %s] s (%zu samples)", &c == &scores.front() ? "" : ",", 1e3 * c.score.meanRef,
                  exactNumber(c.score.windowBegin).c_str(), exactNumber(c.score.windowEnd).c_str(),
                  c.score.windowSamplesRef);
  std::printf(", peak |Delta z| %.4g mm\n", 1e3 * scores.front().score.peakRef);
  std::printf("%-28s %14s %14s %10s %10s %-16s %s\n", "run", "mean dz [mm]", "Delta_seg [%]", "RMS [mm]",
              "RMS/peak", "window [s]", "curve");
  for (const CurveScore &c : scores) {
    const DeltaZScore &s = c.score;
    std::printf("%-28s %14.4f %14.1f %10.4f %10.3f %-16s %s-%s s, %zu samples\n", c.run.c_str(), 1e3 * s.meanModel,
                s.segregationError, 1e3 * s.rms, s.rmsRelative,
                (exactNumber(s.windowBegin) + "-" + exactNumber(s.windowEnd)).c_str(),
                exactNumber(s.overlapBegin).c_str(), exactNumber(s.overlapEnd).c_str(), s.curveSamples);
  }
}

/// Any other curve (d32 of the bottom layer and of zones), in mm.
void printCurveScores(const std::string &reference, const std::vector<CurveScore> &scores) {
  std::printf("Against %s (values in mm):\n", reference.c_str());
  std::printf("%-24s %-14s %-14s %11s %11s %11s %10s %10s  %s\n", "run", "curve", "window [s]", "mean ref",
              "mean run", "diff [%]", "RMS", "RMS/peak", "curve");
  for (const CurveScore &c : scores) {
    const DeltaZScore &s = c.score;
    std::printf("%-24s %-14s %-14s %11.5f %11.5f %11.2f %10.5f %10.4f  %s-%s s, %zu samples\n", c.run.c_str(),
                c.curve.c_str(), (exactNumber(s.windowBegin) + "-" + exactNumber(s.windowEnd)).c_str(),
                1e3 * s.meanRef, 1e3 * s.meanModel, s.segregationError, 1e3 * s.rms, s.rmsRelative,
                exactNumber(s.overlapBegin).c_str(), exactNumber(s.overlapEnd).c_str(), s.curveSamples);
  }
}

/// Each class's z_CoG,i - z_CoG,bed against the reference's, then the
/// poly-disperse number of each run and the notes (classes not scored).
/// Printed before the Delta z table, and no line starts with a run's label:
/// scripts read the Delta z row as the last line, or as the line starting
/// with the label.
void printClassScores(const std::vector<CurveScore> &scores, const std::vector<PolydisperseScore> &polys,
                      const std::vector<std::string> &notes) {
  if (!scores.empty()) {
    std::printf("Each class: z_cog,i - z_cog,bed against the reference (RMS over the run / the reference's peak "
                "|z_cog,i - z_cog,bed|; means over the window, in mm):\n");
    std::printf("%-16s %-28s %-12s %10s %10s %10s %10s %10s %10s\n", "class", "run", "window [s]", "mean ref",
                "mean run", "diff", "RMS", "peak ref", "RMS/peak");
    for (const CurveScore &c : scores) {
      const DeltaZScore &s = c.score;
      std::printf("%-16s %-28s %-12s %10.4f %10.4f %10.4f %10.4f %10.4f %10.3f\n", c.curve.c_str(), c.run.c_str(),
                  (exactNumber(s.windowBegin) + "-" + exactNumber(s.windowEnd)).c_str(), 1e3 * s.meanRef,
                  1e3 * s.meanModel, 1e3 * (s.meanModel - s.meanRef), 1e3 * s.rms, 1e3 * s.peakRef, s.rmsRelative);
    }
  }
  for (const PolydisperseScore &p : polys) {
    std::printf("Poly-disperse, %s: sqrt(sum w_i RMS_i^2) = %.4f mm = %.3f of the peak %.4f mm of %s; w_i",
                p.run.c_str(), 1e3 * p.rms, p.rmsRelative, 1e3 * p.peakLargest, p.largestClass.c_str());
    for (double w : p.weights) std::printf(" %.4g", w);
    std::printf(" (mass shares of %s)\n", p.weightsFrom.c_str());
  }
  for (const std::string &note : notes) std::printf("Note: %s\n", note.c_str());
}

/// Delta z(t) of the reference and every run from the curves CSV, each run's
/// legend carrying its scores over the first window; beside it each class's
/// z_CoG,i - z_CoG,bed when the classes CSV was written.
PetscErrorCode drawDeltaZ(MPI_Comm comm, const CompareOptions &o, const std::vector<CurveScore> &scores,
                          const std::vector<std::string> &classLegends) {
  PetscFunctionBeginUser;
  const TimeSpan &w = o.windows.front();
  std::vector<std::string> args{o.output, "-o", o.png, "--title", o.title, "--window",
                                exactNumber(w.begin) + "," + exactNumber(w.end)};
  if (!classLegends.empty()) args.insert(args.end(), {"--classes", classesFile(o.output)});
  for (const auto &text : classLegends) args.insert(args.end(), {"--class-legend", text});
  for (const auto &label : o.labels) {
    char text[200] = "";
    for (const CurveScore &c : scores)
      if (c.run == label && c.curve == "delta_z" && c.score.windowBegin == w.begin && c.score.windowEnd == w.end)
        std::snprintf(text, sizeof text, "%s: $\\Delta_\\mathrm{seg}$ = %.0f %%, RMS/peak = %.2f", label.c_str(),
                      c.score.segregationError, c.score.rmsRelative);
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

/// Rank 0: Delta z or d32 curves over time; of centre-of-gravity files also
/// every class.  *classLegends: when the classes CSV was written, a legend
/// for each run's class curves (with its poly-disperse number).
void compareCurves(const CompareOptions &o, const CsvTable &refTable, std::vector<CurveScore> *scores,
                   std::vector<std::string> *classLegends) {
  const CurveSet ref = readCurves(refTable, 0.0);
  const bool cog = answerFileKind(refTable) == AnswerFile::centresOfGravity;
  const ClassCurveSet refClasses = cog ? readClassCurves(refTable, 0.0) : ClassCurveSet{};
  std::vector<CurveSet> runs, runClasses;
  std::vector<CurveScore> classScores;
  std::vector<PolydisperseScore> polys;
  std::vector<std::string> notes;
  for (std::size_t i = 0; i < o.runs.size(); ++i) {
    const CsvTable table = CsvTable::read(o.runs[i], "run's file");
    runs.push_back(readCurves(table, o.offset));
    const auto s = scoreCurves(ref, runs.back(), o.labels[i], o.windows);
    scores->insert(scores->end(), s.begin(), s.end());
    if (!cog) continue;
    const ClassComparison c = compareClasses(refClasses, readClassCurves(table, o.offset), o.labels[i], o.windows);
    runClasses.push_back(c.matched);
    classScores.insert(classScores.end(), c.scores.begin(), c.scores.end());
    notes.insert(notes.end(), c.notes.begin(), c.notes.end());
    if (c.hasPolydisperse) polys.push_back(c.polydisperse);
    char text[200];
    std::snprintf(text, sizeof text, "%s: poly-disperse %.2f of the largest class's peak", o.labels[i].c_str(),
                  c.polydisperse.rmsRelative);
    classLegends->push_back(c.hasPolydisperse ? text : o.labels[i]);
  }
  printClassScores(classScores, polys, notes);
  if (ref.names == std::vector<std::string>{"delta_z"}) printDeltaZScores(o.reference, *scores);
  else printCurveScores(o.reference, *scores);
  if (classScores.empty() || o.output.empty()) classLegends->clear(); // no classes CSV, no class panel
  if (!o.output.empty()) {
    writeCurvesSideBySide(o.output, ref, runs, o.labels);
    std::printf("Wrote %s\n", o.output.c_str());
    if (!classLegends->empty()) {
      writeCurvesSideBySide(classesFile(o.output), refClasses.curves, runClasses, o.labels);
      std::printf("Wrote %s\n", classesFile(o.output).c_str());
    }
  }
  scores->insert(scores->end(), classScores.begin(), classScores.end()); // after the curves' rows, as written
  if (!o.scores.empty()) writeCurveScores(o.scores, o.reference, *scores, polydisperseRows(polys));
}

/// Rank 0: vertical profiles.
void compareProfileFiles(const CompareOptions &o, const CsvTable &refTable) {
  const ProfileTable ref = readProfiles(refTable);
  std::vector<ProfileDifference> rows;
  for (std::size_t i = 0; i < o.runs.size(); ++i) {
    const auto d = compareProfiles(ref, readProfiles(CsvTable::read(o.runs[i], "run's file")), o.labels[i]);
    rows.insert(rows.end(), d.begin(), d.end());
  }
  std::printf("Vertical profiles against %s (alpha: volume fraction, over the layers holding solid):\n",
              o.reference.c_str());
  std::printf("%-24s %-18s %7s %12s %12s %12s %10s\n", "run", "curve", "layers", "RMS diff", "max |diff|",
              "peak ref", "RMS/peak");
  for (const auto &d : rows)
    std::printf("%-24s %-18s %7zu %12.4g %12.4g %12.4g %10.3f\n", d.run.c_str(), d.curve.c_str(), d.layers, d.rms,
                d.maxAbs, d.peakRef, d.rmsRelative);
  if (!o.scores.empty()) writeProfileScores(o.scores, o.reference, rows);
}

/// Rank 0: the halves' size distributions.
void compareHalvesFiles(const CompareOptions &o, const CsvTable &refTable) {
  const HalvesTable ref = readHalves(refTable);
  std::vector<HalvesDifference> rows;
  for (std::size_t i = 0; i < o.runs.size(); ++i) {
    const auto d = compareHalves(ref, readHalves(CsvTable::read(o.runs[i], "run's file")), o.labels[i]);
    rows.insert(rows.end(), d.begin(), d.end());
  }
  std::printf("Size distributions of the bottom and top halves against %s (mass fractions; d32 in mm):\n",
              o.reference.c_str());
  std::printf("%-24s %-10s %10s %10s %10s %10s %10s %10s\n", "run", "class", "bottom ref", "bottom run", "diff",
              "top ref", "top run", "diff");
  for (const auto &d : rows) {
    const double f = d.diameter == 0.0 ? 1e3 : 1.0; // the d32 row in mm
    std::printf("%-24s %-10s %10.4f %10.4f %10.4f %10.4f %10.4f %10.4f\n", d.run.c_str(), d.label.c_str(),
                f * d.bottomRef, f * d.bottomRun, f * (d.bottomRun - d.bottomRef), f * d.topRef, f * d.topRun,
                f * (d.topRun - d.topRef));
  }
  if (!o.scores.empty()) writeHalvesScores(o.scores, o.reference, rows);
}

bool isDatabase(const std::string &path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  return ext == ".h5" || ext == ".hdf5";
}

/// Collective: Delta DB between two bed dynamics.
PetscErrorCode databaseDistanceCommand(MPI_Comm comm, const CompareOptions &o) {
  PetscMPIInt rank;
  double dyn[2] = {0.0, 0.0};
  std::size_t samples[2] = {0, 0};
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  for (int i = 0; i < 2; ++i) {
    const std::string &path = o.distance[i];
    if (isDatabase(path)) {
      DatabaseLoadOptions load;
      load.loadShifts = false;
      std::unique_ptr<Database> db;
      PetscCall(Database::load(comm, path, load, &db));
      std::vector<double> zCog;
      PetscCall(databaseBedCentres(*db, &zCog));
      dyn[i] = bedDynamics(zCog);
      samples[i] = zCog.size();
    } else {
      PetscCall(collectively(comm, [&] {
        if (rank == 0) dyn[i] = bedDynamicsOfFile(CsvTable::read(path, "bed-dynamics file"));
      }, PETSC_ERR_USER_INPUT));
      PetscCallMPI(MPI_Bcast(&dyn[i], 1, MPI_DOUBLE, 0, comm));
    }
  }
  PetscCall(collectively(comm, [&] {
    if (rank != 0) return;
    double distance = 0.0;
    try {
      distance = databaseDistance(dyn[0], dyn[1]);
    } catch (const std::invalid_argument &) {
      throw std::runtime_error("'" + o.distance[1] + "' has no bed dynamics (Delta z_CoG = 0), so it cannot be "
                               "the denominator of the database distance.");
    }
    for (int i = 0; i < 2; ++i)
      std::printf("Delta z_CoG %c = %.6g mm  (%s%s)\n", 'A' + i, 1e3 * dyn[i], o.distance[i].c_str(),
                  samples[i] ? (", " + std::to_string(samples[i]) + " frames").c_str() : "");
    std::printf("Delta DB = |A - B| / B = %.6g (%.4g %%)\n", distance, 100.0 * distance);
    if (!o.scores.empty())
      writeTextFile(o.scores, "# database distance: |Delta z_CoG,a - Delta z_CoG,b| / Delta z_CoG,b, b the "
                              "second named\na,b,delta_z_cog_a_m,delta_z_cog_b_m,database_distance\n" +
                                  o.distance[0] + "," + o.distance[1] + "," + csvNumber(dyn[0]) + "," +
                                  csvNumber(dyn[1]) + "," + csvNumber(distance) + "\n");
  }, PETSC_ERR_USER_INPUT));
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
  if (!o.distance.empty()) {
    PetscCall(databaseDistanceCommand(comm, o));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  int kind = 0; // AnswerFile, broadcast from rank 0
  PetscCall(collectively(comm, [&] {
    if (rank != 0) return;
    const AnswerFile k = answerFileKind(CsvTable::read(o.reference, "reference file"));
    kind = static_cast<int>(k);
    for (const auto &run : o.runs) { // one kind throughout
      const AnswerFile r = answerFileKind(CsvTable::read(run, "run's file"));
      if (r != k)
        throw std::runtime_error("'" + run + "' is a " + describe(r) + " but the reference '" + o.reference +
                                 "' is a " + describe(k) + ": compare files of one kind.");
    }
    if (k == AnswerFile::bedDynamics)
      throw std::runtime_error("'" + o.reference + "' holds a bed dynamics: compare it with -db_distance A,B.");
    if ((k == AnswerFile::profiles || k == AnswerFile::halves) && !o.output.empty())
      throw std::runtime_error("-o writes curves over time, which the " + describe(k) + " '" + o.reference +
                               "' does not hold: use -scores.");
    if (k == AnswerFile::bottomLayer && !o.png.empty())
      throw std::runtime_error("-png draws Delta z, profiles and halves, not the bottom-layer file '" +
                               o.reference + "': plot the -o CSV.");
  }, PETSC_ERR_USER_INPUT));
  PetscCallMPI(MPI_Bcast(&kind, 1, MPI_INT, 0, comm));
  const AnswerFile k = static_cast<AnswerFile>(kind);
  // The Delta z figure is drawn from the curves CSV: by default the PNG's name with .csv.
  if (k == AnswerFile::centresOfGravity && o.output.empty() && !o.png.empty()) o.output = sibling(o.png, ".csv");
  std::vector<CurveScore> scores; // rank 0's
  std::vector<std::string> classLegends; // rank 0's
  PetscCall(collectively(comm, [&] {
    if (rank != 0) return;
    const CsvTable ref = CsvTable::read(o.reference, "reference file");
    if (k == AnswerFile::centresOfGravity || k == AnswerFile::bottomLayer) compareCurves(o, ref, &scores, &classLegends);
    if (k == AnswerFile::profiles) compareProfileFiles(o, ref);
    if (k == AnswerFile::halves) compareHalvesFiles(o, ref);
    if (!o.scores.empty()) std::printf("Wrote %s\n", o.scores.c_str());
  }, PETSC_ERR_USER_INPUT));
  if (o.png.empty()) PetscFunctionReturn(PETSC_SUCCESS);
  if (k == AnswerFile::centresOfGravity) PetscCall(drawDeltaZ(comm, o, scores, classLegends));
  if (k == AnswerFile::profiles) PetscCall(drawFiles(comm, o, "compare_profiles.py"));
  if (k == AnswerFile::halves) PetscCall(drawFiles(comm, o, "compare_halves.py"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd::cli
