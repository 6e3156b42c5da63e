// The two baselines on the base polygons: the god-object of Zilles & Salisbury (1995)
// (`direct`) and force shading on the same proxy (`shading`, Morgenbesser & Srinivasan 1996).
#pragma once

#include <memory>

#include "embree_scene.h"
#include "force_method.h"

namespace sf {

/// A god-object (proxy) constrained to the facets of the base polygons (polygon_facets.h).
///
/// Contact starts when the segment from the previous HIP to the current one enters a facet
/// from its front side (PolygonScene::firstEntry: rtcIntersect1 on the polygon user geometry,
/// our exact double segment/facet test in the intersect callback); a HIP that is already inside
/// at its first step is not in contact (no crossing, as in the original method). In contact,
/// each step rebuilds the active constraints the Zilles-Salisbury way: from the old proxy the
/// segment towards the goal is tested for facets it enters; each one entered stops the proxy at
/// the crossing and becomes an active plane (at most three; a linearly dependent plane replaces
/// the oldest), and the goal becomes the point of the active planes' intersection nearest the
/// HIP (Lagrange multipliers, 1-3 planes). When no facet is entered the proxy reaches the goal;
/// a plane stays active only while the proxy lies on its facet (closed, inflated by the facet
/// tolerance): planes whose facet it slid off (past a convex edge) are dropped and the passes
/// go on from there within the same step, so that the proxy never rests in the air. With no
/// active plane the proxy is the HIP itself and contact ends. At most 12 passes per step; when
/// they run out the proxy stays at its last point on the surface (SF_TRACK_PROXY_LIMIT).
/// direct:  F = k (proxy - HIP).
/// shading: F = k |proxy - HIP| n, n interpolated from the corner normals at the proxy with
///          mean value coordinates on its polygon (mean_value.h).
/// ForceSample: scp = proxy, face / xi / eta its polygon and domain point (MVC), normal the
/// force direction, iterations = passes, transitions = 1 when the proxy changed polygon.
class GodObjectRenderer final : public ForceRenderer {
 public:
  /// method: Direct or Shading. Throws InputError for bad options or ForceMethod::Patch.
  GodObjectRenderer(std::shared_ptr<const PatchCache> cache, std::shared_ptr<const PolygonScene> scene,
                    ForceMethod method, const ForceOptions& options);
  ForceSample step(const Eigen::Vector3d& hip) noexcept override;
  void reset() noexcept override;
  /// The polygons need no patch: 0 on a skeleton, the cache's face count when prebuilt.
  int patchesBuilt() const noexcept override { return hasPatchData(*cache_) ? cache_->numFaces() : 0; }

 private:
  /// Point nearest `hip` on the intersection of the active planes; false when dependent.
  bool goal(const Eigen::Vector3d& hip, const int* act, int m, Eigen::Vector3d& g) const noexcept;

  std::shared_ptr<const PatchCache> cache_;
  std::shared_ptr<const PolygonScene> scene_;
  bool shading_;
  ForceOptions options_;
  std::vector<double> lambda_;
  bool inContact_ = false, havePrev_ = false;
  Eigen::Vector3d prevHip_{0, 0, 0}, proxy_{0, 0, 0};
  int face_ = -1;
};

}  // namespace sf
