// The parts of a database file around its frames (docs/database-format.md):
// the root's format attributes, /mesh and /metadata (with the operating
// conditions of version 2), and the identity a checkpoint records.  Shared
// by the writer (database_writer.cpp) and the loader (database_loader.cpp);
// every reader throws h5::Error with a sentence naming the file.
#pragma once

#include "base/h5.hpp"
#include "rcfd/database.hpp"

#include <string>

namespace rcfd {

/// The root attribute format of every database file.
constexpr const char *kFormatName = "rcfd-database";

/// /mesh: the box attributes and the mesh's arrays.
void writeMesh(const h5::File &f, const Mesh &mesh);
/// The box mesh of /mesh, checked against its stored cell volumes.
Mesh readMesh(const h5::File &f);

/// The operating conditions that are known, as optional attributes of /metadata.
void writeConditions(const h5::File &f, const OperatingConditions &c);

/// The file's format version, one this rcfd reads.
long long checkFormat(const h5::File &f);

/// The identity a run's checkpoint records: the content hash, or for an older
/// file without one a hash of when and how it was made.
std::string readIdentity(const h5::File &f);

/// /metadata, checked (positive dt_rec and density, gravity, SI units).
DatabaseMetadata readMetadata(const h5::File &f);

} // namespace rcfd
