// The one check every input file passes before it is opened: it must be a
// regular file.  Opening a FIFO for reading waits for a writer for ever,
// /dev/zero never ends and a directory reads as nothing; each is refused with
// one sentence naming it instead.
#pragma once

#include <string>

namespace rcfd {

/// The sentence that refuses `path` when it exists and is not a regular file
/// (after following symbolic links): a directory, a FIFO, a device, a socket.
/// "" when it is a regular file or does not exist (the opener says that).
std::string notRegularFile(const std::string &path);

/// Throws std::runtime_error with notRegularFile(path) when that is not "".
/// Called by every reader of an input file (base/h5, base/csv, the particle,
/// Eulerian, list and path readers, the options-file check) before it opens it.
void requireRegularFile(const std::string &path);

} // namespace rcfd
