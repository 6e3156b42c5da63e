// Vertex normals for patch construction.
#pragma once

#include <string>
#include <vector>

#include <smoothforce/mesh/mesh.h>

namespace sf {

/// How vertex normals are obtained.
/// Auto:  per-vertex normals from the file when it has exactly one per vertex, else Angle.
/// File:  the file's normals: per vertex, or per corner (OBJ `f v//vn`), kept per corner;
///        throws InputError when the file has none.
/// Angle: angle-weighted average of Newell face normals (Thürmer & Wüthrich 1998).
/// Area:  area-weighted (the Newell vector's length is twice the area).
enum class NormalMode { Auto, File, Angle, Area };

/// Parses "auto|file|angle|area"; throws InputError otherwise.
NormalMode parseNormalMode(const std::string& s);
const char* toString(NormalMode m);

/// Newell normal of face f (not normalised; length = 2 x area for planar faces).
Eigen::Vector3d newellNormal(const PolygonMesh& mesh, int f);

/// Unit normal per corner (#C by 3, same order as mesh.faceVertices). For every mode but
/// File with per-corner normals, all corners of one vertex carry the same normal.
/// A vertex whose normal cannot be formed (all incident faces degenerate, or the weighted
/// sum cancels) gets the normal of its first non-degenerate incident face, and is listed in
/// `fallbackVertices` if given. Throws InputError for non-finite or zero file normals,
/// naming the vertex or corner.
std::vector<Eigen::Vector3d> cornerNormals(const PolygonMesh& mesh, NormalMode mode,
                                           std::vector<int>* fallbackVertices = nullptr);

}  // namespace sf
