// SPDX-License-Identifier: Apache-2.0
// Vertex normals for patch construction.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include <smoothforce/mesh/creases.h>
#include <smoothforce/mesh/mesh.h>

namespace sf {

/// Angle between two vectors (any length, not zero), radians in [0, pi]; the atan2 form, accurate
/// near 0 and pi where acos of the dot product is not.
double angleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b);

/// How vertex normals are obtained.
/// Auto:  the file's normals wherever the file gives one normal per vertex: per vertex in
///        vertex order (OBJ with as many `vn` as `v` and faces without normal indices, OFF
///        NOFF, PLY nx ny nz), or through face references (OBJ `f v//vn`, `f v/vt/vn`) where
///        every corner of the vertex references the same normal (normalised, within
///        kSameNormalAngle of the vertex's first corner in face order; that corner's normal is
///        used). At a vertex whose corners carry different file normals (a crease, or flat
///        shading) the angle-weighted normal (Angle) is used instead; with CreaseOptions::normals,
///        each smoothing sector (corners joined across edges where the normals agree) keeps its
///        first corner's file normal instead, and the edges between sectors are creases. The
///        vertex is listed in NormalReport::splitVertices. Without file normals: Angle everywhere.
/// File:  the file's normals: per vertex, or per corner (OBJ `f v//vn`), kept per corner as
///        given (marked creases are not applied); throws InputError when the file has none.
/// In every mode but File, at the vertices that marked creases touch (creases.h: tags,
/// smoothing groups, --crease-angle), each smoothing sector takes the Angle (Area in Area mode)
/// normal of its own faces: the faces on either side of a crease keep their own tangent plane.
/// Angle: angle-weighted average of Newell face normals (Thürmer & Wüthrich 1998).
/// Area:  area-weighted (the Newell vector's length is twice the area).
enum class NormalMode { Auto, File, Angle, Area };

/// Two file normals of one vertex's corners at most this far apart (radians, after normalising)
/// count as one normal under Auto. Exporters write one `vn` line per corner, rounded to 4-6
/// decimals: two roundings of nearly one direction differ by up to about 2e-4 rad, while an
/// intended crease is degrees.
inline constexpr double kSameNormalAngle = 1e-3;

/// Where the normals of cornerNormals() came from.
enum class NormalSource {
  FileVertexOrder,  ///< the file's, one per vertex in vertex order
  FileFaceRefs,     ///< the file's, one per vertex through face references (Auto)
  FileCorners,      ///< the file's per corner, as given (File)
  FileAndAngle,     ///< Auto: the file's, angle-weighted at the split vertices
  FileSectors,      ///< Auto with CreaseOptions::normals: the file's, one per smoothing sector
  Angle,            ///< angle-weighted Newell normals
  Area,             ///< area-weighted Newell normals
  CageLimit         ///< Catmull-Clark limit normals of a subdivision cage (cage_limit.h)
};

/// What cornerNormals() did, for reports (`cache build` prints describe()).
struct NormalReport {
  NormalMode mode = NormalMode::Auto;         ///< the mode asked for
  NormalSource source = NormalSource::Angle;  ///< where the normals came from
  std::vector<int> splitVertices;             ///< vertices whose corners carry file normals more than
                                              ///< kSameNormalAngle apart (Auto and File, per-corner files)
  std::vector<int> fallbackVertices;          ///< vertices whose weighted normal needed a fallback
  CreaseSet creases;                          ///< the marked creases (findCreases)
  int fileVertices = 0;         ///< referenced vertices whose corners agree on one file normal (file sources)
  int creaseCorners = 0;        ///< corners whose normal differs from the first corner of their vertex
  bool fileHasNormals = false;  ///< the mesh carries per-vertex or per-corner file normals
  /// Human-readable lines: the source, then counts and first ids of split, crease and
  /// fallback vertices.
  std::vector<std::string> describe(int maxIds = 10) const;
};

/// Parses "auto|file|angle|area"; throws InputError otherwise.
NormalMode parseNormalMode(const std::string& s);
const char* toString(NormalMode m);

/// Newell normal of face f (not normalised; length = 2 x area for planar faces).
Eigen::Vector3d newellNormal(const PolygonMesh& mesh, int f);

/// Unit normal per corner (#C by 3, same order as mesh.faceVertices). Corners of one vertex
/// carry the same normal except across creases (split file normals, marked creases).
/// creaseOptions: which marks make creases (findCreases; its InputErrors propagate).
/// A vertex whose weighted normal cannot be formed (all incident faces degenerate, or the
/// weighted sum cancels) gets the normal of its first non-degenerate incident face, and is
/// listed in `report.fallbackVertices`. Throws InputError for non-finite or zero file normals
/// (naming the vertex or corner) and for file normal counts that do not match the mesh.
std::vector<Eigen::Vector3d> cornerNormals(const PolygonMesh& mesh, NormalMode mode, NormalReport& report,
                                           const CreaseOptions& creaseOptions = {});

/// As above, keeping only the fallback vertices of the report (if `fallbackVertices` is given).
std::vector<Eigen::Vector3d> cornerNormals(const PolygonMesh& mesh, NormalMode mode,
                                           std::vector<int>* fallbackVertices = nullptr);

}  // namespace sf
