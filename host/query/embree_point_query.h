// Private to the query module: one Embree point query around a point (the user geometries'
// point-query callbacks do the work and keep their state in `user`).
#pragma once

#include <embree3/rtcore.h>

#include <Eigen/Core>
#include <limits>

namespace sf {

/// Runs rtcPointQuery on `scene` at p (m, rounded to float) within `radius` (m; infinite by
/// default: the callbacks shrink it themselves), passing `user` to the callbacks.
inline void embreePointQuery(RTCScene scene, const Eigen::Vector3d& p, void* user,
                             float radius = std::numeric_limits<float>::infinity()) noexcept {
  RTCPointQuery q;
  q.x = float(p.x());
  q.y = float(p.y());
  q.z = float(p.z());
  q.radius = radius;
  q.time = 0;
  RTCPointQueryContext ctx;
  rtcInitPointQueryContext(&ctx);
  rtcPointQuery(scene, &q, &ctx, nullptr, user);
}

}  // namespace sf
