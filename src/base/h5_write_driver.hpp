// The HDF5 file driver rcfd writes files with.  It writes like HDF5's own
// POSIX (sec2) driver, but a write that fails is not reported to HDF5: the
// driver remembers the system's error, skips the writes after it, and
// h5::File reports it with the file's name.  HDF5 1.10 cannot recover from a
// failed write while it closes a file (the close fails, the handle stays
// registered and the library crashes at MPI_Finalize), so a full disk must
// never reach it.
#pragma once

#include <hdf5.h>

namespace rcfd::h5 {

/// A file access property list (to be closed with H5Pclose) for the driver;
/// the first write error (an errno) of a file opened with it is stored in
/// *firstError, which must outlive the file.
hid_t checkedWriteAccess(int *firstError);

} // namespace rcfd::h5
