// SPDX-License-Identifier: Apache-2.0
// Embree BVHs over tessellations of the patches: candidates for the global nearest point (point
// queries on the adaptive triangles, boxes inflated by their error bounds, our exact
// double-precision point-triangle distance), the error-band test and the winding number (rays on
// the uniform, closed tessellation, crossings counted in an intersection filter).
#include <smoothforce/query/patch_surface.h>

#include <embree3/rtcore.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include <smoothforce/base/coordinate_range.h>

#include "embree_point_query.h"
#include "gp_closest.h"
#include "gp_config.h"
#include "surface_tessellation.h"
#include "winding_rays.h"

namespace sf {

struct PatchSurface::Impl {
  RTCDevice device = nullptr;
  std::atomic<int64_t> embreeBytes{0};  ///< what the device holds (its memory monitor)
  /// user geometry, boxes inflated by each triangle's error bound: the adaptive triangles (the
  /// candidates' primitives 0..N-1, N = the adaptive tessellation's size), then the uniform
  /// triangles it split (bandOnly): the error band's primitives are the uniform triangles, those
  /// kept whole among the first N and the split ones after them
  RTCScene points = nullptr;
  std::vector<int32_t> bandOnly;      ///< uniform triangles the adaptive tessellation split, ascending
  std::unique_ptr<WindingRays> rays;  ///< the uniform triangles as Embree triangles (winding())
  const PatchSurface* surface = nullptr;
  float pad = 0;                    ///< m: float rounding of the BVHs, added to boxes and radii
  Eigen::Vector3d origin{0, 0, 0};  ///< m: the BVHs' frame (localOrigin of the geometry's box)
  char error[256] = {0};
  ~Impl() {
    rays.reset();  // (its scene, before the device)
    if (points) rtcReleaseScene(points);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

/// The tessellations aim no finer than this many times the evaluation noise: below it a
/// triangle's measured error is rounding, and subdividing it only multiplies the triangles.
constexpr double kNoiseFloor = 4;

void onError(void* user, RTCError code, const char* str) {
  auto* impl = static_cast<PatchSurface::Impl*>(user);
  if (impl->error[0] == 0) std::snprintf(impl->error, sizeof impl->error, "Embree error %d: %s", int(code), str);
}

/// Closest point of triangle abc to p (kernels/gp_closest.h, which the OpenCL candidate search
/// runs too): returns the squared distance and the barycentric weights (u, v, w) of the closest
/// point.
double closestOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                         const Eigen::Vector3d& c, double& u, double& v, double& w) {
  return gp_closest_on_triangle(p.data(), a.data(), b.data(), c.data(), &u, &v, &w);
}

/// The candidate record of triangle t (index id) at distance d, closest point (u, v, w).
SurfaceCandidate candidateRecord(const AdaptiveTriangleRef& t, int id, double d, double u, double v, double w) {
  SurfaceCandidate c;
  c.face = t.face;
  c.triangle = id;
  c.distance = d;
  c.lower = d - t.error;
  c.X = u * *t.X[0] + v * *t.X[1] + w * *t.X[2];
  return c;
}

void setBounds(RTCBounds* b, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double e, float pad) {
  if (!std::isfinite(e)) e = 0;  // a triangle with a non-finite evaluation: its corners only
  b->lower_x = float(lo.x() - e) - pad;
  b->lower_y = float(lo.y() - e) - pad;
  b->lower_z = float(lo.z() - e) - pad;
  b->upper_x = float(hi.x() + e) + pad;
  b->upper_y = float(hi.y() + e) + pad;
  b->upper_z = float(hi.z() + e) + pad;
}

void pointBounds(const RTCBoundsFunctionArguments* args) {
  const auto* impl = static_cast<const PatchSurface::Impl*>(args->geometryUserPtr);
  const AdaptiveTriangleRef t = adaptiveTriangleRef(impl->surface->uniform(), impl->surface->adaptive(), args->primID);
  const Eigen::Vector3d lo = t.P[0]->cwiseMin(*t.P[1]).cwiseMin(*t.P[2]),
                        hi = t.P[0]->cwiseMax(*t.P[1]).cwiseMax(*t.P[2]);
  setBounds(args->bounds_o, lo - impl->origin, hi - impl->origin, t.error, impl->pad);
}

/// The shared BVH's primitive: adaptive triangle primID, or after them the split uniform one.
void surfaceBounds(const RTCBoundsFunctionArguments* args) {
  const auto* impl = static_cast<const PatchSurface::Impl*>(args->geometryUserPtr);
  const size_t n = impl->surface->adaptive().size();
  if (args->primID < n) {
    pointBounds(args);
    return;
  }
  const UniformTessellation& u = impl->surface->uniform();
  const int32_t t = impl->bandOnly[args->primID - n];
  const auto& tr = u.tri[t];
  const Eigen::Vector3d &a = u.vertex[tr[0]], &b = u.vertex[tr[1]], &c = u.vertex[tr[2]];
  setBounds(args->bounds_o, a.cwiseMin(b).cwiseMin(c) - impl->origin, a.cwiseMax(b).cwiseMax(c) - impl->origin,
            u.error[t], impl->pad);
}

// ---- candidates ----

constexpr size_t kMaxCandidates = PatchSurface::kMaxCandidates;

/// Which query runs on the shared BVH: the first part of both point-query states.
struct QueryState {
  bool band;
};

struct CandidateState : QueryState {
  const UniformTessellation* uniform;
  const AdaptiveTessellation* adaptive;
  Eigen::Vector3d q;
  double bound;  ///< min over the triangles seen of (distance + error)
  float pad;
  size_t count;
  CandidateBuffer<kMaxCandidates> c;  ///< c[0..count) written
  /// collect only triangles after this (lower bound, triangle) in that order (null: all); every
  /// triangle still counts towards bound
  const SurfaceCandidate* after;
};

bool candidateFn(RTCPointQueryFunctionArguments* args) {
  auto* st = static_cast<CandidateState*>(static_cast<QueryState*>(args->userPtr));
  if (args->primID >= st->adaptive->size()) return false;  // a split uniform triangle: the band's only
  const AdaptiveTriangleRef t = adaptiveTriangleRef(*st->uniform, *st->adaptive, args->primID);
  double u, v, w;
  const double d = std::sqrt(closestOnTriangle(st->q, *t.P[0], *t.P[1], *t.P[2], u, v, w));
  const double e = t.error;
  if (!(d - e <= st->bound)) return false;
  const int id = static_cast<int>(args->primID);
  SurfaceCandidate* slot = nullptr;
  if (st->after && !candidateBefore(st->after->lower, st->after->triangle, d - e, id)) {
    // collected by an earlier call: only its bound counts
  } else if (st->count < kMaxCandidates) {
    slot = &st->c[st->count++];
  } else {  // full: replace the last candidate in (lower bound, triangle) order, if after this one
    // (a strict order: the candidates kept do not depend on the order Embree visits them in)
    slot = &st->c[0];
    for (size_t i = 1; i < st->count; ++i)
      if (candidateBefore(*slot, st->c[i])) slot = &st->c[i];
    if (!candidateBefore(d - e, id, slot->lower, slot->triangle)) slot = nullptr;
  }
  if (slot) *slot = candidateRecord(t, id, d, u, v, w);
  if (d + e < st->bound) {
    st->bound = d + e;  // every box is inflated by its triangle's error: no more margin needed
    const float r = float(st->bound) * (1.0f + 1e-6f) + st->pad;
    if (r < args->query->radius) {
      args->query->radius = r;
      return true;
    }
  }
  return false;
}

// ---- error band ----

struct BandState : QueryState {
  const UniformTessellation* u;
  const AdaptiveTessellation* a;         ///< the shared BVH's first primitives
  const std::vector<int32_t>* bandOnly;  ///< and the others
  Eigen::Vector3d q;
  bool inside = false;
  double reach = std::numeric_limits<double>::infinity();  ///< m, distance + error bound of the triangle found
  int face = -1;                                           ///< its face
};

/// Whether st.q lies in the error band of uniform triangle t (then st records it).
bool testBand(BandState& st, int64_t t) {
  const UniformTessellation& u = *st.u;
  const auto& tr = u.tri[t];
  double a, b, c;
  const double d = std::sqrt(closestOnTriangle(st.q, u.vertex[tr[0]], u.vertex[tr[1]], u.vertex[tr[2]], a, b, c));
  if (d > u.error[t]) return false;
  st.inside = true;
  st.reach = d + u.error[t];
  st.face = u.triFace[t];
  return true;
}

bool bandFn(RTCPointQueryFunctionArguments* args) {
  auto* st = static_cast<BandState*>(static_cast<QueryState*>(args->userPtr));
  if (st->inside) return false;
  const size_t n = st->a->size();
  const int64_t t = args->primID < n ? st->a->ref[args->primID] : (*st->bandOnly)[args->primID - n];
  if (t < 0 || !testBand(*st, t)) return false;  // t < 0: a piece of a split triangle, no band's
  args->query->radius = 0;                       // found one: stop looking
  return true;
}

/// The shared BVH's point query: the candidates' or the band's, as the state says.
bool surfaceQueryFn(RTCPointQueryFunctionArguments* args) {
  return static_cast<const QueryState*>(args->userPtr)->band ? bandFn(args) : candidateFn(args);
}

}  // namespace

namespace {

/// choosePatchSurfaceLevel, keeping its level-2 tessellation (with error bounds) in *probeOut
/// where it made one.
int chooseLevel(const PatchCache& cache, const PatchSurfaceOptions& o, UniformTessellation* probeOut) {
  if (o.level > 0) return o.level;
  // a triangle's error shrinks like its size squared: error(L) ~ error(2) (2 / L)^2
  // from the level estimate (tessellateUniform), not the error bounds: see triangleError
  std::vector<double> e;
  UniformTessellation probe = tessellateUniform(cache, 2, true, nullptr, &e);
  if (e.empty()) return 1;
  for (double& x : e) x = std::isfinite(x) ? x : 0.0;
  const size_t k = e.size() * 9 / 10;
  std::nth_element(e.begin(), e.begin() + k, e.end());
  // no finer than the evaluation noise resolves (a mesh far from the origin)
  const double target = std::max(o.targetError * boundingDiagonal(cache), kNoiseFloor * evaluationNoise(cache));
  int L = 1;
  while (L < 32 && e[k] * 4.0 / (double(L) * L) > target) ++L;
  while (L > 1 && trianglesAtLevel(cache, L) > o.triangleBudget) --L;
  if (probeOut) *probeOut = std::move(probe);
  return L;
}

}  // namespace

int choosePatchSurfaceLevel(const PatchCache& cache, const PatchSurfaceOptions& o) {
  return chooseLevel(cache, o, nullptr);
}

PatchSurface::PatchSurface(const PatchCache& cache, const PatchSurfaceOptions& options)
    : cache_(cache),
      windingOnly_(options.windingOnly),
      points_(std::make_unique<AdaptiveTessellation>()),
      impl_(std::make_unique<Impl>()) {
  if (!hasPatchData(cache)) throw InputError("the patch surface needs built patches (a cache, not a skeleton)");
  if (options.level < 0 || options.level > 64) throw InputError("patch surface level must be in 0..64");
  if (!(options.targetError > 0) || options.subdivision < 0 || options.subdivision > 8 || options.adaptiveBudget < 1)
    throw InputError("patch surface: targetError must be > 0, subdivision in 0..8 and adaptiveBudget >= 1");
  const double diag = boundingDiagonal(cache);
  const double noise = evaluationNoise(cache);
  // winding only: no band, and so no error bounds to compute (the same vertices); at level 2 the
  // level's choice already made the tessellation with its error bounds (dense meshes)
  UniformTessellation probe;
  const int level = chooseLevel(cache, options, &probe);
  uniform_ = std::make_unique<UniformTessellation>(level == 2 && probe.level == 2 && !options.windingOnly
                                                       ? std::move(probe)
                                                       : tessellateUniform(cache, level, !options.windingOnly));
  for (double& e : uniform_->error) e += noise;
  bandError_.assign(cache.numFaces(), 0.0);
  for (size_t t = 0; t < uniform_->tri.size(); ++t)
    bandError_[uniform_->triFace[t]] = std::max(bandError_[uniform_->triFace[t]], uniform_->error[t]);
  if (options.candidates && !options.windingOnly)
    *points_ = tessellateAdaptive(cache, *uniform_, std::max(options.targetError * diag, kNoiseFloor * noise),
                                  options.subdivision, static_cast<size_t>(options.adaptiveBudget));
  points_->pad = noise;
  error_.assign(cache.numFaces(), 0.0);
  for (size_t t = 0; t < points_->size(); ++t) {
    const AdaptiveTriangleRef p = adaptiveTriangleRef(*uniform_, *points_, t);
    error_[p.face] = std::max(error_[p.face], p.error);
    maxError_ = std::max(maxError_, p.error);
  }
  closed_ = true;
  for (int f = 0; f < cache.numFaces(); ++f) {
    if (cache.faceStatus[f] & GP_ST_NOT_BUILT) {
      closed_ = false;
      continue;
    }
    for (int s = cache.faceOffsets[f]; s < cache.faceOffsets[f + 1]; ++s) closed_ = closed_ && cache.slotTwin[s] >= 0;
  }

  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const auto& p : uniform_->vertex) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  impl_->origin = localOrigin(lo, hi);
  double widest = 0;
  for (double e : uniform_->error) widest = std::max(widest, std::isfinite(e) ? e : 0.0);
  if (!uniform_->vertex.empty()) {  // a non-finite band error is no band (testBand compares against it)
    bandLo_ = lo.array() - widest;
    bandHi_ = hi.array() + widest;
  }
  double extent = diag;
  for (const auto& p : uniform_->vertex) extent = std::max(extent, (p - impl_->origin).cwiseAbs().maxCoeff());
  impl_->surface = this;
  impl_->pad = float(1e-5 * extent) + 1e-30f;
  impl_->device = newEmbreeDevice(onError, impl_.get(), &impl_->embreeBytes);
  const UniformTessellation& u = *uniform_;
  if (!options.windingOnly) {  // the band's triangles: those kept whole, then the split ones
    std::vector<char> whole(u.tri.size(), 0);
    for (const int32_t r : points_->ref)
      if (r >= 0) whole[r] = 1;
    for (size_t t = 0; t < u.tri.size(); ++t)
      if (!whole[t]) impl_->bandOnly.push_back(static_cast<int32_t>(t));
  }
  const size_t prims = points_->size() + impl_->bandOnly.size();
  if (prims > size_t(std::numeric_limits<unsigned>::max()))
    throw std::length_error("patch surface: more triangles than a BVH takes");
  RTCGeometry g = prims == 0 ? nullptr : userGeometry(impl_->device, prims, impl_.get(), surfaceBounds, surfaceQueryFn);
  impl_->points = sceneOf(impl_->device, g, false);
  impl_->rays = std::make_unique<WindingRays>(impl_->device, u, nullptr, impl_->origin);
  if (impl_->error[0]) throw std::runtime_error(std::string("building the patch surface BVHs: ") + impl_->error);
}

