// SPDX-License-Identifier: Apache-2.0
// The only file that calls Embree. Embree works in float: the user primitives' bounds are
// padded so that BVH culling stays conservative for the double-precision queries, and the
// query radius / ray tfar are only ever shrunk to values above the exact double result.
#include <smoothforce/query/embree_scene.h>

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include <smoothforce/base/coordinate_range.h>

#include "embree_point_query.h"

namespace sf {

struct PolygonScene::Impl {
  RTCDevice device = nullptr;
  std::atomic<int64_t> embreeBytes{0};  ///< what the device holds (its memory monitor)
  RTCScene scene = nullptr;
  const PolygonFacets* facets = nullptr;
  float pad = 0;          ///< m, added around every primitive box and to shrunk radii
  Eigen::Vector3d origin{0, 0, 0};  ///< m: the BVH's frame (localOrigin of the geometry's box)
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
  lo -= impl->origin;
  hi -= impl->origin;
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
  bool bothSides;  ///< also report exits (the reversed segment entering a facet)
  bool through;    ///< segmentEntersFacet's through test for entries
  double bestT;
  int bestFacet;
  bool bestEntering;
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
    if (segmentEntersFacet(pf, i, sc->a, sc->b, t, sc->through) &&
        (t < sc->bestT || (t == sc->bestT && (!sc->bestEntering || i < sc->bestFacet)))) {
      sc->bestT = t;
      sc->bestFacet = i;
      sc->bestEntering = true;
      hit = true;
    }
    if (sc->bothSides && segmentEntersFacet(pf, i, sc->b, sc->a, t) &&
        (1 - t < sc->bestT || (1 - t == sc->bestT && !sc->bestEntering && i < sc->bestFacet))) {
      sc->bestT = 1 - t;
      sc->bestFacet = i;
      sc->bestEntering = false;
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
    : cache_(cache),
      planarTolerance_(planarTolerance),
      facets_(buildPolygonFacets(cache, planarTolerance)),
      creaseVertex_(creaseVertexFlags(cache)),
      impl_(std::make_unique<Impl>()) {
  hasCreases_ = std::find(creaseVertex_.begin(), creaseVertex_.end(), 1) != creaseVertex_.end();
  impl_->facets = &facets_;
  impl_->origin = localOrigin(facets_.boxMin, facets_.boxMax);
  const double scale = facets_.extent() + std::max((facets_.boxMax - impl_->origin).cwiseAbs().maxCoeff(),
                                                   (facets_.boxMin - impl_->origin).cwiseAbs().maxCoeff());
  impl_->pad = float(1e-5 * scale) + 1e-30f;
  impl_->device = newEmbreeDevice(onError, impl_.get(), &impl_->embreeBytes);
  impl_->scene = sceneOf(impl_->device,
                         cache.numFaces() > 0 ? userGeometry(impl_->device, cache.numFaces(), impl_.get(), boundsFn,
                                                             pointQueryFn, intersectFn, occludedFn)
                                              : nullptr,
                         true, RTC_BUILD_QUALITY_HIGH);
  if (impl_->error[0]) throw std::runtime_error(std::string("building the polygon BVH: ") + impl_->error);
  (void)nearest(0.5 * (facets_.boxMin + facets_.boxMax));  // warm-up: first-touch of the BVH
}

PolygonScene::~PolygonScene() = default;

size_t PolygonScene::bytes() const noexcept {
  return facets_.bytes() + vectorBytes(creaseVertex_) + embreeBytes(impl_->embreeBytes);
}

NearestPolygonPoint PolygonScene::nearest(const Eigen::Vector3d& p) const noexcept {
  NearestPolygonPoint out;
  if (cache_.numFaces() == 0 || !inCoordinateRange(p)) return out;  // beyond: Embree refuses the point
  PointState st{&facets_, p, p, std::numeric_limits<double>::infinity(), -1, impl_->pad};
  embreePointQuery(impl_->scene, p - impl_->origin, &st);
  if (st.facet < 0) return out;
  out.facet = st.facet;
  out.face = facets_.facetFace[st.facet];
  out.point = st.best;
  out.distance = std::sqrt(st.bestDist2);
  return out;
}

namespace {

PolygonCrossing segmentQuery(const PolygonScene::Impl& impl, const PolygonFacets& facets, const Eigen::Vector3d& a,
                             const Eigen::Vector3d& b, const int* exclude, int nExclude, bool bothSides,
                             bool through) noexcept {
  PolygonCrossing out;
  if (facets.numFaces() == 0 || !inCoordinateRange(a) || !inCoordinateRange(b)) return out;
  SegmentContext sc;
  rtcInitIntersectContext(&sc.base);
  sc.pf = &facets;
  sc.a = a;
  sc.b = b;
  sc.exclude = exclude;
  sc.nExclude = exclude ? nExclude : 0;
  sc.bothSides = bothSides;
  sc.through = through;
  sc.bestT = 2;
  sc.bestFacet = -1;
  sc.bestEntering = true;
  const Eigen::Vector3d d = b - a, o = a - impl.origin;  // the ray's origin in the BVH's frame
  RTCRayHit rh = embreeRay(o, d, 1.0f + 1e-5f);
  if (!(d.squaredNorm() > 0)) return out;  // a zero-length segment enters nothing
  rtcIntersect1(impl.scene, &sc.base, &rh);
  if (sc.bestFacet < 0) return out;
  out.facet = sc.bestFacet;
  out.face = facets.facetFace[sc.bestFacet];
  out.t = sc.bestT;
  out.point = a + sc.bestT * d;
  out.entering = sc.bestEntering;
  return out;
}

}  // namespace

PolygonCrossing PolygonScene::firstEntry(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const int* exclude,
                                         int nExclude, bool through) const noexcept {
  return segmentQuery(*impl_, facets_, a, b, exclude, nExclude, false, through);
}

PolygonCrossing PolygonScene::firstCrossing(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const noexcept {
  return segmentQuery(*impl_, facets_, a, b, nullptr, 0, true, false);
}

bool PolygonScene::contains(const Eigen::Vector3d& p, const Eigen::Vector3d& dir) const noexcept {
  if (facets_.numFaces() == 0 || !inCoordinateRange(p)) return false;
  const double len = 2 * facets_.extent() + (p - 0.5 * (facets_.boxMin + facets_.boxMax)).norm();
  const Eigen::Vector3d fixed[3] = {Eigen::Vector3d(0.5406, 0.6209, 0.5676).normalized(),
                                    Eigen::Vector3d(-0.7071, 0.1961, -0.6793).normalized(),
                                    Eigen::Vector3d(0.2673, -0.8018, 0.5345).normalized()};
  const bool haveDir = dir.allFinite() && dir.squaredNorm() > 0;
  int exits = 0;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d d = haveDir && k == 0 ? Eigen::Vector3d(dir.normalized()) : fixed[k];
    const PolygonCrossing c = firstCrossing(p, p + len * d);
    exits += c.face >= 0 && !c.entering ? 1 : 0;
  }
  return exits >= 2;
}

}  // namespace sf
