// Mesh readers: OBJ, OFF, PLY (ASCII, binary little- and big-endian).
#pragma once

#include <string>

#include <smoothforce/mesh/mesh.h>

namespace sf {

/// Reads a polygon mesh, choosing the format by extension (.obj, .off, .ply; case-insensitive).
/// Faces and vertices are kept in file order, n-gons as they are; no face is dropped.
/// Throws InputError naming `path:line` (text formats) or `path: byte offset` (binary PLY)
/// for: unreadable file, unknown extension, malformed or non-finite numbers, wrong or huge
/// counts (checked against the file size before allocating), indices out of range, faces
/// with fewer than 3 corners.
PolygonMesh readMesh(const std::string& path);

}  // namespace sf
