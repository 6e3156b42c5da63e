// Global queries on the base polygons with Embree 3 (paper 4.1, step 1): nearest point and
// first segment crossing. One user-geometry primitive per polygon; the distances and the
// crossings are computed in double by our own exact callbacks (polygon_facets.h), Embree
// only supplies the BVH culling. All Embree calls live in embree_scene.cpp.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <memory>

#include "polygon_facets.h"

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
  /// First facet that segment a -> b enters from its front side (segmentEntersFacet), with
  /// the smallest t; facets listed in exclude[0..nExclude) are skipped.
  PolygonCrossing firstEntry(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const int* exclude = nullptr,
                             int nExclude = 0) const noexcept;

  const PolygonFacets& facets() const noexcept { return facets_; }
  const PatchCache& cache() const noexcept { return cache_; }

  struct Impl;  ///< Embree device and scene (opaque; embree_scene.cpp)

 private:
  const PatchCache& cache_;
  PolygonFacets facets_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sf
