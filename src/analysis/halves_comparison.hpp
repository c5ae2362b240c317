// Size distributions of the bed's bottom and top halves (halves.csv of rcfd
// reference and rcfd run: class,diameter,bottom_mass_fraction,
// top_mass_fraction, time means over a window) compared class by class and by
// the halves' Sauter diameters.  Serial and PETSc-free; errors name the file.
#pragma once

#include "analysis/segregation_score.hpp"

#include <string>
#include <vector>

namespace rcfd {

struct HalvesTable {
  std::string path;
  std::vector<std::string> label;       // d1.950mm, ...
  std::vector<double> diameter;         // m
  std::vector<double> bottom, top;      // mass fractions, each summing to 1
};

/// Throws naming the file when the header does not start with those four
/// columns or a value is not a number; further columns are read past.
HalvesTable readHalves(const CsvTable &table);

/// Sauter diameter 1 / sum(m_i / d_i) of mass fractions m_i [m].
double sauterDiameter(const std::vector<double> &massFractions, const std::vector<double> &diameter);

/// A row of the comparison: a class matched by diameter (within 1 %), or
/// the halves' Sauter diameters (label "d32", in m).
struct HalvesDifference {
  std::string run, label;
  double diameter = 0.0; // m; 0 for the d32 row
  double bottomRef = 0.0, bottomRun = 0.0, topRef = 0.0, topRun = 0.0;
};

/// The reference's classes that the run has, then the d32 row (computed over
/// each file's own classes, so populations with other classes compare too).
std::vector<HalvesDifference> compareHalves(const HalvesTable &reference, const HalvesTable &run,
                                            const std::string &label);

void writeHalvesScores(const std::string &path, const std::string &referencePath,
                       const std::vector<HalvesDifference> &rows);

} // namespace rcfd
