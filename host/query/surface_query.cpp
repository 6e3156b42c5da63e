// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/query/surface_query.h>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include <smoothforce/base/coordinate_range.h>
#include <smoothforce/base/error.h>
#include <smoothforce/query/global_query.h>
#include <smoothforce/query/patch_refine.h>

namespace sf {

struct SurfaceQuery::Impl {
  explicit Impl(const PatchCache& cache)
      : refiners([&cache] { return std::make_unique<PatchRefiner>(cache); }) {}
  mutable tbb::enumerable_thread_specific<std::unique_ptr<PatchRefiner>> refiners;
};

SurfaceQuery::SurfaceQuery(std::shared_ptr<const PatchCache> cache, const RefineOptions& options,
                           std::shared_ptr<const PatchSurface> surface)
    : cache_(std::move(cache)), options_(options) {
  if (!cache_) throw std::invalid_argument("SurfaceQuery: no cache");
  if (!hasPatchData(*cache_))
    throw InputError("the surface query needs a prebuilt cache (patches built); this one is a skeleton");
  validateRefineOptions(options_);
  if (surface && &surface->cache() != cache_.get())
    throw InputError("SurfaceQuery: the patch surface must be built from the same cache");
  surface_ = surface ? std::move(surface) : std::make_shared<const PatchSurface>(*cache_, patchSurfaceOptions(options_));
  impl_ = std::make_unique<Impl>(*cache_);
}

SurfaceQuery::~SurfaceQuery() = default;

namespace {

SurfaceQueryResult answer(const PatchSurface& surface, PatchRefiner& refiner, const Eigen::Vector3d& p,
                          const RefineOptions& options) noexcept {
  SurfaceQueryResult r;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (!inCoordinateRange(p)) {
    r.signedDistance = nan;
    r.point = r.normal = Eigen::Vector3d::Constant(nan);
    r.status = SF_TRACK_BAD_HIP;
    return r;
  }
  double reach = std::numeric_limits<double>::infinity();
  int reachFace = -1;
  const int verdict = insideByWinding(surface, p, &reach, &reachFace);
  const PatchNearest q = nearestOnPatches(surface, refiner, p, options, nullptr, reach, nullptr, reachFace);
  const RefineResult& n = q.nearest;
  if (n.face < 0 || !std::isfinite(n.distance)) {
    r.signedDistance = nan;
    r.point = r.normal = Eigen::Vector3d::Constant(nan);
    r.status = SF_TRACK_NO_POLYGON;
    return r;
  }
  const bool inside = insidePatchSurface(surface, p, q, nullptr, verdict);
  r.signedDistance = inside ? -n.distance : n.distance;
  r.point = n.scp;
  r.normal = n.normal;
  r.face = n.face;
  r.xi = n.xi;
  r.eta = n.eta;
  r.status = n.status | (inside ? SF_TRACK_INSIDE : 0u);
  return r;
}

}  // namespace

void SurfaceQuery::query(const double* points, size_t count, SurfaceQueryResult* out, int threads) const {
  if (count == 0) return;
  if (!points || !out) throw std::invalid_argument("SurfaceQuery::query: points and out must not be NULL");
  auto body = [&](const tbb::blocked_range<size_t>& range) {
    std::unique_ptr<PatchRefiner>& refiner = impl_->refiners.local();
    for (size_t i = range.begin(); i != range.end(); ++i)
      out[i] = answer(*surface_, *refiner, Eigen::Vector3d(points[3 * i], points[3 * i + 1], points[3 * i + 2]),
                      options_);
  };
  if (threads == 1) {
    body(tbb::blocked_range<size_t>(0, count));
    return;
  }
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  arena.execute([&] { tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 64), body); });
}

SurfaceQueryResult SurfaceQuery::query(const Eigen::Vector3d& point) const {
  PatchRefiner refiner(*cache_);
  return answer(*surface_, refiner, point, options_);
}

}  // namespace sf
