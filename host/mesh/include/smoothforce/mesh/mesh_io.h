// SPDX-License-Identifier: Apache-2.0
// Mesh readers: OBJ, OFF, PLY (ASCII, binary little- and big-endian).
#pragma once

#include <string>

#include <smoothforce/mesh/mesh.h>

namespace sf {

/// Reads a polygon mesh, choosing the format by extension (.obj, .off, .ply; case-insensitive).
/// Faces and vertices are kept in file order, n-gons as they are; no face is dropped.
/// Text may end its lines in LF, CRLF or CR and start with a UTF-8 byte-order mark; an OBJ
/// line that ends in a backslash continues on the next line.
/// Throws InputError naming `path:line` (text formats) or `path: byte offset` (binary PLY)
/// for: unreadable file, unknown extension, UTF-16 or UTF-32 text (`path:` only),
/// malformed or non-finite numbers, wrong or huge counts (checked against the file size
/// before allocating; an OFF line of the other kind than its counts promise is named),
/// indices out of range, faces with fewer than 3 corners.
PolygonMesh readMesh(const std::string& path);

}  // namespace sf
