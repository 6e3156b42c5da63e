// SPDX-License-Identifier: Apache-2.0
// Private to the query module: setting up Embree devices and user-geometry scenes, one ray, and
// one point query around a point (the user geometries' point-query callbacks do the work and keep
// their state in `user`).
#pragma once

#include <embree3/rtcore.h>

#include <Eigen/Core>
#include <atomic>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

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

/// A ray from o (m, rounded to float) along d over [0, tfar] (in units of |d|), with no hit yet:
/// for rtcIntersect1.
inline RTCRayHit embreeRay(const Eigen::Vector3d& o, const Eigen::Vector3d& d, float tfar) noexcept {
  RTCRayHit rh;
  rh.ray.org_x = float(o.x());
  rh.ray.org_y = float(o.y());
  rh.ray.org_z = float(o.z());
  rh.ray.dir_x = float(d.x());
  rh.ray.dir_y = float(d.y());
  rh.ray.dir_z = float(d.z());
  rh.ray.tnear = 0;
  rh.ray.tfar = tfar;
  rh.ray.time = 0;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

/// A new Embree device whose errors go to onError(user, ...), and whose allocations and frees
/// (BVHs, geometry buffers) are added to *bytes when given (Embree's memory monitor: the bytes
/// the device holds now); throws std::runtime_error with Embree's error code when it cannot be made.
inline RTCDevice newEmbreeDevice(RTCErrorFunction onError, void* user, std::atomic<int64_t>* bytes = nullptr) {
  RTCDevice device = rtcNewDevice(nullptr);
  if (!device)
    throw std::runtime_error("rtcNewDevice failed: Embree error " + std::to_string(int(rtcGetDeviceError(nullptr))));
  rtcSetDeviceErrorFunction(device, onError, user);
  if (bytes)
    rtcSetDeviceMemoryMonitorFunction(
        device,
        [](void* counter, ssize_t delta, bool) {
          static_cast<std::atomic<int64_t>*>(counter)->fetch_add(delta, std::memory_order_relaxed);
          return true;  // never refuse an allocation
        },
        bytes);
  return device;
}

/// The bytes a device's memory monitor counted, 0 when it counted none (or a negative sum).
inline size_t embreeBytes(const std::atomic<int64_t>& bytes) noexcept {
  const int64_t b = bytes.load(std::memory_order_relaxed);
  return b > 0 ? static_cast<size_t>(b) : 0;
}

inline void embreeNoIntersect(const RTCIntersectFunctionNArguments*) {}
inline void embreeNoOccluded(const RTCOccludedFunctionNArguments*) {}

/// A committed user geometry of `count` primitives with these callbacks and `user` as its data
/// (intersect and occluded: none when null, for point queries only).
inline RTCGeometry userGeometry(RTCDevice device, size_t count, void* user, RTCBoundsFunction bounds,
                                RTCPointQueryFunction query, RTCIntersectFunctionN intersect = nullptr,
                                RTCOccludedFunctionN occluded = nullptr) {
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
  rtcSetGeometryUserPrimitiveCount(g, static_cast<unsigned>(count));
  rtcSetGeometryUserData(g, user);
  rtcSetGeometryBoundsFunction(g, bounds, nullptr);
  rtcSetGeometryIntersectFunction(g, intersect ? intersect : embreeNoIntersect);
  rtcSetGeometryOccludedFunction(g, occluded ? occluded : embreeNoOccluded);
  rtcSetGeometryPointQueryFunction(g, query);
  rtcCommitGeometry(g);
  return g;
}

/// A committed scene holding g (taking it over; none when null); robust: RTC_SCENE_FLAG_ROBUST.
inline RTCScene sceneOf(RTCDevice device, RTCGeometry g, bool robust,
                        RTCBuildQuality quality = RTC_BUILD_QUALITY_MEDIUM) {
  RTCScene s = rtcNewScene(device);
  if (robust) rtcSetSceneFlags(s, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(s, quality);
  if (g) {
    rtcAttachGeometry(s, g);
    rtcReleaseGeometry(g);
  }
  rtcCommitScene(s);
  return s;
}

}  // namespace sf
