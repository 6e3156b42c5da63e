#include "god_object.h"

#include <Eigen/Dense>
#include <cmath>

#include "force_tracking.h"
#include "mean_value.h"

namespace sf {

namespace {
constexpr int kMaxPasses = 12;
}

GodObjectRenderer::GodObjectRenderer(std::shared_ptr<const PatchCache> cache, std::shared_ptr<const PolygonScene> scene,
                                     ForceMethod method, const ForceOptions& options)
    : cache_(std::move(cache)), scene_(std::move(scene)), shading_(method == ForceMethod::Shading), options_(options) {
  validateForceOptions(options);
  if (method == ForceMethod::Patch) throw InputError("GodObjectRenderer: method must be direct or shading");
  int maxN = 3;
  for (int f = 0; f < cache_->numFaces(); ++f) maxN = std::max(maxN, cache_->faceSize(f));
  lambda_.resize(maxN);
}

void GodObjectRenderer::reset() noexcept {
  inContact_ = false;
  havePrev_ = false;
  face_ = -1;
}

bool GodObjectRenderer::goal(const Eigen::Vector3d& hip, const int* act, int m, Eigen::Vector3d& g) const noexcept {
  const PolygonFacets& pf = scene_->facets();
  if (m == 0) {
    g = hip;
    return true;
  }
  // minimise |g - hip|^2 subject to n_i . (g - o_i) = 0: g = hip - sum lambda_i n_i,
  // Gram lambda = n_i . (hip - o_i)
  Eigen::Matrix3d N = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (int i = 0; i < m; ++i) {
    N.col(i) = pf.facetNormal[act[i]];
    rhs(i) = pf.facetNormal[act[i]].dot(hip - pf.facetOrigin[act[i]]);
  }
  if (m == 1) {
    g = hip - rhs(0) * N.col(0);
    return true;
  }
  if (m == 2) {
    const double c = N.col(0).dot(N.col(1)), det = 1 - c * c;
    if (!(det > 1e-10)) return false;
    const double l0 = (rhs(0) - c * rhs(1)) / det, l1 = (rhs(1) - c * rhs(0)) / det;
    g = hip - l0 * N.col(0) - l1 * N.col(1);
    return true;
  }
  const double det = N.determinant();  // three planes: their common point
  if (!(std::abs(det) > 1e-5)) return false;
  const Eigen::Matrix3d G = N.transpose() * N;
  g = hip - N * G.ldlt().solve(rhs);
  return g.allFinite();
}

ForceSample GodObjectRenderer::step(const Eigen::Vector3d& hip) noexcept {
  ForceSample s;
  s.scp = hip;
  if (!hip.allFinite()) {
    reset();
    s.status = SF_TRACK_BAD_HIP;
    return s;
  }
  const bool was = inContact_;
  if (!was) {  // contact starts where the HIP's path enters a polygon from its front side
    s.status |= SF_TRACK_GLOBAL;
    PolygonCrossing c;
    if (havePrev_) c = scene_->firstEntry(prevHip_, hip);
    prevHip_ = hip;
    havePrev_ = true;
    if (c.face < 0) return s;
    proxy_ = c.point;
    s.status |= SF_TRACK_ENTER;
  }
  prevHip_ = hip;
  const PolygonFacets& pf = scene_->facets();
  int act[3], m = 0, passes = 0;
  Eigen::Vector3d x = proxy_, g = hip;
  bool done = false;
  while (passes < kMaxPasses && !done) {
    ++passes;
    while (!goal(hip, act, m, g)) {  // dependent planes: drop the oldest
      for (int i = 1; i < m; ++i) act[i - 1] = act[i];
      --m;
    }
    const PolygonCrossing c = scene_->firstEntry(x, g, act, m);
    if (c.face < 0) {
      x = g;
      // a constraint holds only while the proxy is on its facet: drop those it slid off
      // (past a convex edge) and continue from there in the same step
      int kept = 0;
      for (int i = 0; i < m; ++i)
        if (facetOutsideDistance(pf, act[i], x) <= pf.facetTolerance[act[i]]) act[kept++] = act[i];
      done = kept == m;
      m = kept;
      continue;
    }
    x = c.point;
    if (m == 3) {
      act[0] = act[1];
      act[1] = act[2];
      act[2] = c.facet;
      s.status |= SF_TRACK_PROXY_LIMIT;
    } else {
      act[m++] = c.facet;
    }
  }
  if (!done) s.status |= SF_TRACK_PROXY_LIMIT;  // the proxy stays at the last crossing, on the surface
  s.iterations = passes;
  if (m == 0) {
    inContact_ = false;
    proxy_ = hip;
    face_ = -1;
    s.status = (s.status & ~SF_TRACK_ENTER) | (was ? SF_TRACK_LEAVE : 0u);
    return s;
  }
  inContact_ = true;
  proxy_ = x;
  int best = act[0];
  double bestOut = facetOutsideDistance(pf, act[0], x);
  for (int i = 1; i < m; ++i) {
    const double d = facetOutsideDistance(pf, act[i], x);
    if (d < bestOut) {
      bestOut = d;
      best = act[i];
    }
  }
  const int face = pf.facetFace[best];
  s.transitions = was && face != face_ ? 1 : 0;
  face_ = face;
  const Eigen::Vector2d X = polygonToDomain(pf, *cache_, face, x, lambda_.data());
  const Eigen::Vector3d d = x - hip;
  const double depth = d.norm();
  s.contact = true;
  s.scp = x;
  s.face = face;
  s.xi = X.x();
  s.eta = X.y();
  if (shading_) {
    s.normal = interpolateCornerNormal(pf, *cache_, face, x, lambda_.data());
    s.force = options_.stiffness * depth * s.normal;
  } else {
    s.normal = depth > 0 ? Eigen::Vector3d(d / depth) : pf.facetNormal[best];
    s.force = options_.stiffness * d;
  }
  return s;
}

}  // namespace sf
