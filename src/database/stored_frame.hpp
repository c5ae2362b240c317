// A frame exactly as a database file stores it (natural order, weights as
// written, identity rows included): for tools that transform whole frames
// (rcfd coarsen, quantisation) and must not see the loader's rescaling.
#pragma once

#include "base/h5.hpp"
#include "rcfd/frames.hpp"

namespace rcfd {

/// Frame k of an open database file with `cells` cells; throws h5::Error.
FrameRecord readStoredFrame(const h5::File &f, int k, int cells);

} // namespace rcfd
