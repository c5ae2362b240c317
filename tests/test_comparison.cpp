// rcfd compare's scoring on hand-made files with hand-computed answers:
// Delta z (Eq. 7) over two windows and the RMS over the reference's peak, an
// ensemble scored by its mean, the bottom layer's d32 with a gap, profiles,
// the halves' size distributions, the database distance, window labels that
// read back exactly, and bad input refused naming the file; the same classes
// and poly-disperse number through the public rcfd::Comparison (rcfd/study.hpp).
#include "observable/bed_dynamics.hpp"
#include "analysis/class_scores.hpp"
#include "analysis/comparison.hpp"
#include "analysis/halves_comparison.hpp"
#include "analysis/profile_comparison.hpp"
#include "check.hpp"
#include "rcfd/study.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

using namespace rcfd;
using rcfd::test::throwsWith;

namespace {

std::string write(const std::string &path, const std::string &text) {
  std::ofstream(path) << text;
  return path;
}

CsvTable table(const std::string &path) { return CsvTable::read(path); }

/// Field `column` of data row `row` (after the header) of a CSV rcfd wrote.
std::string field(const std::string &path, std::size_t row, const std::string &column) {
  std::ifstream in(path);
  std::string line, name;
  std::vector<std::string> header;
  std::size_t r = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> fields;
    std::stringstream ss(line);
    while (std::getline(ss, name, ',')) fields.push_back(name);
    if (header.empty()) {
      header = fields;
      continue;
    }
    if (r++ != row) continue;
    for (std::size_t c = 0; c < header.size(); ++c)
      if (header[c] == column) return c < fields.size() ? fields[c] : "";
  }
  return "<missing>";
}