PatchSurface::~PatchSurface() = default;

size_t PatchSurface::bytes() const noexcept {
  return vectorBytes(error_, bandError_, impl_->bandOnly) + points_->bytes() + uniform_->bytes() +
         embreeBytes(impl_->embreeBytes);
}

int PatchSurface::level() const noexcept { return uniform_->level; }
size_t PatchSurface::numTriangles() const noexcept { return uniform_->tri.size(); }

size_t PatchSurface::candidates(const Eigen::Vector3d& q, SurfaceCandidate* out, size_t cap, double reach,
                                int reachFace, const SurfaceCandidate* after) const noexcept {
  if (points_->ref.empty() || !inCoordinateRange(q) || cap == 0) return 0;  // beyond: Embree refuses the point
  CandidateState st;
  st.band = false;
  st.uniform = uniform_.get();
  st.adaptive = points_.get();
  st.after = after;
  st.q = q;
  st.bound = std::numeric_limits<double>::infinity();
  st.pad = impl_->pad;
  st.count = 0;
  // The patch point P that gives reach (|q - P| <= reach) lies within its triangle's error e of
  // that triangle, whose distance + e is then at most |q - P| + 2e <= reach + 2 e =: r0, with e
  // at most the largest error of P's face (or of all), so the search can start at radius r0.
  // Every triangle that can be a candidate (distance - error <= the final bound) is then visited
  // as long as the final bound is <= r0; the error bounds are estimates, so where it is not, the
  // search runs again without the radius: the same candidates always.
  const double r0 = searchRadius(reach, reachFace);
  if (r0 < 1e30) {
    embreePointQuery(impl_->points, q - impl_->origin, static_cast<QueryState*>(&st),
                     float(r0) * (1.0f + 1e-6f) + st.pad);
    if (!(st.bound <= r0)) {
      st.bound = std::numeric_limits<double>::infinity();
      st.count = 0;
      embreePointQuery(impl_->points, q - impl_->origin, static_cast<QueryState*>(&st));
    }
  } else {
    embreePointQuery(impl_->points, q - impl_->origin, static_cast<QueryState*>(&st));
  }
  size_t n = 0;
  for (size_t i = 0; i < st.count; ++i)
    if (st.c[i].lower <= st.bound) st.c[n++] = st.c[i];
  std::sort(st.c.data(), st.c.data() + n, [](const SurfaceCandidate& a, const SurfaceCandidate& b) {
    return a.lower < b.lower || (a.lower == b.lower && a.triangle < b.triangle);
  });
  n = std::min(n, cap);
  std::copy_n(st.c.data(), n, out);
  return n;
}

