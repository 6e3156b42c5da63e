// SPDX-License-Identifier: Apache-2.0
// The coordinate range of positions the library takes (mesh vertices, HIPs, trajectory points).
#pragma once

#include <cmath>

namespace sf {

/// The largest coordinate magnitude of a position, m: 10^15, far beyond any haptic scene in
/// metres or millimetres. Beyond it a point is not a position the queries can take: Embree's
/// float BVHs reject points beyond 1.8e18 m (Debian's libembree aborts on that assertion), and
/// squared distances in float overflow near 1.8e19 m. Mesh readers and CSV readers refuse coordinates
/// beyond it (file:line), renderers report such a HIP as SF_TRACK_BAD_HIP (no force, state
/// reset), and the queries find nothing there.
inline constexpr double kMaxCoordinate = 1e15;

/// Whether every coordinate of p (p[0], p[1], p[2]) is finite and within +-kMaxCoordinate.
template <class V>
bool inCoordinateRange(const V& p) noexcept {
  return std::fabs(p[0]) <= kMaxCoordinate && std::fabs(p[1]) <= kMaxCoordinate && std::fabs(p[2]) <= kMaxCoordinate;
}

/// The point to take a geometry's coordinates about where their rounding or cancellation would
/// lose its detail: the centre of its box [lo, hi] where that centre lies farther from (0,0,0)
/// than the box's diagonal (a mesh far from the origin: float coordinates at 1e7 m are 1 m
/// apart, and products of coordinates cancel), else (0,0,0), so that nothing changes for a
/// geometry about the origin; (0,0,0) too for an empty or non-finite box. V: an Eigen vector.
template <class V>
V localOrigin(const V& lo, const V& hi) {
  const V zero = V::Zero();
  if (!lo.allFinite() || !hi.allFinite() || !(lo.array() <= hi.array()).all()) return zero;
  const V c = 0.5 * (lo + hi);
  return c.norm() > (hi - lo).norm() ? c : zero;
}

/// Whether p lies farther from the box [lo, hi] than the box's diagonal (p, lo, hi indexable
/// [0..3), m): no contact holds there, for a penetration beyond the object's size has no
/// meaning (the renderers then leave any contact; a tracker held it from 1e14 m away).
template <class V>
bool farBeyondBox(const V& p, const V& lo, const V& hi) noexcept {
  double out2 = 0, diag2 = 0;
  for (int a = 0; a < 3; ++a) {
    const double d = p[a] < lo[a] ? lo[a] - p[a] : (p[a] > hi[a] ? p[a] - hi[a] : 0.0);
    out2 += d * d;
    diag2 += (hi[a] - lo[a]) * (hi[a] - lo[a]);
  }
  return out2 > diag2;
}

}  // namespace sf