// Reference Delta z = 0, 1, 2, 3, 4 mm at t = 0, 0.5, 1, 1.5, 2 s; the run is 2 mm at
// t = 0.1, 1.1, 2.1 s of its own time, shifted by -0.1 s.  Windows [0, 1] and [1, 2]:
// reference means 1 and 3 mm, run 2 mm: Eq. 7 +100 % and -33.3 %.  Curve at the run's
// times 0, 1, 2 s: differences 2, 0, -2 mm, RMS sqrt(8/3) mm, peak 4 mm.
void deltaZ(const std::string &dir) {
  const std::string ref = write(dir + "/ref-cog.csv", "time_s,z_cog_bed_m,z_cog_d1.950mm_m,z_cog_d2.820mm_m,delta_z_m\n"
                                                      "0,0.1,0.1,0.1,0\n0.5,0.1,0.1005,0.0995,0.001\n"
                                                      "1,0.1,0.101,0.099,0.002\n1.5,0.1,0.1015,0.0985,0.003\n"
                                                      "2,0.1,0.102,0.098,0.004\n");
  const std::string run = write(dir + "/run-cog.csv", "time_s,z_cog_bed_m,z_cog_d1.950mm_m,z_cog_d2.820mm_m,delta_z_m,"
                                                      "bulk_mismatch\n0.1,0.1,0.101,0.099,0.002,0\n"
                                                      "1.1,0.1,0.101,0.099,0.002,0\n2.1,0.1,0.101,0.099,0.002,0\n");
  const CurveSet r = readCurves(table(ref), 0.0), m = readCurves(table(run), -0.1);
  const std::vector<TimeSpan> windows{{0.0, 1.0}, {1.0, 2.0}};
  const auto s = scoreCurves(r, m, "two mm", windows);
  RCFD_CHECK(s.size() == 2 && s[0].curve == "delta_z" && s[1].run == "two mm");
  RCFD_CHECK(s[0].score.windowSamplesRef == 3 && s[0].score.windowSamplesModel == 2);
  RCFD_CHECK_CLOSE(s[0].score.meanRef, 1e-3, 1e-15);
  RCFD_CHECK_CLOSE(s[0].score.segregationError, 100.0, 1e-9);
  RCFD_CHECK_CLOSE(s[1].score.meanRef, 3e-3, 1e-15);
  RCFD_CHECK_CLOSE(s[1].score.segregationError, -100.0 / 3.0, 1e-9);
  RCFD_CHECK(s[1].score.curveSamples == 3);
  RCFD_CHECK_CLOSE(s[1].score.rms, std::sqrt(8.0 / 3.0) * 1e-3, 1e-15);
  RCFD_CHECK_CLOSE(s[1].score.rmsRelative, std::sqrt(8.0 / 3.0) / 4.0, 1e-12);

  // The scores CSV: one row per curve and window, the window and curve labels
  // reading back as exactly the times used (2.1 - 0.1 is not 2 in binary).
  const std::string scores = dir + "/scores.csv";
  writeCurveScores(scores, ref, s);
  RCFD_CHECK(field(scores, 1, "window_begin_s") == "1" && field(scores, 1, "unit") == "m");
  RCFD_CHECK(std::strtod(field(scores, 1, "curve_end_s").c_str(), nullptr) == s[1].score.overlapEnd);
  RCFD_CHECK(std::strtod(field(scores, 0, "curve_begin_s").c_str(), nullptr) == s[0].score.overlapBegin);
  RCFD_CHECK_CLOSE(std::strtod(field(scores, 1, "relative_difference_percent").c_str(), nullptr), -100.0 / 3.0, 1e-6);
  RCFD_CHECK_CLOSE(std::strtod(field(scores, 0, "mean_difference").c_str(), nullptr), 1e-3, 1e-12);
  RCFD_CHECK(field(scores, 2, "run") == "<missing>");
  RCFD_CHECK(exactNumber(0.1 + 0.2) == "0.30000000000000004" && exactNumber(3.04 + 0.005) == "3.045");
  RCFD_CHECK(exactNumber(0.5) == "0.5" && exactNumber(0.205) == "0.205");
  RCFD_CHECK(exactNumber(10) == "10" && exactNumber(1200) == "1200" && exactNumber(-3.5) == "-3.5");
  RCFD_CHECK(exactNumber(1e-7) == "1e-07" && std::strtod(exactNumber(1.0 / 3.0).c_str(), nullptr) == 1.0 / 3.0);

  // An ensemble summary is scored by its mean column: the same numbers.
  const std::string ens = write(dir + "/ensemble.csv", "# mean and sample standard deviation over 2 ensemble members\n"
                                                       "time_s,z_cog_bed_m_mean,z_cog_bed_m_std,delta_z_m_mean,"
                                                       "delta_z_m_std\n0.1,0.1,0,0.002,0.001\n1.1,0.1,0,0.002,0.001\n"
                                                       "2.1,0.1,0,0.002,0.001\n");
  RCFD_CHECK(answerFileKind(table(ens)) == AnswerFile::centresOfGravity);
  const auto e = scoreCurves(r, readCurves(table(ens), -0.1), "ensemble", windows);
  RCFD_CHECK(e.size() == 2);
  RCFD_CHECK_CLOSE(e[0].score.segregationError, 100.0, 1e-9);
  RCFD_CHECK_CLOSE(e[1].score.rms, std::sqrt(8.0 / 3.0) * 1e-3, 1e-15);

  // A window outside the data names the file that has no sample in it.
  RCFD_CHECK(throwsWith([&] { scoreCurves(r, m, "x", {{5.0, 6.0}}); },
                        "'" + ref + "', delta_z: the scoring window [5, 6] s holds no sample of the reference."));
  RCFD_CHECK(throwsWith([&] { scoreCurves(r, readCurves(table(run), 3.0), "x", {{0.0, 1.0}}); },
                        "'" + run + "', delta_z: the scoring window [0, 1] s holds no sample of the rcfd run."));
}

