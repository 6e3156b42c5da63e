// SPDX-License-Identifier: Apache-2.0
#include "winding_rays.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "embree_point_query.h"

namespace sf {
namespace {

struct WindingContext {
  RTCIntersectContext base;  ///< first, so that Embree's context pointer is ours
  const UniformTessellation* u;
  const int64_t* ids;  ///< scene primitive -> u->tri index (null: the identity)
  Eigen::Vector3d dir;
  int nearWinding;  ///< the signed crossings nearer than `split` along the ray (all of them with an infinite split)
  int farWinding;   ///< ... and the others
  float split;
  bool clean;      ///< every crossing so far transversal and inside its triangle, away from its edges
  float minDepth;  ///< ... and at least this far along the ray (its float origin's rounding, many times)
};

/// A crossing counts as clean when its barycentric coordinates are all at least this (Embree
/// computes them in float: far above their rounding) ...
constexpr float kWindingEdgeMargin = 1e-4f;
/// ... and the ray meets the triangle's plane at a sine of at least this, at a distance of at least
/// this times the origin's largest coordinate (about 80 float roundings of it) from the ray's start
/// and from its split.
constexpr double kWindingMinSine = 1e-3;
constexpr float kWindingMinDepth = 1e-5f;

void windingFilter(const RTCFilterFunctionNArguments* args) {
  if (args->N != 1 || !args->valid[0]) return;
  auto* wc = reinterpret_cast<WindingContext*>(const_cast<RTCIntersectContext*>(args->context));
  const unsigned prim = RTCHitN_primID(args->hit, args->N, 0);
  const auto& tr = wc->u->tri[wc->ids ? wc->ids[prim] : prim];
  const Eigen::Vector3d& a = wc->u->vertex[tr[0]];
  const Eigen::Vector3d n = (wc->u->vertex[tr[1]] - a).cross(wc->u->vertex[tr[2]] - a);
  const double s = n.dot(wc->dir);
  const float t = RTCRayN_tfar(args->ray, args->N, 0);
  (t < wc->split ? wc->nearWinding : wc->farWinding) += s > 0 ? 1 : (s < 0 ? -1 : 0);
  const float bu = RTCHitN_u(args->hit, args->N, 0), bv = RTCHitN_v(args->hit, args->N, 0);
  if (!(std::min({bu, bv, 1.0f - bu - bv}) >= kWindingEdgeMargin && std::abs(s) >= kWindingMinSine * n.norm() &&
        t >= wc->minDepth && !(std::abs(t - wc->split) < wc->minDepth)))
    wc->clean = false;
  args->valid[0] = 0;  // reject: keep traversing for the further crossings
}

}  // namespace

const Eigen::Vector3d WindingRays::kDirections[3] = {Eigen::Vector3d(0.5406, 0.6209, 0.5676).normalized(),
                                                     Eigen::Vector3d(-0.7071, 0.1961, -0.6793).normalized(),
                                                     Eigen::Vector3d(0.2673, -0.8018, 0.5345).normalized()};

WindingRays::WindingRays(RTCDevice device, const UniformTessellation& u, const std::vector<int64_t>* triangles,
                         const Eigen::Vector3d& origin)
    : u_(u), origin_(origin) {
  const size_t count = triangles ? triangles->size() : u.tri.size();
  RTCGeometry g = nullptr;
  if (count > 0) {
    // the scene's own vertices: those its triangles use (all of u's without a subset)
    std::vector<int32_t> local;
    std::vector<int32_t> used;
    if (triangles) {
      ids_ = *triangles;
      local.assign(u.vertex.size(), -1);
      for (const int64_t t : ids_)
        for (const int32_t v : u.tri[t])
          if (local[v] < 0) {
            local[v] = static_cast<int32_t>(used.size());
            used.push_back(v);
          }
    }
    const size_t nv = triangles ? used.size() : u.vertex.size();
    g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), nv));
    auto* ib = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), count));
    if (!vb || !ib) {
      rtcReleaseGeometry(g);
      throw std::runtime_error("winding rays: Embree could not allocate the buffers");
    }
    for (size_t i = 0; i < nv; ++i) {
      const Eigen::Vector3d& p = u.vertex[triangles ? used[i] : i];
      for (int a = 0; a < 3; ++a) vb[3 * i + a] = float(p[a] - origin[a]);
    }
    for (size_t i = 0; i < count; ++i) {
      const auto& tr = u.tri[triangles ? ids_[i] : i];
      for (int a = 0; a < 3; ++a) ib[3 * i + a] = unsigned(triangles ? local[tr[a]] : tr[a]);
    }
    rtcSetGeometryIntersectFilterFunction(g, windingFilter);
    rtcCommitGeometry(g);
  }
  scene_ = sceneOf(device, g, true);
}

WindingRays::~WindingRays() {
  if (scene_) rtcReleaseScene(scene_);
}

namespace {

/// Traces the ray from q (m, in the world) along unit dir through `scene` (in the frame of
/// `origin`), its crossings counted and split at `split` (m) as WindingContext says.
WindingContext traceWinding(RTCScene scene, const UniformTessellation& u, const std::vector<int64_t>& ids,
                            const Eigen::Vector3d& origin, const Eigen::Vector3d& q, const Eigen::Vector3d& dir,
                            float split) noexcept {
  WindingContext wc;
  rtcInitIntersectContext(&wc.base);
  wc.u = &u;
  wc.ids = ids.empty() ? nullptr : ids.data();
  wc.dir = dir;
  wc.nearWinding = wc.farWinding = 0;
  wc.split = split;
  wc.clean = true;
  const Eigen::Vector3d o = q - origin;  // the ray's origin in the scene's frame
  wc.minDepth = kWindingMinDepth * float(o.cwiseAbs().maxCoeff());
  RTCRayHit rh = embreeRay(o, dir, std::numeric_limits<float>::infinity());
  rtcIntersect1(scene, &wc.base, &rh);
  return wc;
}

}  // namespace

int WindingRays::crossings(const Eigen::Vector3d& q, int k, bool* clean) const noexcept {
  const WindingContext wc =
      traceWinding(scene_, u_, ids_, origin_, q, kDirections[k], std::numeric_limits<float>::infinity());
  if (!wc.clean) *clean = false;
  return wc.nearWinding;
}

void WindingRays::splitCrossings(const Eigen::Vector3d& q, const Eigen::Vector3d& dir, double length, int* nearSum,
                                 int* farSum, bool* clean) const noexcept {
  const WindingContext wc = traceWinding(scene_, u_, ids_, origin_, q, dir, float(length));
  if (!wc.clean) *clean = false;
  *nearSum += wc.nearWinding;
  *farSum += wc.farWinding;
}

}  // namespace sf
