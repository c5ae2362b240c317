// PNG figures of the centre-of-gravity series rcfd writes (cog.csv), and of
// an ensemble's mean and spread.
#pragma once

#include <string>
#include <vector>

namespace rcfd {

/// z_cog of the bed and of every fraction over time (mm), and delta_z in a
/// second figure next to it (<png stem>-delta.png).  Throws std::runtime_error.
void plotCogCsv(const std::string &csvPath, const std::string &pngPath, const std::string &title);

/// Mean and standard deviation over the members' cog.csv files (same rows),
/// written as CSV (time, then mean and std of every column) and as a PNG of
/// the z_cog and delta_z means with +- one standard deviation bands.
void summariseEnsemble(const std::vector<std::string> &memberCsvs, const std::string &csvOut,
                       const std::string &pngOut, const std::string &title);

} // namespace rcfd