// Bottom-layer d32: reference 2.3, 2.4, (gap), 2.6 mm at t = 0, 1, 2, 3 s; run 2.2 mm
// throughout.  Window [0, 3]: reference mean 7.3/3 mm.  Curve at the run's times, the
// reference interpolated over its gap (2.5 mm at 2 s): differences -0.1, -0.2, -0.3,
// -0.4 mm, RMS sqrt(0.075) mm.  The zone column d32_feed_m is a second curve.
void bottomLayer(const std::string &dir) {
  const std::string ref = write(dir + "/ref-bottom.csv", "time_s,d32_bottom_m,umf_m_s,usup_m_s,defluidized,d32_feed_m\n"
                                                         "0,0.0023,0.9,1.1,0,0.002\n1,0.0024,0.9,1.1,0,0.002\n"
                                                         "2,nan,nan,1.1,0,0.002\n3,0.0026,1,1.1,0,0.002\n");
  const std::string run = write(dir + "/run-bottom.csv", "time_s,d32_bottom_m,umf_m_s,usup_m_s,defluidized,d32_feed_m\n"
                                                         "0,0.0022,0.9,1.1,0,0.003\n1,0.0022,0.9,1.1,0,0.003\n"
                                                         "2,0.0022,0.9,1.1,0,0.003\n3,0.0022,0.9,1.1,0,0.003\n");
  RCFD_CHECK(answerFileKind(table(ref)) == AnswerFile::bottomLayer);
  const CurveSet r = readCurves(table(ref), 0.0);
  RCFD_CHECK((r.names == std::vector<std::string>{"d32_bottom", "d32_feed"}) && r.curves[0].time.size() == 3);
  const auto s = scoreCurves(r, readCurves(table(run), 0.0), "run", {{0.0, 3.0}});
  RCFD_CHECK(s.size() == 2);
  RCFD_CHECK_CLOSE(s[0].score.meanRef, 7.3e-3 / 3.0, 1e-15);
  RCFD_CHECK_CLOSE(s[0].score.meanModel - s[0].score.meanRef, 2.2e-3 - 7.3e-3 / 3.0, 1e-15);
  RCFD_CHECK(s[0].score.curveSamples == 4);
  RCFD_CHECK_CLOSE(s[0].score.rms, std::sqrt(0.075) * 1e-3, 1e-15);
  RCFD_CHECK_CLOSE(s[1].score.rms, 1e-3, 1e-15);
  RCFD_CHECK_CLOSE(s[1].score.segregationError, 50.0, 1e-9);
  // A run file of the curves kind but without a curve of the reference.
  const std::string other = write(dir + "/other-bottom.csv", "time_s,d32_bottom_m_x\n0,1\n");
  RCFD_CHECK(throwsWith([&] { readCurves(table(other), 0.0); }, "'" + other + "' is none of the files"));
}

// Profiles on 4 layers, the top one empty in both: small class differences -0.05, 0,
// 0.05 (RMS sqrt(0.005/3), peak 0.3), large 0.05, 0, 0.05, total 0, 0, 0.1 (RMS
// sqrt(0.01/3), max 0.1, peak 0.5).  The run labels its small class d1.95mm.
void profiles(const std::string &dir) {
  const std::string ref = write(dir + "/ref-profiles.csv", "# SI units\nz,alpha_d1.950mm,alpha_d2.820mm,alpha_total\n"
                                                           "0.0025,0.3,0.2,0.5\n0.0075,0.2,0.2,0.4\n"
                                                           "0.0125,0.1,0,0.1\n0.0175,0,0,0\n");
  const std::string run = write(dir + "/run-profiles.csv", "z,alpha_d1.95mm,alpha_d2.820mm,alpha_total\n"
                                                           "0.0025,0.25,0.25,0.5\n0.0075,0.2,0.2,0.4\n"
                                                           "0.0125,0.15,0.05,0.2\n0.0175,0,0,0\n");
  const auto d = compareProfiles(readProfiles(table(ref)), readProfiles(table(run)), "run");
  RCFD_CHECK(d.size() == 3 && d[0].curve == "alpha_d1.950mm" && d[2].curve == "alpha_total");
  RCFD_CHECK(d[0].layers == 3 && d[0].zBegin == 0.0025 && d[0].zEnd == 0.0125);
  RCFD_CHECK_CLOSE(d[0].rms, std::sqrt(0.005 / 3.0), 1e-15);
  RCFD_CHECK_CLOSE(d[0].rmsRelative, std::sqrt(0.005 / 3.0) / 0.3, 1e-14);
  RCFD_CHECK_CLOSE(d[1].rms, std::sqrt(0.005 / 3.0), 1e-15);
  RCFD_CHECK_CLOSE(d[1].maxAbs, 0.05, 1e-15);
  RCFD_CHECK_CLOSE(d[2].rms, std::sqrt(0.01 / 3.0), 1e-15);
  RCFD_CHECK_CLOSE(d[2].maxAbs, 0.1, 1e-15);
  RCFD_CHECK_CLOSE(d[2].peakRef, 0.5, 1e-15);
  const std::string scores = dir + "/profile-scores.csv";
  writeProfileScores(scores, ref, d);
  RCFD_CHECK(field(scores, 2, "curve") == "alpha_total" && field(scores, 2, "layers") == "3");
  RCFD_CHECK_CLOSE(std::strtod(field(scores, 2, "rms_difference").c_str(), nullptr), std::sqrt(0.01 / 3.0), 1e-9);
  // Another mesh, another layout, a missing total.
  const std::string coarse = write(dir + "/coarse.csv", "z,alpha_d1.950mm,alpha_total\n0.005,0.3,0.3\n0.015,0.1,0.1\n");
  RCFD_CHECK(throwsWith([&] { compareProfiles(readProfiles(table(ref)), readProfiles(table(coarse)), "c"); },
                        "'" + coarse + "' has other layers than the reference"));
  const std::string noTotal = write(dir + "/nototal.csv", "z,alpha_d1.950mm\n0.005,0.3\n");
  RCFD_CHECK(throwsWith([&] { readProfiles(table(noTotal)); }, "'" + noTotal + "' is not a profiles file"));
}