SurfaceCandidate PatchSurface::candidateOf(const Eigen::Vector3d& q, int t) const noexcept {
  if (t < 0 || static_cast<size_t>(t) >= points_->size()) return SurfaceCandidate{};
  const AdaptiveTriangleRef tri = adaptiveTriangleRef(*uniform_, *points_, static_cast<size_t>(t));
  double u, v, w;
  const double d = std::sqrt(closestOnTriangle(q, *tri.P[0], *tri.P[1], *tri.P[2], u, v, w));
  return candidateRecord(tri, t, d, u, v, w);
}

size_t PatchSurface::numPointTriangles() const noexcept { return points_->size(); }

void PatchSurface::pointTriangle(size_t t, Eigen::Vector3d corners[3], double* error) const noexcept {
  const AdaptiveTriangleRef p = adaptiveTriangleRef(*uniform_, *points_, t);
  for (int k = 0; k < 3; ++k) corners[k] = *p.P[k];
  *error = p.error;
}

bool PatchSurface::overTriangle(int t, int f, const Eigen::Vector2d& X) const noexcept {
  if (t < 0 || static_cast<size_t>(t) >= points_->size() || !X.allFinite()) return false;
  const AdaptiveTriangleRef p = adaptiveTriangleRef(*uniform_, *points_, static_cast<size_t>(t));
  if (p.face != f) return false;
  const Eigen::Vector2d c[3] = {*p.X[0], *p.X[1], *p.X[2]};
  auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); };
  const double area = cross(c[1] - c[0], c[2] - c[0]);  // twice the signed area
  if (!(std::abs(area) > 0)) return false;
  // barycentric coordinates of X: the signed areas of the sub-triangles over the whole
  const double l0 = cross(c[1] - X, c[2] - X) / area, l1 = cross(c[2] - X, c[0] - X) / area;
  const double l2 = 1 - l0 - l1, low = -1e-12;
  return l0 >= low && l1 >= low && l2 >= low;
}

