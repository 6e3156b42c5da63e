// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/sweep/probe_inside.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <smoothforce/base/error.h>
#include <smoothforce/base/status.h>
#include <smoothforce/query/embree_scene.h>
#include <smoothforce/query/point_index.h>
#include <smoothforce/query/patch_surface.h>
#include <smoothforce/query/polygon_facets.h>
#include <smoothforce/query/surface_faults.h>
#include <smoothforce/sweep/morton_order.h>
#include <smoothforce/sweep/sweep_reference.h>

namespace sf {

namespace {
/// Every polygon edge has a twin (slotTwin): the polygons close.
bool polygonsClosed(const PatchCache& cache) {
  if (cache.numFaces() == 0) return false;
  for (int f = 0; f < cache.numFaces(); ++f)
    for (int s = cache.faceOffsets[f]; s < cache.faceOffsets[f + 1]; ++s)
      if (cache.slotTwin[s] < 0) return false;
  return true;
}

/// The largest level (at most 64) whose uniform tessellation has at most `budget` triangles
/// (n L^2 per n-gon).
int levelWithin(const PatchCache& cache, double budget) {
  const double perLevel2 = static_cast<double>(cache.numSlots());  // triangles at level 1
  return perLevel2 > 0 ? static_cast<int>(std::floor(std::sqrt(budget / perLevel2))) : 64;
}

/// About twice the level of the patch method's own query (PatchSurfaceOptions defaults), at most
/// 64 and at most 4 M triangles.
int oracleLevel(const PatchCache& cache) {
  const int chosen = choosePatchSurfaceLevel(cache, PatchSurfaceOptions{});
  return std::clamp(std::min(2 * chosen, levelWithin(cache, 4e6)), std::max(1, chosen), 64);
}
}  // namespace

ProbeInsideTest::ProbeInsideTest(const PatchCache& cache, ForceMethod method) : cache_(&cache) {
  if (method == ForceMethod::Patch) {
    if (!hasPatchData(cache))
      throw InputError("inside test: the patch method's surface needs built patches (a prebuilt cache)");
    PatchSurfaceOptions o;
    o.level = oracleLevel(cache);
    o.candidates = false;  // only the uniform tessellation's rays and error bands are used
    surface_ = std::make_unique<const PatchSurface>(cache, o);
    closed_ = surface_->closed();
  } else {
    polygons_ = std::make_unique<const PolygonScene>(cache, kWatertightPlanarTolerance);
    closed_ = polygonsClosed(cache);
  }
}

ProbeInsideTest::~ProbeInsideTest() = default;

uint32_t ProbeInsideTest::classify(const Eigen::Vector3d& hip) const noexcept {
  if (!closed_ || !hip.allFinite()) return SF_PROBE_UNDECIDED;
  if (surface_) {
    if (surface_->inErrorBand(hip)) return SF_PROBE_UNDECIDED;
    return surface_->winding(hip) >= 1 ? SF_PROBE_INSIDE : 0;
  }
  return polygons_->contains(hip, Eigen::Vector3d::Zero()) ? SF_PROBE_INSIDE : 0;
}

std::vector<uint32_t> ProbeInsideTest::classify(const std::vector<Eigen::Vector3d>& hips) const {
  // along a Morton curve of the HIPs: consecutive tests walk the same BVH nodes (a sweep's HIPs
  // come in the random order of their samples); each test is on its own
  std::vector<uint32_t> out(hips.size());
  if (hips.size() > UINT32_MAX) {  // beyond mortonOrder's indices: in the given order
    tbb::parallel_for(size_t(0), hips.size(), [&](size_t i) { out[i] = classify(hips[i]); });
    return out;
  }
  const std::vector<uint32_t> order = mortonOrder(hips);
  tbb::parallel_for(size_t(0), hips.size(), [&](size_t k) { out[order[k]] = classify(hips[order[k]]); });
  return out;
}

int ProbeInsideTest::level() const noexcept { return surface_ ? surface_->level() : 0; }

double ProbeInsideTest::surfaceFaultDistance(const Eigen::Vector3d& q) const {
  if (!surface_ || !closed_) return std::numeric_limits<double>::infinity();
  std::call_once(faultsOnce_, [this] {
    // folds and overlaps thinner than a triangle show only at finer levels: the finest level
    // within 10^6 triangles (winding only, dropped once its faults are taken), and never coarser
    // than the test's own, whose tessellation serves where it is that level (the same verdicts)
    const int level = std::clamp(levelWithin(*cache_, 1e6), surface_->level(), 64);
    if (level == surface_->level()) {
      faults_ = faultTriangles(*surface_, measureSurfaceFaults(*surface_));
    } else {
      PatchSurfaceOptions o;
      o.level = level;
      o.windingOnly = true;
      const PatchSurface fine(*cache_, o);
      faults_ = faultTriangles(fine, measureSurfaceFaults(fine));
    }
    std::vector<Eigen::Vector3d> centroids;
    for (const auto& t : faults_) {
      const Eigen::Vector3d c = (t[0] + t[1] + t[2]) / 3.0;
      for (const Eigen::Vector3d& v : t) faultRadius_ = std::max(faultRadius_, (v - c).norm());
      centroids.push_back(c);
    }
    faultCentroids_ = std::make_unique<const PointIndex>(std::move(centroids));
  });
  // the triangles in order of their centroids' distance, until that distance minus the largest
  // centroid-to-corner distance cannot beat the nearest found
  double best = std::numeric_limits<double>::infinity();
  std::vector<uint32_t> idx;
  std::vector<double> d2;
  for (size_t k = 16;; k *= 4) {
    idx.resize(k);
    d2.resize(k);
    const size_t n = faultCentroids_->knn(q, k, idx.data(), d2.data());
    for (size_t i = 0; i < n; ++i) {
      if (std::sqrt(d2[i]) - faultRadius_ >= best) return best;
      const auto& t = faults_[idx[i]];
      best = std::min(best, (closestPointOnTriangle(q, t[0], t[1], t[2]) - q).norm());
    }
    if (n < k) return best;
  }
}

}  // namespace sf