// Halves: reference bottom 0.4 / 0.6, top 0.6 / 0.4 (small / large); run bottom 0.3 / 0.7,
// top 0.7 / 0.3.  Differences -0.1, +0.1 at the bottom, +0.1, -0.1 at the top; the d32
// rows by hand: 1 / (0.4 / 1.95 + 0.6 / 2.82) mm = 2.392950 mm and so on.
void halves(const std::string &dir) {
  const std::string ref = write(dir + "/ref-halves.csv", "# mass fractions\nclass,diameter,bottom_mass_fraction,"
                                                         "top_mass_fraction\nd1.950mm,0.00195,0.4,0.6\n"
                                                         "d2.820mm,0.00282,0.6,0.4\n");
  const std::string run = write(dir + "/run-halves.csv", "class,diameter,bottom_mass_fraction,top_mass_fraction,"
                                                         "d_over_d32\nd2.820mm,0.00282,0.7,0.3,1.2\n"
                                                         "d1.950mm,0.001951,0.3,0.7,0.8\n");
  RCFD_CHECK(answerFileKind(table(ref)) == AnswerFile::halves);
  const auto d = compareHalves(readHalves(table(ref)), readHalves(table(run)), "run");
  RCFD_CHECK(d.size() == 3 && d[0].label == "d1.950mm" && d[2].label == "d32");
  RCFD_CHECK_CLOSE(d[0].bottomRun - d[0].bottomRef, -0.1, 1e-15);
  RCFD_CHECK_CLOSE(d[0].topRun - d[0].topRef, 0.1, 1e-15);
  RCFD_CHECK_CLOSE(d[1].bottomRun - d[1].bottomRef, 0.1, 1e-15);
  RCFD_CHECK_CLOSE(d[2].bottomRef, 2.392950391644909e-3, 1e-15);
  RCFD_CHECK_CLOSE(d[2].topRef, 2.2245145631067964e-3, 1e-15);
  RCFD_CHECK_CLOSE(d[2].bottomRun, 1.0 / (0.3 / 1.951e-3 + 0.7 / 2.82e-3), 1e-15);
  const std::string scores = dir + "/halves-scores.csv";
  writeHalvesScores(scores, ref, d);
  RCFD_CHECK(field(scores, 2, "unit") == "m" && field(scores, 0, "unit") == "1");
  RCFD_CHECK_CLOSE(std::strtod(field(scores, 1, "top_difference").c_str(), nullptr), -0.1, 1e-9);
  const std::string text = write(dir + "/text.csv", "class,diameter,bottom_mass_fraction,top_mass_fraction\n"
                                                    "d1.950mm,0.00195,0.4,lots\n");
  RCFD_CHECK(throwsWith([&] { readHalves(table(text)); }, "'" + text + "', line 2, column 'top_mass_fraction': expected a number"));
}

/// A cog.csv of classes `labels` at t = 0, 1, 2, 3 s: the bed at `bed` m, each class
/// `offsets` mm above it (a row per class), `masses` kg in mass_<label>_kg columns if any.
std::string cogFile(const std::string &path, const std::vector<double> &bed, const std::vector<std::string> &labels,
                    const std::vector<std::vector<double>> &offsets, const std::vector<double> &masses) {
  std::string text = "time_s,z_cog_bed_m";
  for (const auto &l : labels) text += ",z_cog_" + l + "_m";
  for (std::size_t i = 0; i < masses.size(); ++i) text += ",mass_" + labels[i] + "_kg";
  text += "\n";
  for (std::size_t k = 0; k < bed.size(); ++k) {
    text += std::to_string(k) + "," + csvNumber(bed[k]);
    for (const auto &o : offsets) text += "," + csvNumber(bed[k] + 1e-3 * o[k]);
    for (double m : masses) text += "," + csvNumber(m);
    text += "\n";
  }
  return write(path, text);
}

