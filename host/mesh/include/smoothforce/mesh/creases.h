// SPDX-License-Identifier: Apache-2.0
// Crease edges and corner vertices: where the patch surface keeps a sharp feature.
#pragma once

#include <array>
#include <functional>
#include <cstdint>
#include <string>
#include <vector>

#include <smoothforce/mesh/mesh.h>

namespace sf {

/// Which marks of the mesh make crease edges (under --normals file, the file's normals are used as
/// given, so split file normals are creases whatever these say: normals.h).
/// tags:     OBJ `t crease` / `t corner` and PLY edge crease properties, with sharpness > 0.
///           Semi-sharp tags (0 < sharpness < 10) are made fully sharp: no blend radius.
/// groups:   OBJ smoothing groups: an edge between faces of different groups is a crease, and
///           every edge of a face with smoothing off (`s off`, `s 0`) is one. A file whose faces
///           all have smoothing off (exporter boilerplate) carries no crease this way.
/// normals:  split file normals (a vertex whose corners carry file normals more than
///           kSameNormalAngle apart) under --normals auto: each smoothing sector keeps its file
///           normal. Off by default: flat-shaded exports split every vertex.
/// angleDeg: `--crease-angle`: an edge whose two faces' normals are more than this many degrees
///           apart is a crease; 0 is off. Range [0, 180).
struct CreaseOptions {
  bool tags = true;
  bool groups = true;
  bool normals = false;
  double angleDeg = 0;
};

/// Throws InputError unless 0 <= angleDeg < 180 (a finite number).
void checkCreaseOptions(const CreaseOptions& options);

/// The marks as `--creases` spells them: a comma-separated list of tags, groups, normals in that
/// order ("tags,groups" by default), or "none".
std::string creaseMarksText(const CreaseOptions& options);

/// Sets options.tags, groups and normals from a comma-separated list of those names (any order,
/// each at most once) or "none"; throws InputError naming the value otherwise.
void parseCreaseMarks(const std::string& text, CreaseOptions& options);

/// OpenSubdiv's infinitely sharp (Sdc::Crease::SHARPNESS_INFINITE).
inline constexpr double kInfiniteSharpness = 10;

/// The crease edges and corner vertices that the marks of a mesh make.
/// edges:     vertex pairs, lower id first, sorted, each once; sharpness: per edge (the largest
///            of its marks; kInfiniteSharpness for group and angle creases).
/// corners:   vertices tagged `t corner` with sharpness > 0, sorted.
/// fromTags, fromGroups, fromAngle: crease edges each source marked (an edge may count twice).
/// semiSharp: tagged edges with 0 < sharpness < 10, made fully sharp.
struct CreaseSet {
  std::vector<std::array<int32_t, 2>> edges;
  std::vector<double> sharpness;
  std::vector<int32_t> corners;
  int fromTags = 0, fromGroups = 0, fromAngle = 0, semiSharp = 0;
  bool groupsAllOff = false;  ///< the file's smoothing groups were all off, and so ignored
  bool empty() const { return edges.empty() && corners.empty(); }
};

/// The crease set of `mesh` under `options`. Throws InputError, naming the file and line, for a
/// tag whose vertices are out of range or whose edge no face of the mesh has.
CreaseSet findCreases(const PolygonMesh& mesh, const CreaseOptions& options);

/// Crease edges and vertices as a patch surface holds them (after normals and construction):
/// edges: vertex pairs of the edges whose two faces' corner normals differ at an end (lower id
/// first, sorted); and the vertices by the number of crease edges they touch: darts (1), crease
/// vertices (2) and corners (3 or more).
struct CreaseSummary {
  std::vector<std::array<int32_t, 2>> edges;
  std::vector<int32_t> darts, creaseVertices, corners;
  /// Report lines: counts and first ids (as `cache info` prints them); none without creases.
  std::vector<std::string> describe(int maxIds = 10) const;
};

/// The crease summary of a mesh from its corner normals (#C, as construction uses them): an edge
/// with one neighbour face is a crease where the two faces' normals at one of its ends differ
/// (exactly: construction shares a curve across it then).
CreaseSummary summarizeCreases(const PolygonMesh& mesh, const std::vector<int32_t>& slotTwin,
                               const double* cornerNormals);

}  // namespace sf

namespace sf {

/// Smoothing sectors: the corners of one vertex that share a normal. Two corners of vertex v in
/// faces that share an edge at v are joined when join(a, b, slot) says so (a, b: the corners,
/// slot: the shared edge's slot in a's face); sectors are the connected groups. Returns #C sector
/// ids, numbered in order of first corner; *count receives the number of sectors.
std::vector<int32_t> cornerSectors(const PolygonMesh& mesh, const std::vector<int32_t>& slotTwin,
                                   const std::function<bool(int32_t a, int32_t b, int32_t slot)>& join,
                                   int* count);

/// True when the edge (v0, v1) is in the crease set (binary search; any order of v0, v1).
bool isCrease(const CreaseSet& creases, int32_t v0, int32_t v1);

}  // namespace sf
