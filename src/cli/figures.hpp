// Figures are drawn by small matplotlib scripts (src/cli/figures/*.py,
// installed in share/rcfd/figures) from the CSV files rcfd has written, so
// that every number is in a file and a user can edit a script and re-run it
// for a paper.  Python and matplotlib are optional at run time.
#pragma once

#include "rcfd/handle.hpp" // PetscErrorCode, PETSC_SUCCESS on PETSc 3.18
#include "base/petsc_compat.hpp"

#include <string>
#include <vector>

namespace rcfd::cli {

/// Collective.  Rank 0 runs `python3 DIR/script args...`, DIR being
/// $RCFD_FIGURES_DIR, else share/rcfd/figures next to the program's prefix,
/// else the source tree's src/cli/figures; the interpreter is $RCFD_PYTHON,
/// else /usr/bin/python3, else python3 on the PATH.  Without python3 and
/// matplotlib it says so once per process and returns success; a script that
/// fails is an error on every rank naming the command.
PetscErrorCode drawFigure(MPI_Comm comm, const std::string &script, const std::vector<std::string> &args);

/// The default of `rcfd run -plot`: false when $RCFD_PLOT is 0 (a cluster's batch
/// jobs, the test suite: starting python and matplotlib costs about a second
/// per run), true otherwise.
bool figuresByDefault();

/// Collective.  The centre-of-gravity figures of a cog.csv (or ensemble.csv):
/// png (cog.py) and png's name with -delta.png (delta_z.py).
PetscErrorCode drawCogFigures(MPI_Comm comm, const std::string &csv, const std::string &png,
                              const std::string &title);

} // namespace rcfd::cli