// Every class, z_CoG,i - z_CoG,bed [mm] at t = 0, 1, 2, 3 s, the beds moving differently:
//   reference d1.000mm -2 -4 -6 -8 (peak 8), d2.000mm 0 1 0 -1 (peak 1), d3.000mm 1 3 5 10 (peak 10);
//   run       d1.005mm -1 -4 -7 -8 (RMS sqrt(1/2)), d2.000mm 2 3 2 1 (RMS 2), d3.02mm 1 3 5 7 (RMS 1.5);
// classes within 1 % are one.  Mass shares 0.2 / 0.3 / 0.5: the poly-disperse number
// sqrt(0.2 * 0.5 + 0.3 * 4 + 0.5 * 2.25) mm = sqrt(2.425) mm, over d3's peak 10 mm.  Window
// [0, 1.5]: d1 means -3 and -2.5 mm.  A run without d2 (and with a d4 the reference lacks)
// weighs d1 and d3 by 0.2 and 0.5 renormalised: sqrt((0.2 * 0.5 + 0.5 * 2.25) / 0.7) mm.
void classes(const std::string &dir) {
  const std::vector<double> refBed{0.1, 0.12, 0.1, 0.12}, runBed{0.11, 0.11, 0.11, 0.11};
  const std::vector<double> d1{-1, -4, -7, -8}, d2{2, 3, 2, 1}, d3{1, 3, 5, 7};
  const std::string ref = cogFile(dir + "/ref-classes.csv", refBed, {"d1.000mm", "d2.000mm", "d3.000mm"},
                                  {{-2, -4, -6, -8}, {0, 1, 0, -1}, {1, 3, 5, 10}}, {});
  const std::string run = cogFile(dir + "/run-classes.csv", runBed, {"d1.005mm", "d2.000mm", "d3.02mm"},
                                  {d1, d2, d3}, {0.2e-3, 0.3e-3, 0.5e-3});
  const std::string lacking = cogFile(dir + "/lacking.csv", runBed, {"d1.000mm", "d3.000mm", "d4.000mm"},
                                      {d1, d3, d3}, {0.2, 0.5, 0.3});
  const std::string massless = cogFile(dir + "/massless.csv", runBed, {"d1.000mm", "d2.000mm", "d3.000mm"},
                                       {d1, d2, d3}, {});
  const ClassCurveSet r = readClassCurves(table(ref), 0.0);
  RCFD_CHECK(r.curves.names == (std::vector<std::string>{"class_d1.000mm", "class_d2.000mm", "class_d3.000mm"}));
  RCFD_CHECK(r.massShares.empty());
  const std::vector<TimeSpan> windows{{0.0, 1.5}, {0.0, 3.0}};
  const ClassComparison c = compareClasses(r, readClassCurves(table(run), 0.0), "run", windows);
  RCFD_CHECK(c.notes.empty() && c.scores.size() == 6 && c.hasPolydisperse);
  RCFD_CHECK(c.scores[0].curve == "class_d1.000mm" && c.scores[5].curve == "class_d3.000mm");
  const double rms[3] = {std::sqrt(0.5), 2.0, 1.5}, peak[3] = {8.0, 1.0, 10.0};
  for (int i = 0; i < 3; ++i) {
    const DeltaZScore &s = c.scores[2 * i].score;
    RCFD_CHECK(s.curveSamples == 4);
    RCFD_CHECK_CLOSE(s.rms, 1e-3 * rms[i], 1e-14);
    RCFD_CHECK_CLOSE(s.peakRef, 1e-3 * peak[i], 1e-14);
    RCFD_CHECK_CLOSE(s.rmsRelative, rms[i] / peak[i], 1e-12);
  }
  RCFD_CHECK(c.scores[0].score.windowSamplesRef == 2 && c.scores[1].score.windowSamplesModel == 4);
  RCFD_CHECK_CLOSE(c.scores[0].score.meanRef, -3e-3, 1e-14);
  RCFD_CHECK_CLOSE(c.scores[0].score.meanModel - c.scores[0].score.meanRef, 0.5e-3, 1e-14);
  const PolydisperseScore &p = c.polydisperse;
  RCFD_CHECK(p.weightsFrom == run && p.largestClass == "class_d3.000mm" && p.weights.size() == 3);
  RCFD_CHECK_CLOSE(p.weights[1], 0.3, 1e-14);
  RCFD_CHECK_CLOSE(p.rms, 1e-3 * std::sqrt(2.425), 1e-14);
  RCFD_CHECK_CLOSE(p.peakLargest, 10e-3, 1e-14);
  RCFD_CHECK_CLOSE(p.rmsRelative, std::sqrt(2.425) / 10.0, 1e-12);

  // A run lacking d2 and holding a d4: both noted, d1 and d3 scored and weighed.
  const ClassComparison l = compareClasses(r, readClassCurves(table(lacking), 0.0), "lacking", windows);
  RCFD_CHECK(l.scores.size() == 4 && l.notes.size() == 2 && l.matched.names.size() == 2);
  RCFD_CHECK(l.notes.size() == 2 && l.notes[0].find("has no class d2.000mm") != std::string::npos &&
             l.notes[1].find("the reference '" + ref + "' has no class d4.000mm") != std::string::npos);
  RCFD_CHECK_CLOSE(l.polydisperse.rms, 1e-3 * std::sqrt((0.2 * 0.5 + 0.5 * 2.25) / 0.7), 1e-14);
  RCFD_CHECK_CLOSE(l.polydisperse.weights[0], 0.2 / 0.7, 1e-14);
  // No mass columns on either side: classes scored, no poly-disperse number, a note why.
  const ClassComparison m = compareClasses(r, readClassCurves(table(massless), 0.0), "massless", windows);
  RCFD_CHECK(m.scores.size() == 6 && !m.hasPolydisperse && m.notes.size() == 1 &&
             m.notes[0].find("no poly-disperse number") != std::string::npos);
  // The poly-disperse row in the scores CSV, after the class rows.
  const std::string scores = dir + "/class-scores.csv";
  writeCurveScores(scores, ref, c.scores, polydisperseRows({p}));
  RCFD_CHECK(field(scores, 6, "curve") == "polydisperse" && field(scores, 6, "window_begin_s").empty());
  RCFD_CHECK_CLOSE(std::strtod(field(scores, 6, "rms_over_peak").c_str(), nullptr), std::sqrt(2.425) / 10.0, 1e-8);
  RCFD_CHECK_CLOSE(std::strtod(field(scores, 4, "rms_over_peak").c_str(), nullptr), 0.15, 1e-8);

  // Columns that do not fit together: one sentence naming the file.
  const std::string wrongMass = write(dir + "/wrong-mass.csv", "time_s,z_cog_bed_m,z_cog_d1.000mm_m,z_cog_d2.000mm_m,"
                                                               "mass_d1.000mm_kg,mass_d2.500mm_kg\n0,0.1,0.1,0.1,1,1\n");
  RCFD_CHECK(throwsWith([&] { readClassCurves(table(wrongMass), 0.0); },
                        "'" + wrongMass + "' has mass columns of the classes d1.000mm, d2.500mm but centre-of-gravity "
                        "columns of d1.000mm, d2.000mm: each class needs both, in the same order."));
  const std::string noBed = write(dir + "/no-bed.csv", "time_s,z_cog_d1.000mm_m,z_cog_d2.000mm_m\n0,0.1,0.1\n");
  RCFD_CHECK(throwsWith([&] { readClassCurves(table(noBed), 0.0); },
                        "'" + noBed + "' has class columns (z_cog_d1.000mm_m, z_cog_d2.000mm_m) but no z_cog_bed_m"));
  const std::string twins = write(dir + "/twins.csv", "time_s,z_cog_bed_m,z_cog_d1.000mm_m,z_cog_d1.005mm_m\n0,0.1,0.1,0.1\n");
  RCFD_CHECK(throwsWith([&] { readClassCurves(table(twins), 0.0); },
                        "'" + twins + "' has two classes within 1 % of d1.005mm"));
}

