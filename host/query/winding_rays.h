// SPDX-License-Identifier: Apache-2.0
// The winding number of a uniform tessellation by ray crossings (PatchSurface::winding), over
// any subset of its triangles: the crossings of disjoint subsets add up to the whole's, so a
// caller that changes a few faces traces the rest once and only the changed faces again.
#pragma once

#include <embree3/rtcore.h>
#include <Eigen/Core>

#include <cstdint>
#include <vector>

#include "surface_tessellation.h"

namespace sf {

/// An Embree scene (robust mode) over triangles of a uniform tessellation, in the frame of
/// `origin`, counting the signed crossings of rays from a point. The triangle test of Embree's
/// robust mode depends only on the ray and the triangle's float corners, so a triangle crosses a
/// ray here exactly where it does in any other such scene with the same origin.
class WindingRays {
 public:
  /// The three ray directions (unit, fixed, skew to the axes).
  static const Eigen::Vector3d kDirections[3];

  /// device: the Embree device (outlives this). u: the tessellation (outlives this, unchanged).
  /// triangles: indices into u.tri to trace (null: all). origin: the scene's frame, m.
  /// Throws std::runtime_error when Embree cannot allocate the buffers.
  WindingRays(RTCDevice device, const UniformTessellation& u, const std::vector<int64_t>* triangles,
              const Eigen::Vector3d& origin);
  ~WindingRays();
  WindingRays(const WindingRays&) = delete;
  WindingRays& operator=(const WindingRays&) = delete;

  /// Signed crossings of ray k (0..2, kDirections[k]) from q: +1 where it leaves through a
  /// triangle's front, -1 through its back. *clean false unless every crossing is transversal,
  /// inside its triangle away from its edges (barycentric coordinates >= 1e-4) and not at the
  /// ray's start; *clean is left as it was otherwise, so that one flag can gather several scenes.
  int crossings(const Eigen::Vector3d& q, int k, bool* clean) const noexcept;

  /// Signed crossings, as crossings(), of the ray from q along unit `dir`, split at `length` (m,
  /// > 0) along it: those nearer added to *nearSum, the others to *farSum. *clean as crossings(),
  /// and false too where a crossing lies within the origin's rounding of `length`.
  void splitCrossings(const Eigen::Vector3d& q, const Eigen::Vector3d& dir, double length, int* nearSum, int* farSum,
                      bool* clean) const noexcept;

 private:
  const UniformTessellation& u_;
  std::vector<int64_t> ids_;  ///< scene primitive -> u.tri index (empty: the identity)
  Eigen::Vector3d origin_;
  RTCScene scene_ = nullptr;
};

/// The winding number from the rays' crossings (crossings(k, &clean) as WindingRays::crossings,
/// summed over the scenes that make up the surface): the first ray decides where every crossing
/// it makes is clean (the watertight scene counts each once), otherwise the majority of the three
/// (a ray that grazes an edge or vertex can miscount); 1 inside a closed outward surface, 0
/// outside.
template <class Crossings>
int windingFromRays(Crossings&& crossings) noexcept {
  int w[3];
  for (int k = 0; k < 3; ++k) {
    bool clean = true;
    w[k] = crossings(k, &clean);
    if (k == 0 && clean) return w[0];
    if (k == 1 && w[0] == w[1]) return w[0];  // two rays agree: the third cannot change the majority
  }
  if (w[0] == w[2]) return w[0];
  if (w[1] == w[2]) return w[1];
  return w[0];
}

/// The winding numbers at `back` and at front = back + length * dir (m; unit dir, length > 0):
/// from one ray from back along dir where every crossing it makes is clean (split(back, dir,
/// length, &near, &far, &clean) as WindingRays::splitCrossings, summed over the scenes that make
/// up the surface):
/// front's is the crossings beyond length, back's all of them (the winding number changes by
/// each crossing between the two points). Otherwise each by windingFromRays (crossings(point, k,
/// &clean) as there). Returns whether the one ray decided.
template <class Split, class Crossings>
bool windingsAlongRay(const Eigen::Vector3d& back, const Eigen::Vector3d& dir, double length, Split&& split,
                      Crossings&& crossings, int* atBack, int* atFront) noexcept {
  int nearSum = 0, farSum = 0;
  bool clean = true;
  split(back, dir, length, &nearSum, &farSum, &clean);
  if (clean) {
    *atFront = farSum;
    *atBack = nearSum + farSum;
    return true;
  }
  const Eigen::Vector3d front = back + length * dir;
  *atBack = windingFromRays([&](int k, bool* c) { return crossings(back, k, c); });
  *atFront = windingFromRays([&](int k, bool* c) { return crossings(front, k, c); });
  return false;
}

}  // namespace sf
