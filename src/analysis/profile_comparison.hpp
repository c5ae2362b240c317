// Vertical profiles (profiles.csv of rcfd reference and rcfd run: z, then
// alpha_d<D>mm per size class and alpha_total, time means over a window)
// compared layer by layer.  Serial and PETSc-free; errors name the file.
#pragma once

#include "analysis/segregation_score.hpp"

#include <string>
#include <vector>

namespace rcfd {

struct ProfileTable {
  std::string path;
  std::vector<double> z;                  // m, layer centres, increasing
  std::vector<std::string> curves;        // column names: alpha_d1.950mm, ..., alpha_total
  std::vector<double> diameter;           // m, per curve; 0 for alpha_total
  std::vector<std::vector<double>> alpha; // [curve][layer], volume fractions
};

/// Throws naming the file when its header is not z,alpha_d<D>mm...,alpha_total
/// or a value is not a number.
ProfileTable readProfiles(const CsvTable &table);

/// One compared profile.  Layers: those where the reference's or the run's
/// alpha_total is positive (the freeboard above both beds would dilute the
/// RMS); rms over them of alpha_run - alpha_ref; peakRef the reference's
/// largest alpha there.
struct ProfileDifference {
  std::string run, curve;
  std::size_t layers = 0;
  double zBegin = 0.0, zEnd = 0.0; // m, lowest and highest layer centre used
  double rms = 0.0, maxAbs = 0.0, peakRef = 0.0, rmsRelative = 0.0;
};

/// The index in run.curves of the reference's curve c (a class matched by
/// diameter within 1 %, alpha_total by name), or -1.
int matchingProfile(const ProfileTable &reference, std::size_t c, const ProfileTable &run);

/// Every curve of the reference that the run has too (alpha_total always).
/// Throws naming the run's file when its layers are not the reference's
/// (another mesh: profiles are layer means, so they are not interpolated).
std::vector<ProfileDifference> compareProfiles(const ProfileTable &reference, const ProfileTable &run,
                                               const std::string &label);

/// One row per compared curve, units in the header.
void writeProfileScores(const std::string &path, const std::string &referencePath,
                        const std::vector<ProfileDifference> &rows);

} // namespace rcfd
