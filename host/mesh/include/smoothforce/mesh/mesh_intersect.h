// SPDX-License-Identifier: Apache-2.0
// Polygons that intersect other polygons of the mesh, and polygons whose own outline crosses
// itself: what the input itself allows a surface through its vertices to be.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include <smoothforce/mesh/mesh.h>

namespace sf {

/// Two faces that intersect and share no vertex. a < b (0-based face ids, file order); the
/// areas are those of the two faces' triangulations (polygonTriangles), m^2.
struct IntersectingPair {
  int a = 0, b = 0;
  double areaA = 0, areaB = 0;
  bool operator==(const IntersectingPair&) const = default;
};

/// The faces' surfaces as triangles on the polygons' own corners (plus a centroid per fanned
/// face). points: #V vertex positions then one centroid per fanned face; tri: indices into
/// points, counter-clockwise as the face; triFace: the face of each triangle; faceArea: #F, m^2
/// (sum of the face's triangle areas). Zero-area triangles (exactly collinear corners) are
/// left out: they lie on the outline of their face or are a degenerate face (checkMesh reports
/// those).
struct MeshTriangles {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int32_t, 3>> tri;
  std::vector<int32_t> triFace;
  std::vector<double> faceArea;
};

/// Triangulates every face: a triangle as it is; an n-gon (n >= 4) as the fan of n triangles
/// (centroid, V_k, V_k+1) that the query module uses for non-planar faces (polygon_facets.h)
/// when every fan triangle projected on the face's Newell plane turns the face's way (the
/// polygon is star-shaped about its centroid); otherwise (a non-convex outline such as an L) by
/// ear clipping of that projection, which keeps the triangles inside the outline; an outline
/// that ear clipping cannot finish (it crosses itself) or one of more than 256 corners falls
/// back to the fan. Faces of fewer than 3 corners get no triangle. Never throws.
MeshTriangles polygonTriangles(const PolygonMesh& mesh);

/// Closed triangles p and q (corners in order; each of non-zero area) share at least one point.
/// Exact for finite coordinates whose products neither overflow nor underflow (magnitudes
/// between about 1e-100 and 1e100, or 0): Guigue and Devillers' test on exact orient3d, a
/// coplanar pair by exact orient2d in the coordinate plane where both project without
/// degenerating. Touching counts as intersecting. Beyond that range a predicate that overflows
/// reads as 0 (on the plane); the answer may then be wrong, but the call always returns.
bool trianglesIntersect(const Eigen::Vector3d p[3], const Eigen::Vector3d q[3]) noexcept;

/// For each vertex, the smallest vertex id at bitwise the same position: faces meeting at
/// vertices that were not welded (a seam written twice) count as adjacent too. #V.
std::vector<int32_t> weldedVertexIds(const PolygonMesh& mesh);

/// Faces a and b share a vertex (by weldedVertexIds' ids `welded`).
bool facesShareVertex(const PolygonMesh& mesh, const std::vector<int32_t>& welded, int a, int b);

/// Every pair of faces that share no vertex (weldedVertexIds) and whose triangles
/// (polygonTriangles) intersect (trianglesIntersect: exact, touching included), sorted by
/// (a, b). Broad phase: a bounding-box hierarchy over the triangles (boxes exact, compared
/// closed), so no pair is missed. Faces that share a vertex are not tested: an intersection
/// between neighbours is not reported.
std::vector<IntersectingPair> findIntersectingFaces(const PolygonMesh& mesh);
/// The same from a triangulation already made (mesh must be the one it was made of).
std::vector<IntersectingPair> findIntersectingFaces(const PolygonMesh& mesh, const MeshTriangles& triangles);

/// Faces whose outline, projected on the face's Newell plane (about its centroid), is not a
/// simple polygon: two edges that are not neighbours share a point, or two neighbouring edges
/// fold back onto each other (collinear, overlapping). Exact on the projected coordinates
/// (orient2d). Faces that checkMesh calls degenerate (repeated vertex, zero-length edge, zero
/// area) are not examined, nor faces of more than kMaxSelfCrossingCorners corners (counted in
/// *unchecked when given). Sorted face ids.
inline constexpr int kMaxSelfCrossingCorners = 1024;
std::vector<int> findSelfCrossingFaces(const PolygonMesh& mesh, int* unchecked = nullptr);

/// Faces within reach of intersecting polygons: #F, 1 for every face of a pair and every face
/// sharing a vertex (weldedVertexIds) with one, else 0. A fault of a surface through the
/// vertices there may be the input's own.
std::vector<char> facesNearIntersections(const PolygonMesh& mesh, const std::vector<IntersectingPair>& pairs);

}  // namespace sf