// Bed dynamics: z_CoG = 0.10, 0.12, 0.10, 0.12 m, Delta z_CoG = 0.01 m; a bed_dynamics.csv
// of 0.008 m; Delta DB = |0.01 - 0.008| / 0.008 = 0.25 (the second the denominator).
void distance(const std::string &dir) {
  const std::string cog = write(dir + "/bed-cog.csv", "time_s,z_cog_bed_m,delta_z_m\n0,0.1,0\n1,0.12,0\n"
                                                      "2,0.1,0\n3,0.12,0\n");
  const std::string bed = write(dir + "/bed_dynamics.csv", "samples,mean_z_cog_m,delta_z_cog_m\n4,0.1,0.008\n");
  const double a = bedDynamicsOfFile(table(cog)), b = bedDynamicsOfFile(table(bed));
  RCFD_CHECK_CLOSE(a, 0.01, 1e-15);
  RCFD_CHECK_CLOSE(databaseDistance(a, b), 0.25, 1e-12);
  RCFD_CHECK_CLOSE(databaseDistance(b, a), 0.2, 1e-12);
  RCFD_CHECK(throwsWith([&] { bedDynamicsOfFile(table(dir + "/ensemble.csv")); }, "is an ensemble summary"));
  RCFD_CHECK(throwsWith([&] { bedDynamicsOfFile(table(dir + "/ref-profiles.csv")); }, "has no z_cog_bed_m column"));
}

