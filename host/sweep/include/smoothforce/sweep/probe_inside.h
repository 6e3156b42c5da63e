// The sweep's own inside test of a HIP (issue 10): the reference for the `missed` column, a
// computation independent of each force method's contact decision.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include <smoothforce/force/force_method.h>
#include <smoothforce/patch/patch_cache.h>

namespace sf {

class PatchSurface;
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

 private:
  bool closed_ = false;
  std::unique_ptr<const PatchSurface> surface_;
  std::unique_ptr<const PolygonScene> polygons_;
};

}  // namespace sf
