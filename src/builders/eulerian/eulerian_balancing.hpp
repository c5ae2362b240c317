// Balancing of a traced Eulerian shift (docs/database-format.md, "Building from
// Eulerian frames"): unreached cells filled from their neighbours, support
// seeds, and iterative proportional scaling towards the next frame's solid.
#pragma once

#include "builders/eulerian/eulerian_frames.hpp"

#include <vector>

namespace rcfd {

/// The traced shift T made mass-consistent, T m = mNext to the scaling
/// tolerance where it can be: cells of `fullNext` (holding solid at t_{k+1})
/// that no tracer reached borrow their nearest reached neighbours' sources,
/// every occupied column gets support seeds, and scaling runs, widening the
/// support up to opt.maxSupportRadius cells while rows still miss their
/// target.  m, mNext: solid volumes per cell at t_k and t_{k+1}.  Sets the
/// stats of balancing (filled and unreached cells, residuals, mass change,
/// iterations, support radius).
CsrMatrix balanceShift(CsrMatrix T, const std::vector<double> &m, const std::vector<double> &mNext,
                       const std::vector<char> &fullNext, const EulerianBuildOptions &opt,
                       EulerianFrameStats *stats);

} // namespace rcfd
