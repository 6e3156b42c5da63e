// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/force/god_object.h>

#include <Eigen/Dense>
#include <cmath>

#include <smoothforce/base/coordinate_range.h>
#include <smoothforce/force/force_tracking.h>
#include <smoothforce/query/mean_value.h>

namespace sf {

namespace {
constexpr int kMaxPasses = 12;

/// The cache's base polygons moved by -origin: positions, topology and corner normals only
/// (a skeleton, no patch records), for the renderer's local frame.
std::shared_ptr<const PatchCache> movedPolygons(const PatchCache& c, const Eigen::Vector3d& origin) {
  auto m = std::make_shared<PatchCache>();
  m->options = c.options;
  m->meshHash = c.meshHash;
  m->positions = c.positions;
  for (size_t i = 0; i < m->positions.size(); ++i) m->positions[i] -= origin[static_cast<int>(i % 3)];
  m->faceOffsets = c.faceOffsets;
  m->faceVertices = c.faceVertices;
  m->cornerNormals = c.cornerNormals;
  m->slotTwin = c.slotTwin;
  return m;
}

/// True when `moved` holds the polygons of `c` moved by -origin (movedPolygons), bit for bit.
bool inLocalFrame(const PatchCache& moved, const PatchCache& c, const Eigen::Vector3d& origin) {
  if (moved.positions.size() != c.positions.size() || moved.faceOffsets != c.faceOffsets ||
      moved.faceVertices != c.faceVertices || moved.cornerNormals != c.cornerNormals || moved.slotTwin != c.slotTwin)
    return false;
  for (size_t i = 0; i < c.positions.size(); ++i)
    if (!(moved.positions[i] == c.positions[i] - origin[static_cast<int>(i % 3)])) return false;
  return true;
}

/// The origin of a god-object renderer's local frame for `cache` (localOrigin of its box).
Eigen::Vector3d frameOrigin(const PatchCache& cache) {
  Eigen::Vector3d lo, hi;
  referencedBox(cache, lo, hi);
  return localOrigin(lo, hi);
}
}  // namespace

std::shared_ptr<const PolygonScene> godObjectScene(const PatchCache& cache) {
  const Eigen::Vector3d origin = frameOrigin(cache);
  if (origin == Eigen::Vector3d::Zero()) return std::make_shared<const PolygonScene>(cache, kWatertightPlanarTolerance);
  struct Framed {  // the moved polygons and their scene, which refers to them
    std::shared_ptr<const PatchCache> moved;
    PolygonScene scene;
    explicit Framed(std::shared_ptr<const PatchCache> m)
        : moved(std::move(m)), scene(*moved, kWatertightPlanarTolerance) {}
  };
  auto framed = std::make_shared<const Framed>(movedPolygons(cache, origin));
  return std::shared_ptr<const PolygonScene>(framed, &framed->scene);
}

GodObjectRenderer::GodObjectRenderer(std::shared_ptr<const PatchCache> cache, std::shared_ptr<const PolygonScene> scene,
                                     ForceMethod method, const ForceOptions& options)
    : cache_(std::move(cache)), scene_(std::move(scene)), shading_(method == ForceMethod::Shading), options_(options) {
  validateForceOptions(options);
  if (method == ForceMethod::Patch) throw InputError("GodObjectRenderer: method must be direct or shading");
  origin_ = frameOrigin(*cache_);
  if (origin_ != Eigen::Vector3d::Zero()) {  // far from the origin: facets, proxy and HIP about the mesh
    const bool shared = scene_ && scene_->planarTolerance() <= kWatertightPlanarTolerance &&
                        &scene_->cache() != cache_.get() && inLocalFrame(scene_->cache(), *cache_, origin_);
    if (!shared) {
      frameCache_ = movedPolygons(*cache_, origin_);
      scene_ = std::make_shared<const PolygonScene>(*frameCache_, kWatertightPlanarTolerance);
    }
  } else if (!scene_ || scene_->planarTolerance() > kWatertightPlanarTolerance) {  // gaps between projected facets
    scene_ = std::make_shared<const PolygonScene>(*cache_, kWatertightPlanarTolerance);
  }
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
  // The point of the active planes nearest the HIP, in steps that each stay well conditioned
  // (small corrections rather than one Gram solve of the HIP's large offsets, whose error
  // grows as eps |hip - o| / sin^2 of the planes' angle; at 1e-5 rad that was 1e-9 m, enough
  // to put the goal off the facets it lies on): project on plane 0; then within plane 0,
  // perpendicular to the line of planes 0 and 1, onto plane 1; then along that line onto plane 2.
  const PolygonFacets& pf = scene_->facets();
  g = hip;
  if (m == 0) return true;
  const Eigen::Vector3d& n0 = pf.facetNormal[act[0]];
  g -= n0.dot(g - pf.facetOrigin[act[0]]) * n0;
  if (m == 1) return true;
  const Eigen::Vector3d& n1 = pf.facetNormal[act[1]];
  const Eigen::Vector3d w = n1 - n1.dot(n0) * n0;  // in plane 0, |w| = sin(angle)
  const double det = w.dot(n1);                    // 1 - (n0.n1)^2
  if (!(det > 1e-10)) return false;
  g -= (n1.dot(g - pf.facetOrigin[act[1]]) / det) * w;
  if (m == 2) return true;
  const Eigen::Vector3d& n2 = pf.facetNormal[act[2]];
  const Eigen::Vector3d u = n0.cross(n1);  // direction of the line of planes 0 and 1
  const double d3 = n2.dot(u);             // det [n0 n1 n2]
  if (!(std::abs(d3) > 1e-5)) return false;
  g -= (n2.dot(g - pf.facetOrigin[act[2]]) / d3) * u;
  return g.allFinite();
}

int GodObjectRenderer::releasable(const Eigen::Vector3d& hip, const Eigen::Vector3d& x, const int* act,
                                  int m) const noexcept {
  // x - hip = sum mu_i n_i (x on the planes' intersection nearest the HIP); a plane with
  // mu_i < 0 pulls the proxy behind it: without it the proxy moves to its front side
  const PolygonFacets& pf = scene_->facets();
  Eigen::Matrix3d N = Eigen::Matrix3d::Zero();
  for (int i = 0; i < m; ++i) N.col(i) = pf.facetNormal[act[i]];
  const Eigen::Vector3d r = x - hip;
  Eigen::Vector3d mu = Eigen::Vector3d::Zero();
  if (m == 2) {
    const double c = N.col(0).dot(N.col(1)), det = 1 - c * c, r0 = N.col(0).dot(r), r1 = N.col(1).dot(r);
    mu << (r0 - c * r1) / det, (r1 - c * r0) / det, 0;
  } else {
    mu = N.partialPivLu().solve(r);
  }
  int j = -1;
  double worst = -1e-9 * r.norm();
  for (int i = 0; i < m; ++i)
    if (mu(i) < worst) {
      worst = mu(i);
      j = i;
    }
  return j;
}

bool GodObjectRenderer::nearestIfInside(const Eigen::Vector3d& hip, Eigen::Vector3d& point) const noexcept {
  const NearestPolygonPoint n = scene_->nearest(hip);
  if (n.facet < 0) return false;
  const PolygonFacets& pf = scene_->facets();
  const double side = pf.facetNormal[n.facet].dot(hip - pf.facetOrigin[n.facet]);
  // nearest point inside its facet: the segment to it crosses nothing else, so the side of
  // that facet's plane decides; on an edge or a vertex the rays of contains() do
  const bool inside = facetOutsideDistance(pf, n.facet, hip) == 0 && std::abs(side) > pf.planeTolerance
                          ? side < 0
                          : scene_->contains(hip, pf.facetNormal[n.facet]);
  if (!inside) return false;
  point = n.point;
  return true;
}

ForceSample GodObjectRenderer::step(const Eigen::Vector3d& worldHip) noexcept {
  if (!inCoordinateRange(worldHip)) {  // not finite, or beyond the queries' range
    reset();
    ForceSample s;
    s.scp = worldHip;
    s.status = SF_TRACK_BAD_HIP;
    return s;
  }
  ForceSample s = localStep(worldHip - origin_);
  s.scp = s.contact ? Eigen::Vector3d(s.scp + origin_) : worldHip;
  return s;
}

ForceSample GodObjectRenderer::localStep(const Eigen::Vector3d& hip) noexcept {
  ForceSample s;
  s.scp = hip;
  if (inContact_ && farBeyondBox(hip, scene_->facets().boxMin, scene_->facets().boxMax)) {
    reset();  // farther from the polygons' box than its size: no contact holds there
    prevHip_ = hip;
    havePrev_ = true;
    s.status = SF_TRACK_LEAVE;
    return s;
  }
  const bool was = inContact_;
  bool inside = false;  // the HIP was found inside the polygons (PolygonScene::contains)
  if (!was) {           // contact starts where the HIP's path enters a polygon from its front side
    s.status |= SF_TRACK_GLOBAL;
    PolygonCrossing c;
    const bool first = !havePrev_;
    if (!first) c = scene_->firstEntry(prevHip_, hip);
    prevHip_ = hip;
    havePrev_ = true;
    if (c.face >= 0) {
      proxy_ = c.point;
    } else if (!first || !nearestIfInside(hip, proxy_)) {  // or at the first HIP, already inside
      return s;
    } else {
      s.status |= SF_TRACK_INSIDE;
      inside = true;
    }
    s.status |= SF_TRACK_ENTER;
  }
  prevHip_ = hip;
  const PolygonFacets& pf = scene_->facets();
  int act[3], m = 0, passes = 0;
  Eigen::Vector3d x = proxy_, g = hip;
  bool done = false;
  // the last state on the surface: where the proxy stays when the passes run out
  int onAct[3] = {-1, -1, -1}, onM = 0;
  Eigen::Vector3d onX = x;
  auto keepOnSurface = [&] {
    onX = x;
    onM = m;
    for (int i = 0; i < m; ++i) onAct[i] = act[i];
  };
  while (passes < kMaxPasses && !done) {
    ++passes;
    while (!goal(hip, act, m, g)) {  // dependent planes: drop the oldest
      for (int i = 1; i < m; ++i) act[i - 1] = act[i];
      --m;
    }
    const PolygonCrossing c = scene_->firstEntry(x, g, act, m, m > 0);
    if (c.face < 0) {
      x = g;
      // a constraint holds only while the proxy is on its facet: drop those it slid off
      // (past a convex edge) and continue from there in the same step
      int kept = 0;
      for (int i = 0; i < m; ++i)
        if (facetOutsideDistance(pf, act[i], x) <= pf.facetTolerance[act[i]]) act[kept++] = act[i];
      done = kept == m;
      m = kept;
      if (done && m >= 2) {  // and one the HIP pulls to its front is released (in a valley too)
        const int j = releasable(hip, x, act, m);
        if (j >= 0) {
          for (int i = j + 1; i < m; ++i) act[i - 1] = act[i];
          --m;
          done = false;
        }
      }
      if (m > 0) keepOnSurface();
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
    keepOnSurface();
  }
  if (!done) {  // the proxy stays at its last point on the surface
    s.status |= SF_TRACK_PROXY_LIMIT;
    x = onX;
    m = onM;
    for (int i = 0; i < m; ++i) act[i] = onAct[i];
  }
  s.iterations = passes;
  if (m == 0 && (inside || (was && nearestIfInside(hip, x)))) {  // no plane left inside: back on the surface
    const NearestPolygonPoint n = scene_->nearest(hip);
    x = n.point;
    act[m++] = n.facet;
    s.status |= SF_TRACK_INSIDE;
  }
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
