// SPDX-License-Identifier: Apache-2.0
// Global queries on the base polygons with Embree 3 (paper 4.1, step 1): nearest point and
// first segment crossing. One user-geometry primitive per polygon; the distances and the
// crossings are computed in double by our own exact callbacks (polygon_facets.h), Embree
// only supplies the BVH culling. All Embree calls live in embree_scene.cpp.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include <smoothforce/query/polygon_facets.h>

namespace sf {

/// Result of PolygonScene::nearest. face -1 when the scene has no polygon.
struct NearestPolygonPoint {
  int face = -1;
  int facet = -1;                                             ///< PolygonFacets facet holding the point
  Eigen::Vector3d point{0, 0, 0};                             ///< m, on the polygon
  double distance = std::numeric_limits<double>::infinity();  ///< m
};

/// Result of PolygonScene::firstEntry. face -1 when nothing is crossed.
struct PolygonCrossing {
  int face = -1, facet = -1;
  double t = 1;                    ///< segment parameter in [0, 1]
  Eigen::Vector3d point{0, 0, 0};  ///< a + t (b - a)
  bool entering = true;            ///< crossed from the facet's front (false: from its back, an exit)
};

/// The BVH over the cache's polygons, built eagerly in the constructor (and warmed up with one
/// query). Queries are const and thread-safe (per-call context on the stack); they do not
/// allocate, lock or throw. The cache must outlive the scene.
class PolygonScene {
 public:
  /// Throws std::runtime_error with Embree's error code and message when Embree fails.
  explicit PolygonScene(const PatchCache& cache, double planarTolerance = kPlanarTolerance);
  ~PolygonScene();
  PolygonScene(const PolygonScene&) = delete;
  PolygonScene& operator=(const PolygonScene&) = delete;

  /// Exact nearest point of the polygons to p (ties: the lower facet found first).
  NearestPolygonPoint nearest(const Eigen::Vector3d& p) const noexcept;
  /// First facet that segment a -> b enters from its front side (segmentEntersFacet, with its
  /// `through` test when through is true), with the smallest t; facets listed in
  /// exclude[0..nExclude) are skipped.
  PolygonCrossing firstEntry(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const int* exclude = nullptr,
                             int nExclude = 0, bool through = false) const noexcept;
  /// First facet that segment a -> b crosses from either side (smallest t; at equal t an
  /// entry before an exit, then the lower facet); `entering` tells the side.
  PolygonCrossing firstCrossing(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const noexcept;
  /// Whether p (m) is inside the closed polygon mesh: the first facet crossed by each of three
  /// rays from p (along `dir` and two fixed skew directions, each 2 bounding-box diagonals
  /// long) is crossed from its back, for at least two of them. Ray-parity style test that
  /// only needs the nearest crossing; false on a ray that leaves through a hole of an open
  /// mesh. dir need not be unit; a zero dir uses only the fixed directions' majority.
  bool contains(const Eigen::Vector3d& p, const Eigen::Vector3d& dir) const noexcept;

  const PolygonFacets& facets() const noexcept { return facets_; }
  /// The planarTolerance the facets were built with (buildPolygonFacets).
  double planarTolerance() const noexcept { return planarTolerance_; }
  const PatchCache& cache() const noexcept { return cache_; }
  /// Whether the corners of vertex v carry more than one normal (creaseVertexFlags): a crease
  /// touches it, and its faces meet as separate sheets there.
  bool creaseVertex(int v) const noexcept { return creaseVertex_[v] != 0; }
  /// Whether the mesh has a crease vertex at all.
  bool hasCreases() const noexcept { return hasCreases_; }
  /// Bytes the scene holds: its facets, its tables and its BVH (Embree's own count of what its
  /// device allocated); the cache not counted.
  size_t bytes() const noexcept;

  struct Impl;  ///< Embree device and scene (opaque; embree_scene.cpp)

 private:
  const PatchCache& cache_;
  double planarTolerance_;
  PolygonFacets facets_;
  std::vector<uint8_t> creaseVertex_;  ///< #V: creaseVertexFlags
  bool hasCreases_ = false;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sf