// The files of classes() through rcfd::Comparison, as rcfd compare and a
// study program see them: every class's z_CoG,i - z_CoG,bed against the
// reference's (RMS sqrt(1/2), 2 and 1.5 mm over peaks 8, 1 and 10 mm; over
// [0, 1.5] s d1's means -3 and -2.5 mm of 2 samples each), the poly-disperse
// number of each run (sqrt(2.425) mm over 10 mm; without d2
// sqrt((0.2 * 0.5 + 0.5 * 2.25) / 0.7) mm), the rows of the scores CSV and
// the classes' curves CSV; a run of another kind refused in one sentence.
void comparisonObject(const std::string &dir) {
  const MPI_Comm comm = PETSC_COMM_WORLD;
  const std::string ref = dir + "/ref-classes.csv", run = dir + "/run-classes.csv", lacking = dir + "/lacking.csv";
  Comparison c(comm);
  RCFD_CHECK(c.setReference(ref) == 0 && c.addRun(run, "run") == 0 && c.addRun(lacking, "lacking") == 0);
  RCFD_CHECK(c.setWindows({0.0, 1.5, 0.0, 3.0}) == 0);
  RCFD_CHECK(c.solve() == 0);
  RCFD_CHECK(c.kind() == Comparison::Kind::centresOfGravity);
  RCFD_CHECK(c.scores().size() == 4 && c.scores()[0].curve == "delta_z"); // 2 runs x 2 windows
  const std::vector<Comparison::Score> &s = c.classScores();
  RCFD_CHECK(s.size() == 10); // run: 3 classes x 2 windows; lacking: d1 and d3
  const char *names[3] = {"class_d1.000mm", "class_d2.000mm", "class_d3.000mm"};
  const double rms[3] = {std::sqrt(0.5), 2.0, 1.5}, peak[3] = {8.0, 1.0, 10.0};
  for (int i = 0; s.size() == 10 && i < 3; ++i)
    for (int w = 0; w < 2; ++w) {
      const Comparison::Score &k = s[2 * i + w];
      RCFD_CHECK(k.run == "run" && k.curve == names[i]);
      RCFD_CHECK_CLOSE(k.agreement.rms, 1e-3 * rms[i], 1e-14);
      RCFD_CHECK_CLOSE(k.agreement.peakReference, 1e-3 * peak[i], 1e-14);
      RCFD_CHECK_CLOSE(k.agreement.rmsRelative, rms[i] / peak[i], 1e-12);
      RCFD_CHECK(k.agreement.overlapSamples == 4 && k.agreement.overlapBegin == 0.0 && k.agreement.overlapEnd == 3.0);
    }
  if (s.size() == 10) {
    const CurveAgreement &d1 = s[0].agreement;
    RCFD_CHECK(d1.windowBegin == 0.0 && d1.windowEnd == 1.5 && d1.samplesReference == 2 && d1.samplesRun == 2);
    RCFD_CHECK_CLOSE(d1.meanReference, -3e-3, 1e-14);
    RCFD_CHECK_CLOSE(d1.meanRun, -2.5e-3, 1e-14);
    RCFD_CHECK(s[1].agreement.samplesRun == 4); // [0, 3] s
    RCFD_CHECK(s[6].run == "lacking" && s[6].curve == names[0] && s[9].curve == names[2]);
    RCFD_CHECK_CLOSE(s[8].agreement.rms, 1.5e-3, 1e-14);
  }
  const std::vector<Comparison::Polydisperse> &p = c.polydisperse();
  RCFD_CHECK(p.size() == 2);
  if (p.size() == 2) {
    RCFD_CHECK(p[0].run == "run" && p[0].runIndex == 0 && p[1].run == "lacking" && p[1].runIndex == 1);
    RCFD_CHECK(p[0].weightsFrom == run && p[0].largestClass == "class_d3.000mm" && p[0].weights.size() == 3);
    RCFD_CHECK_CLOSE(p[0].weights[1], 0.3, 1e-14);
    RCFD_CHECK_CLOSE(p[0].rms, 1e-3 * std::sqrt(2.425), 1e-14);
    RCFD_CHECK_CLOSE(p[0].peakLargest, 10e-3, 1e-14);
    RCFD_CHECK_CLOSE(p[0].rmsRelative, std::sqrt(2.425) / 10.0, 1e-12);
    RCFD_CHECK(p[0].overlapSamples == 4);
    RCFD_CHECK_CLOSE(p[1].rms, 1e-3 * std::sqrt((0.2 * 0.5 + 0.5 * 2.25) / 0.7), 1e-14);
    RCFD_CHECK(p[1].weights.size() == 2);
    if (p[1].weights.size() == 2) RCFD_CHECK_CLOSE(p[1].weights[0], 0.2 / 0.7, 1e-14);
  }
  RCFD_CHECK(c.notes().size() == 2 && c.notes()[0].find("has no class d2.000mm") != std::string::npos);
  // The scores CSV: the curves' rows, the classes', then a poly-disperse row per run.
  const std::string scores = dir + "/object-scores.csv", curves = dir + "/object.csv";
  RCFD_CHECK(c.writeScores(scores) == 0 && c.writeCurves(curves) == 0);
  RCFD_CHECK(field(scores, 3, "curve") == "delta_z" && field(scores, 4, "curve") == names[0]);
  RCFD_CHECK(field(scores, 14, "curve") == "polydisperse" && field(scores, 15, "run") == "lacking");
  RCFD_CHECK_CLOSE(std::strtod(field(scores, 14, "rms_over_peak").c_str(), nullptr), std::sqrt(2.425) / 10.0, 1e-8);
  RCFD_CHECK_CLOSE(std::strtod(field(scores, 8, "rms_over_peak").c_str(), nullptr), 0.15, 1e-8);
  RCFD_CHECK(Comparison::classCurvesFile(curves) == dir + "/object-classes.csv");
  RCFD_CHECK(field(Comparison::classCurvesFile(curves), 3, "class_d3.000mm_run_m") == csvNumber(7e-3));
  RCFD_CHECK(c.view(PETSC_VIEWER_STDOUT_SELF) == 0);

  // A run's file of another kind: one sentence naming both files.
  Comparison other(comm);
  RCFD_CHECK(other.setReference(ref) == 0 && other.addRun(dir + "/ref-profiles.csv") == 0);
  const PetscErrorCode refused = other.solve();
  char *why = nullptr;
  PetscErrorMessage(refused, nullptr, &why);
  RCFD_CHECK(refused == PETSC_ERR_USER_INPUT && why &&
             std::string(why) == "'" + dir + "/ref-profiles.csv' is a profiles file but the reference '" + ref +
                                     "' is a centre-of-gravity file: compare files of one kind.");
  RCFD_CHECK(other.writeScores(dir + "/unsolved.csv") == PETSC_ERR_ORDER && !std::filesystem::exists(dir + "/unsolved.csv"));
  // The database distance of two files (distance(): 0.25).
  Comparison::DatabaseDistance d;
  RCFD_CHECK(Comparison::databaseDistance(comm, dir + "/bed-cog.csv", dir + "/bed_dynamics.csv", &d) == 0);
  RCFD_CHECK_CLOSE(d.dynamicsA, 0.01, 1e-15);
  RCFD_CHECK_CLOSE(d.distance, 0.25, 1e-12);
  RCFD_CHECK(d.framesA == 0 && d.framesB == 0);
}

} // namespace

int main(int argc, char **argv) {
  if (PetscInitialize(&argc, &argv, nullptr, nullptr)) return 1;
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr); // refusals print no traceback
  char tmpl[] = "/tmp/rcfd_test_comparison_XXXXXX";
  const char *dir = mkdtemp(tmpl);
  if (!dir) return 1;
  deltaZ(dir);
  bottomLayer(dir);
  profiles(dir);
  classes(dir);
  halves(dir);
  distance(dir);
  comparisonObject(dir);
  std::filesystem::remove_all(dir);
  PetscPopErrorHandler();
  const int result = RCFD_TEST_RESULT();
  if (PetscFinalize()) return 1;
  return result;
}
