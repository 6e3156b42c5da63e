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

}  // namespace sf
