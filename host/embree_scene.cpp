// The only file that calls Embree. Embree works in float: the user primitives' bounds are
// padded so that BVH culling stays conservative for the double-precision queries, and the
// query radius / ray tfar are only ever shrunk to values above the exact double result.
#include "embree_scene.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace sf {

struct PolygonScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  const PolygonFacets* facets = nullptr;
  float pad = 0;          ///< m, added around every primitive box and to shrunk radii
  char error[256] = {0};  ///< first Embree error (no allocation in the callback)
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

void onError(void* user, RTCError code, const char* str) {
  auto* impl = static_cast<PolygonScene::Impl*>(user);
  if (impl->error[0] == 0) std::snprintf(impl->error, sizeof impl->error, "Embree error %d: %s", int(code), str);
}

void boundsFn(const RTCBoundsFunctionArguments* args) {
  const auto* impl = static_cast<const PolygonScene::Impl*>(args->geometryUserPtr);
  const PolygonFacets& pf = *impl->facets;
  const int f = static_cast<int>(args->primID);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (int i = pf.faceFacetOffsets[f]; i < pf.faceFacetOffsets[f + 1]; ++i)
    for (int v = pf.facetVertOffsets[i]; v < pf.facetVertOffsets[i + 1]; ++v) {
      lo = lo.cwiseMin(pf.facetVert3d[v]);
      hi = hi.cwiseMax(pf.facetVert3d[v]);
    }
  // a projected one-facet face lies within (2 * planarity * diameter) of its vertices' box
  const double grow = pf.facetTolerance[pf.faceFacetOffsets[f]] + impl->pad;
  RTCBounds* b = args->bounds_o;
  b->lower_x = float(lo.x() - grow) - impl->pad;
  b->lower_y = float(lo.y() - grow) - impl->pad;
  b->lower_z = float(lo.z() - grow) - impl->pad;
  b->upper_x = float(hi.x() + grow) + impl->pad;
  b->upper_y = float(hi.y() + grow) + impl->pad;
  b->upper_z = float(hi.z() + grow) + impl->pad;
}

struct PointState {
  const PolygonFacets* pf;
  Eigen::Vector3d p, best;
  double bestDist2;
  int facet;
  float pad;
};

bool pointQueryFn(RTCPointQueryFunctionArguments* args) {
  auto* st = static_cast<PointState*>(args->userPtr);
  if (!nearestOnFace(*st->pf, static_cast<int>(args->primID), st->p, st->best, st->bestDist2, st->facet)) return false;
  const float r = float(std::sqrt(st->bestDist2)) * (1.0f + 1e-6f) + st->pad;
  if (r >= args->query->radius) return false;
  args->query->radius = r;
  return true;
}

/// RTCIntersectContext first, so that Embree's context pointer is ours.
struct SegmentContext {
  RTCIntersectContext base;
  const PolygonFacets* pf;
  Eigen::Vector3d a, b;
  const int* exclude;
  int nExclude;
  double bestT;
  int bestFacet;
};

void intersectFn(const RTCIntersectFunctionNArguments* args) {
  if (args->N != 1 || !args->valid[0]) return;
  auto* sc = reinterpret_cast<SegmentContext*>(args->context);
  const PolygonFacets& pf = *sc->pf;
  const int f = static_cast<int>(args->primID);
  bool hit = false;
  for (int i = pf.faceFacetOffsets[f]; i < pf.faceFacetOffsets[f + 1]; ++i) {
    if (std::find(sc->exclude, sc->exclude + sc->nExclude, i) != sc->exclude + sc->nExclude) continue;
    double t;
    if (segmentEntersFacet(pf, i, sc->a, sc->b, t) && (t < sc->bestT || (t == sc->bestT && i < sc->bestFacet))) {
      sc->bestT = t;
      sc->bestFacet = i;
      hit = true;
    }
  }
  if (!hit) return;
  auto* rh = reinterpret_cast<RTCRayHit*>(args->rayhit);
  rh->ray.tfar = std::min(rh->ray.tfar, float(sc->bestT) * (1.0f + 1e-5f) + 1e-5f);
  rh->hit.geomID = args->geomID;
  rh->hit.primID = args->primID;
}

