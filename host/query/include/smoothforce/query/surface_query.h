// SPDX-License-Identifier: Apache-2.0
// The stateless contact query as a batch service: for N points, the signed distance to the
// patch surface, the nearest surface point with its normal, face and domain coordinates.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <memory>

#include <smoothforce/base/status.h>  // SF_TRACK_* bits of the answers
#include <smoothforce/query/patch_surface.h>
#include <smoothforce/query/refine_options.h>

namespace sf {

/// One point's answer. Where the point is not finite or beyond the coordinate range
/// (coordinate_range.h), or the surface has no patch point: signedDistance NaN, face -1, status
/// SF_TRACK_BAD_HIP or SF_TRACK_NO_POLYGON.
struct SurfaceQueryResult {
  /// m: the distance to the nearest patch point, negative inside the surface (Algorithm 1's
  /// inside test, insidePatchSurface: the winding number of the closed surface where it is
  /// reliable or the side is in doubt, else the side of the nearest point's tangent plane; an
  /// open surface: below a foot point's tangent plane, within reach)
  double signedDistance = 0;
  Eigen::Vector3d point{0, 0, 0};   ///< m, the nearest patch point (the global query's)
  Eigen::Vector3d normal{0, 0, 0};  ///< its unit outward patch normal
  int face = -1;                    ///< its face
  double xi = 0, eta = 0;           ///< its domain point (Eq. 3)
  /// SF_TRACK_* bits of its refinement (CONVERGED, BOUNDARY, FOLD_EDGE, ...) and SF_TRACK_INSIDE
  /// when inside; SF_ST_* bits of the patch point
  uint32_t status = 0;
};

/// The nearest-point and inside query of the patch method (out of contact, as at a contact
/// start: nearestOnPatches and insidePatchSurface, global_query.h) over many points, with no
/// state between points: the answer for a point does not depend on the others, their order or
/// the thread count. Exact to the refinement's tolerances (options; ForceOptions convert, their
/// stiffness and patch capacity unused): the nearest point is the global one within the candidate
/// search's error bounds (tests/query/test_surface_query.cpp against a dense oracle).
class SurfaceQuery {
 public:
  /// cache: prebuilt (hasPatchData); a skeleton throws InputError. Builds the PatchSurface
  /// (tessellation and BVH, patchSurfaceOptions(options)) unless `surface` (of this cache) is given.
  /// Throws InputError for bad options (validateRefineOptions).
  explicit SurfaceQuery(std::shared_ptr<const PatchCache> cache, const RefineOptions& options = {},
                        std::shared_ptr<const PatchSurface> surface = nullptr);
  ~SurfaceQuery();
  SurfaceQuery(const SurfaceQuery&) = delete;
  SurfaceQuery& operator=(const SurfaceQuery&) = delete;

  /// Answers points[0, 3 count) (x, y, z per point, m) into out[0, count), on oneTBB tasks
  /// (threads <= 0: oneTBB's default; 1: the calling thread). Thread-safe: several callers may
  /// query one SurfaceQuery at once. Throws std::invalid_argument for NULL arrays with count > 0.
  void query(const double* points, size_t count, SurfaceQueryResult* out, int threads = 0) const;
  /// One point on the calling thread (allocates a refiner: for many points use query()).
  SurfaceQueryResult query(const Eigen::Vector3d& point) const;

  const PatchSurface& surface() const noexcept { return *surface_; }
  const PatchCache& cache() const noexcept { return *cache_; }

 private:
  struct Impl;
  std::shared_ptr<const PatchCache> cache_;
  std::shared_ptr<const PatchSurface> surface_;
  RefineOptions options_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sf
