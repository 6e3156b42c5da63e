// SPDX-License-Identifier: Apache-2.0
// The sweep's own inside test of a HIP: the reference for the `missed` column, a
// computation independent of each force method's contact decision.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <array>
#include <memory>
#include <mutex>
#include <vector>

#include <smoothforce/force/force_method.h>
#include <smoothforce/patch/patch_cache.h>

namespace sf {

class PatchSurface;
class PointIndex;
class PolygonScene;

/// Whether HIPs lie inside the surface a force method renders.
/// - patch: the winding number of a uniform tessellation of the patches (PatchSurface) at about
///   twice the level the patch method's own query uses (at most 4 M triangles), so its error band
///   is about a quarter of the query's: a different tessellation from the one that decides
///   contact. Inside the band (the tessellation may sit on the other side of the HIP) the test
///   says UNDECIDED rather than guess.
/// - direct, shading: the polygons themselves (PolygonScene::contains: ray parity, majority of
///   three rays), exact up to rounding.
/// An open surface (a boundary edge) is UNDECIDED for every HIP: "inside" needs a closed surface.
/// The cache must outlive the test; classify() is thread-safe.
class ProbeInsideTest {
 public:
  /// Throws InputError for a skeleton cache with method Patch (no patches to tessellate).
  ProbeInsideTest(const PatchCache& cache, ForceMethod method);
  ~ProbeInsideTest();
  ProbeInsideTest(const ProbeInsideTest&) = delete;
  ProbeInsideTest& operator=(const ProbeInsideTest&) = delete;

  /// SF_PROBE_INSIDE, SF_PROBE_UNDECIDED or 0 (outside) for HIP `hip` (m).
  uint32_t classify(const Eigen::Vector3d& hip) const noexcept;
  /// classify() of every HIP, in parallel (oneTBB).
  std::vector<uint32_t> classify(const std::vector<Eigen::Vector3d>& hips) const;
  /// Level of the patch tessellation (0 for the polygon methods).
  int level() const noexcept;
  /// Distance (m) from q to the nearest surface fault of the patch surface (surface_faults.h: a
  /// folded, overlapping or thin triangle of its uniform tessellation at the finest level within
  /// 10^6 triangles, at most 64, at least level()); infinite where there is none: the polygon
  /// methods, an open surface, a surface without faults. The faults are measured on the first
  /// call (measureSurfaceFaults, in parallel: about a second for 10^6 triangles on 2 cores) and
  /// indexed (a k-d tree over their centroids), then reused; thread-safe.
  double surfaceFaultDistance(const Eigen::Vector3d& q) const;

 private:
  const PatchCache* cache_;
  bool closed_ = false;
  std::unique_ptr<const PatchSurface> surface_;
  mutable std::once_flag faultsOnce_;
  mutable std::vector<std::array<Eigen::Vector3d, 3>> faults_;  ///< the fault triangles' corners
  mutable std::unique_ptr<const PointIndex> faultCentroids_;     ///< over faults_' centroids
  mutable double faultRadius_ = 0;  ///< m, the largest centroid-to-corner distance of faults_
  std::unique_ptr<const PolygonScene> polygons_;
};

}  // namespace sf