bool PatchSurface::inErrorBand(const Eigen::Vector3d& q, double* reach, int* reachFace, int hintFace,
                               const Eigen::Vector2d& hintX, const Eigen::Vector3d& hintPoint) const noexcept {
  if (uniform_->tri.empty() || windingOnly_ || !inCoordinateRange(q) || beyondBands(q)) return false;
  BandState st;
  st.band = true;
  st.u = uniform_.get();
  st.a = points_.get();
  st.bandOnly = &impl_->bandOnly;
  st.q = q;
  // the triangle over the hint first: in its band, q is in a band (any triangle's band will do).
  // The hint's point lies within that triangle's error e of it, so q within e of the triangle lies
  // within 2e of the point: farther than twice the face's widest band, the test cannot succeed.
  const bool near = hintFace >= 0 && static_cast<size_t>(hintFace) < bandError_.size() &&
                    !((q - hintPoint).norm() > 2 * bandError_[hintFace]);
  if (const int64_t t = near ? uniformTriangleAt(*uniform_, cache_, hintFace, hintX) : -1; t >= 0) testBand(st, t);
  if (!st.inside)
    // boxes are inflated by the errors: q must lie in one
    embreePointQuery(impl_->points, q - impl_->origin, static_cast<QueryState*>(&st), impl_->pad);
  if (st.inside && reach) *reach = st.reach;
  if (st.inside && reachFace) *reachFace = st.face;
  return st.inside;
}

int PatchSurface::winding(const Eigen::Vector3d& q) const noexcept {
  if (uniform_->tri.empty() || !inCoordinateRange(q)) return 0;
  return windingFromRays([&](int k, bool* clean) { return impl_->rays->crossings(q, k, clean); });
}

void PatchSurface::windingsAlong(const Eigen::Vector3d& back, const Eigen::Vector3d& dir, double length, int* atBack,
                                 int* atFront) const noexcept {
  if (uniform_->tri.empty() || !inCoordinateRange(back) || !inCoordinateRange(back + length * dir)) {
    *atBack = winding(back);
    *atFront = winding(back + length * dir);
    return;
  }
  windingsAlongRay(
      back, dir, length,
      [&](const Eigen::Vector3d& q, const Eigen::Vector3d& d, double l, int* nearSum, int* farSum, bool* clean) {
        impl_->rays->splitCrossings(q, d, l, nearSum, farSum, clean);
      },
      [&](const Eigen::Vector3d& q, int k, bool* clean) { return impl_->rays->crossings(q, k, clean); }, atBack,
      atFront);
}

}  // namespace sf
