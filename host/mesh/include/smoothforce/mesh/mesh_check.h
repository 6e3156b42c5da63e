// SPDX-License-Identifier: Apache-2.0
// Topology and sanity report for a polygon mesh (non-manifold edges, duplicates, ...), and
// what its polygons themselves allow: intersections between them, outlines crossing themselves.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <smoothforce/mesh/mesh.h>
#include <smoothforce/mesh/mesh_intersect.h>

namespace sf {

/// What checkMesh found. Every list holds element ids (0-based, file order).
struct MeshReport {
  int numVertices = 0, numFaces = 0, numEdges = 0;
  std::vector<int> faceSizeHistogram;                ///< [n] = faces with n corners
  std::vector<std::array<int, 2>> nonManifoldEdges;  ///< vertex pairs used by > 2 faces
  std::vector<int> nonManifoldVertices;              ///< vertices with more than one face fan
  std::vector<int> duplicateFaces;                   ///< faces repeating an earlier face's vertex set
  std::vector<int> degenerateFaces;                  ///< repeated vertex, zero-length edge or zero area
  std::vector<int> unreferencedVertices;
  std::vector<std::vector<int>> boundaryLoops;        ///< each a vertex loop
  std::vector<std::array<int, 2>> inconsistentEdges;  ///< interior edges used twice in one direction
  int numComponents = 0;
  double signedVolume = 0;  ///< meaningful for closed meshes (no boundary edges)

  // What the input allows (MeshCheckOptions::intersections; mesh_intersect.h). Reported, never
  // refused: a surface through these polygons' vertices cannot be free of faults there.
  bool intersectionsChecked = false;                ///< false: the three fields below were not computed
  std::vector<IntersectingPair> intersectingPairs;  ///< faces that intersect and share no vertex, (a, b) sorted
  std::vector<int> selfCrossingFaces;               ///< faces whose outline on their Newell plane crosses itself
  int selfCrossingUnchecked = 0;  ///< faces of more than kMaxSelfCrossingCorners corners, not examined
  double surfaceArea = 0;         ///< m^2: all faces' triangulations (polygonTriangles)

  bool closed() const { return boundaryLoops.empty(); }
  /// No topology problem list non-empty (intersections and self-crossing outlines are not
  /// counted: they describe the geometry, and the mesh is usable with them).
  bool clean() const;
  /// The distinct faces of intersectingPairs, sorted.
  std::vector<int> intersectingFaces() const;
  /// m^2: the sum of the areas of intersectingFaces().
  double intersectingArea() const;
  /// Human-readable lines: counts plus the first few ids of each problem (describeInput's last).
  std::vector<std::string> describe(int maxIds = 10) const;
  /// The lines on intersecting and self-crossing polygons alone (none when there are none):
  /// "intersecting polygons: 3 pairs (first: 10-57, ...) on 6 faces, 0.0012 m^2 (0.51% of the
  /// area)" and "self-crossing polygons: 2 (first: 60, 150)".
  std::vector<std::string> describeInput(int maxIds = 10) const;
};

struct MeshCheckOptions {
  /// Also look for intersecting and self-crossing polygons (mesh_intersect.h; about 0.1 s for
  /// 70,000 triangles). Off: only topology and degeneracy.
  bool intersections = true;
};

/// Computes the report. Never throws on bad topology or geometry; that is what it reports.
/// Throws InputError only for a vertex index outside the vertex array.
MeshReport checkMesh(const PolygonMesh& mesh, const MeshCheckOptions& options = {});

/// Face f has fewer than 3 corners, a repeated vertex, a zero-length edge or zero area
/// (relative to its perimeter): what checkMesh lists as degenerate.
bool isDegenerateFace(const PolygonMesh& mesh, int f);

/// Reverses every face's corner order (and corner normals) in place, keeping each face's first
/// corner first.
void flipFaces(PolygonMesh& mesh);

/// What orientCoherently turned.
struct OrientationRepair {
  std::vector<int> turnedFaces;        ///< faces whose corner order was reversed, ascending
  std::vector<int> unorientableFaces;  ///< the lowest face of each component left as read (no orientation agrees)
  /// Lines for `cache build` (empty when nothing was turned or left).
  std::vector<std::string> describe(int maxIds = 10) const;
};

/// Turns the faces that run against their neighbours: in every connected component (faces
/// joined across edges that exactly two faces use), the faces are given one orientation, so
/// that each such edge is used once in each direction, and the orientation of most of the
/// component's faces is kept (on a tie, that of its lowest face id); the faces that disagree
/// have their corner order reversed (and their corner normals with it), keeping their first
/// corner. A component on which no orientation agrees across every edge (a Moebius strip) is
/// left as read and named. Face and vertex ids and positions do not change. Whether a closed
/// mesh then faces inward is applyOrientation's decision, made on the whole mesh (a hollow
/// part's inner shell faces in). #C log #C time.
OrientationRepair orientCoherently(PolygonMesh& mesh);

/// Orientation policy (after orientCoherently, under Outward): `Outward` flips a closed mesh whose signed volume is
/// negative (faces pointing inward, e.g. polygon_laplacian/sphere2.off), when at most 10% of its edges are
/// inconsistently oriented (then the majority's faces point outward after the flip; the
/// report keeps the inconsistent edges); `Keep` leaves it. Returns true when the mesh was flipped.
enum class OrientPolicy { Outward, Keep };
bool applyOrientation(PolygonMesh& mesh, const MeshReport& report, OrientPolicy policy);

}  // namespace sf