void occludedFn(const RTCOccludedFunctionNArguments*) {}  // not used; rtcOccluded is never called

}  // namespace

PolygonScene::PolygonScene(const PatchCache& cache, double planarTolerance)
    : cache_(cache), facets_(buildPolygonFacets(cache, planarTolerance)), impl_(std::make_unique<Impl>()) {
  impl_->facets = &facets_;
  const double scale =
      facets_.extent() + std::max(facets_.boxMax.cwiseAbs().maxCoeff(), facets_.boxMin.cwiseAbs().maxCoeff());
  impl_->pad = float(1e-5 * scale) + 1e-30f;
  impl_->device = rtcNewDevice(nullptr);
  if (!impl_->device)
    throw std::runtime_error("rtcNewDevice failed: Embree error " + std::to_string(int(rtcGetDeviceError(nullptr))));
  rtcSetDeviceErrorFunction(impl_->device, onError, impl_.get());
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  if (cache.numFaces() > 0) {
    RTCGeometry g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, static_cast<unsigned>(cache.numFaces()));
    rtcSetGeometryUserData(g, impl_.get());
    rtcSetGeometryBoundsFunction(g, boundsFn, nullptr);
    rtcSetGeometryIntersectFunction(g, intersectFn);
    rtcSetGeometryOccludedFunction(g, occludedFn);
    rtcSetGeometryPointQueryFunction(g, pointQueryFn);
    rtcCommitGeometry(g);
    rtcAttachGeometry(impl_->scene, g);
    rtcReleaseGeometry(g);
  }
  rtcCommitScene(impl_->scene);
  if (impl_->error[0]) throw std::runtime_error(std::string("building the polygon BVH: ") + impl_->error);
  (void)nearest(0.5 * (facets_.boxMin + facets_.boxMax));  // warm-up: first-touch of the BVH
}

PolygonScene::~PolygonScene() = default;

NearestPolygonPoint PolygonScene::nearest(const Eigen::Vector3d& p) const noexcept {
  NearestPolygonPoint out;
  if (cache_.numFaces() == 0 || !p.allFinite()) return out;
  PointState st{&facets_, p, p, std::numeric_limits<double>::infinity(), -1, impl_->pad};
  RTCPointQuery q;
  q.x = float(p.x());
  q.y = float(p.y());
  q.z = float(p.z());
  q.radius = std::numeric_limits<float>::infinity();
  q.time = 0;
  RTCPointQueryContext ctx;
  rtcInitPointQueryContext(&ctx);
  rtcPointQuery(impl_->scene, &q, &ctx, nullptr, &st);
  if (st.facet < 0) return out;
  out.facet = st.facet;
  out.face = facets_.facetFace[st.facet];
  out.point = st.best;
  out.distance = std::sqrt(st.bestDist2);
  return out;
}

PolygonCrossing PolygonScene::firstEntry(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const int* exclude,
                                         int nExclude) const noexcept {
  PolygonCrossing out;
  if (cache_.numFaces() == 0 || !a.allFinite() || !b.allFinite()) return out;
  SegmentContext sc;
  rtcInitIntersectContext(&sc.base);
  sc.pf = &facets_;
  sc.a = a;
  sc.b = b;
  sc.exclude = exclude;
  sc.nExclude = exclude ? nExclude : 0;
  sc.bestT = 2;
  sc.bestFacet = -1;
  RTCRayHit rh;
  const Eigen::Vector3d d = b - a;
  rh.ray.org_x = float(a.x());
  rh.ray.org_y = float(a.y());
  rh.ray.org_z = float(a.z());
  rh.ray.dir_x = float(d.x());
  rh.ray.dir_y = float(d.y());
  rh.ray.dir_z = float(d.z());
  rh.ray.tnear = 0;
  rh.ray.tfar = 1.0f + 1e-5f;
  rh.ray.time = 0;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  if (!(d.squaredNorm() > 0)) return out;  // a zero-length segment enters nothing
  rtcIntersect1(impl_->scene, &sc.base, &rh);
  if (sc.bestFacet < 0) return out;
  out.facet = sc.bestFacet;
  out.face = facets_.facetFace[sc.bestFacet];
  out.t = sc.bestT;
  out.point = a + sc.bestT * d;
  return out;
}

}  // namespace sf
