// SPDX-License-Identifier: Apache-2.0
// One triangle's fault verdict from its corners and any winding number (surface_faults.h's
// measure, for callers that count crossings over their own scenes: normal_search.cpp).
#pragma once

#include <Eigen/Geometry>

#include <cmath>

#include <smoothforce/query/surface_faults.h>

namespace sf {

/// The verdict of triangle (a, b, c) (m) of a closed surface: its winding numbers probed at the
/// centroid, offset h (m) along the unit normal n on both sides, from windings(back, n, 2h,
/// &atBack, &atFront) (back = centroid - h n, front = back + 2h n: windingsAlongRay's contract);
/// twice its area (m^2) in *area2 (0, Degenerate, for a triangle without a normal).
template <class Windings>
SurfaceVerdict faultVerdict(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, double h,
                            Windings&& windings, double* area2) noexcept {
  const Eigen::Vector3d x = (b - a).cross(c - a);
  const double len = x.norm();
  *area2 = 0;
  if (!(len > 0) || !std::isfinite(len)) return SurfaceVerdict::Degenerate;
  *area2 = len;
  const Eigen::Vector3d n = x / len, mid = (a + b + c) / 3.0;
  int front = 0, back = 0;
  windings(Eigen::Vector3d(mid - h * n), n, 2 * h, &back, &front);
  return front == 0 && back == 1 ? SurfaceVerdict::Consistent
         : front > back          ? SurfaceVerdict::Folded
         : front < back          ? SurfaceVerdict::Overlapping
                                 : SurfaceVerdict::Thin;
}

}  // namespace sf
