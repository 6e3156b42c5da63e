// SPDX-License-Identifier: Apache-2.0
// The two baselines on the base polygons: the god-object of Zilles & Salisbury (1995)
// (`direct`) and force shading on the same proxy (`shading`, Morgenbesser & Srinivasan 1996).
#pragma once

#include <memory>

#include <smoothforce/force/force_method.h>
#include <smoothforce/query/embree_scene.h>

namespace sf {

/// A god-object (proxy) constrained to the facets of the base polygons (polygon_facets.h),
/// built watertight: with kWatertightPlanarTolerance every face that is not flat to rounding
/// is a fan of triangles on its real vertices, so adjacent facets meet on the real edges (a
/// scene built with a larger planarTolerance is replaced by such a scene of the same cache).
///
/// Contact starts when the segment from the previous HIP to the current one enters a facet
/// from its front side (PolygonScene::firstEntry: rtcIntersect1 on the polygon user geometry,
/// our exact double segment/facet test in the intersect callback), or, at the first HIP after
/// reset(), when that HIP is already inside the closed polygons (PolygonScene::contains): the
/// proxy then starts on the nearest polygon point (SF_TRACK_INSIDE). In contact, each step
/// rebuilds the active constraints the Zilles-Salisbury way: from the old proxy the segment
/// towards the goal is tested for facets it enters; each one entered stops the proxy at the
/// crossing and becomes an active plane (at most three; a linearly dependent plane replaces the
/// oldest), and the goal becomes the point of the active planes' intersection nearest the HIP.
/// While sliding on active planes, a facet only touched at the proxy's start (a shared vertex
/// or edge) is entered only when the segment goes on through it (segmentEntersFacet's
/// `through` test). When no facet is entered the proxy reaches the goal; a plane stays active
/// only while the proxy lies on its facet (closed, inflated by the facet tolerance) and while
/// it pushes (Lagrange multiplier >= 0; in a valley the HIP may pull the proxy off one of the
/// two planes): planes whose facet it slid off (past a convex edge) or that pull are dropped
/// and the passes go on from there within the same step. With no active plane the proxy is
/// the HIP itself and contact ends, unless the HIP is still inside the closed polygons: then
/// the proxy is put back on the nearest polygon point (SF_TRACK_INSIDE). At most 12 passes per
/// step; when they run out the proxy stays at its last point on the surface
/// (SF_TRACK_PROXY_LIMIT).
/// direct:  F = k (proxy - HIP).
/// shading: F = k |proxy - HIP| n, n interpolated from the corner normals at the proxy with
///          mean value coordinates on its polygon (mean_value.h).
/// A mesh farther from the world origin than its size (localOrigin, coordinate_range.h) is
/// rendered about its box centre: the facets, the proxy and the HIP are held relative to it,
/// so that the facets' plane tests keep the precision of the mesh's size, not of its
/// coordinates (at 1e7 m a proxy rounded in world coordinates left its plane by 1e-9 m and
/// fell through the facet); SCP and force are returned in world coordinates.
/// ForceSample: scp = proxy, face / xi / eta its polygon and domain point (MVC), normal the
/// force direction, iterations = passes, transitions = 1 when the proxy changed polygon.
/// The watertight polygon scene (kWatertightPlanarTolerance) a GodObjectRenderer of `cache`
/// renders on, for the renderers of one cache to share (SharedGeometry): for a mesh far from
/// the world origin, built on its polygons moved into the renderer's local frame (which it
/// holds), else on `cache` itself (which must outlive it). Throws as PolygonScene does.
std::shared_ptr<const PolygonScene> godObjectScene(const PatchCache& cache);

class GodObjectRenderer final : public ForceRenderer {
 public:
  /// method: Direct or Shading. Throws InputError for bad options or ForceMethod::Patch.
  /// scene: of `cache`, or godObjectScene(*cache) (for a mesh far from the origin, of its
  /// polygons in the local frame: renderers of one cache share it). When it was built with a
  /// planarTolerance above kWatertightPlanarTolerance, or the mesh lies far from the origin and
  /// the scene is not of its polygons in the local frame (checked vertex by vertex), the
  /// renderer builds its own watertight scene (in the local frame).
  GodObjectRenderer(std::shared_ptr<const PatchCache> cache, std::shared_ptr<const PolygonScene> scene,
                    ForceMethod method, const ForceOptions& options);
  ForceSample step(const Eigen::Vector3d& hip) noexcept override;
  void reset() noexcept override;
  /// The polygons need no patch: 0 on a skeleton, the cache's face count when prebuilt.
  int patchesBuilt() const noexcept override { return hasPatchData(*cache_) ? cache_->numFaces() : 0; }
  const void* patchStore() const noexcept override { return hasPatchData(*cache_) ? cache_.get() : nullptr; }

 private:
  /// When `hip` is inside the closed polygons: point = the nearest polygon point, true. Inside:
  /// behind the nearest facet's plane when the nearest point lies inside that facet, else by
  /// PolygonScene::contains (first ray along the nearest facet's normal).
  bool nearestIfInside(const Eigen::Vector3d& hip, Eigen::Vector3d& point) const noexcept;
  /// Index in act[0..m) (m 2 or 3, x on their intersection nearest the HIP) of the plane
  /// with the most negative Lagrange multiplier (the HIP pulls the proxy to its front side),
  /// or -1 when every plane pushes.
  int releasable(const Eigen::Vector3d& hip, const Eigen::Vector3d& x, const int* act, int m) const noexcept;
  /// step() in the local frame: hip and the result's scp relative to origin_.
  ForceSample localStep(const Eigen::Vector3d& hip) noexcept;
  /// Point nearest `hip` on the intersection of the active planes; false when dependent.
  bool goal(const Eigen::Vector3d& hip, const int* act, int m, Eigen::Vector3d& g) const noexcept;

  std::shared_ptr<const PatchCache> cache_;
  std::shared_ptr<const PolygonScene> scene_;  ///< of frameCache_ when the mesh is far from the origin
  std::shared_ptr<const PatchCache> frameCache_;  ///< the polygons moved by -origin_, or null
  Eigen::Vector3d origin_{0, 0, 0};               ///< m: the local frame (localOrigin of the polygons' box)
  bool shading_;
  ForceOptions options_;
  std::vector<double> lambda_;
  bool inContact_ = false, havePrev_ = false;
  Eigen::Vector3d prevHip_{0, 0, 0}, proxy_{0, 0, 0};
  int face_ = -1;
};

}  // namespace sf
