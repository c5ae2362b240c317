// The spread of an ensemble: the same case run along several stitched paths
// (rcfd run -ensemble N), summarised column by column.  Serial and PETSc-free.
#pragma once

#include <string>
#include <vector>

namespace rcfd {

/// Mean and sample standard deviation over the members' cog.csv files (same
/// columns and rows), written atomically to csvOut: a comment line, then the
/// first column (time) as it is and <column>_mean,<column>_std of every
/// other column.  Throws std::runtime_error naming the file at fault.
void writeEnsembleSummary(const std::vector<std::string> &memberCsvs, const std::string &csvOut);

} // namespace rcfd
