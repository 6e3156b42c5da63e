// SPDX-License-Identifier: Apache-2.0
// A-priori boxes of the patches in an Embree BVH, and boxes of patch cells computed on demand: the
// face selection of the lazy global query (lazy_surface.h).
#include <smoothforce/query/lazy_surface.h>

#include <embree3/rtcore.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <smoothforce/patch/detail/gp_math.h>
#include <smoothforce/patch/patch_eval.h>

#include <smoothforce/base/coordinate_range.h>

#include "embree_point_query.h"

namespace sf {

struct LazyPatchSurface::Impl {
  RTCDevice device = nullptr;
  std::atomic<int64_t> embreeBytes{0};  ///< what the device holds (its memory monitor)
  RTCScene scene = nullptr;
  const std::vector<PatchBox>* boxes = nullptr;
  float pad = 0;                    ///< m: float rounding of the BVH
  Eigen::Vector3d origin{0, 0, 0};  ///< m: the BVH's frame (localOrigin of the geometry's box)
  char error[256] = {0};
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

constexpr int kObb = 18;         ///< floats per oriented box (makeObb)
constexpr int kCellSamples = 4;  ///< samples per cell side, less one: a sector has (2 kCellSamples + 1)^2

/// One face's patch records, built from the face's edge data (buildPatchEdges) in double, and its
/// evaluation mode (gp_eval_mode of the construction's status); in a batch (tlEvaluator) also
/// field-major, as FacePointEvaluator::evaluateRecords takes them.
struct FaceRecords {
  int n = 0, mode = 0;
  double recordMajor[GP_MAX_N * GP_E_NFIELDS];  ///< as buildPatchEdges writes them
  double fieldMajor[GP_MAX_N * GP_E_NFIELDS];   ///< recordsFieldMajor of recordMajor, in a batch only
  /// Builds face f's records; false where the face gets no patch.
  bool build(const PatchCache& cache, int f) noexcept;
};

/// The evaluator of the calling thread's batch of faces (the construction's sector boxes, every
/// face's cells), or the one a servo step lends for a face's on-demand cells (its refiner's):
/// samples 16 at a time on its SIMD lanes, the bits of one scalar evaluation at a time. Null:
/// one at a time. An evaluator's scratch is about 230 kB, so a batch's lives only as long as the
/// batch, and a step only borrows one (a step never allocates).
thread_local FacePointEvaluator* tlEvaluator = nullptr;

bool FaceRecords::build(const PatchCache& cache, int f) noexcept {
  const uint32_t status = buildPatchEdges(cache, f, recordMajor);
  if (status & GP_ST_NOT_BUILT) return false;
  n = cache.faceSize(f);
  mode = gpd::gp_eval_mode(static_cast<int>(cache.options.crossTangent), status);
  if (tlEvaluator) recordsFieldMajor(n, recordMajor, fieldMajor);  // without one, sampleSector reads recordMajor
  return true;
}

/// Lends each thread of a parallel loop over faces an evaluator for the loop's duration.
class BatchEvaluators {
 public:
  /// Runs body(f) for f in [0, count) in parallel, chunks of `grain` faces, each thread with its evaluator.
  template <class Body>
  void run(int count, int grain, const Body& body) {
    tbb::parallel_for(tbb::blocked_range<int>(0, count, grain), [&](const tbb::blocked_range<int>& r) {
      FacePointEvaluator* previous = tlEvaluator;
      tlEvaluator = &evaluators_.local();
      for (int f = r.begin(); f < r.end(); ++f) body(f);
      tlEvaluator = previous;
    });
  }

 private:
  tbb::enumerable_thread_specific<FacePointEvaluator> evaluators_;
};

void onError(void* user, RTCError code, const char* str) {
  auto* impl = static_cast<LazyPatchSurface::Impl*>(user);
  if (impl->error[0] == 0) std::snprintf(impl->error, sizeof impl->error, "Embree error %d: %s", int(code), str);
}

void boundsFn(const RTCBoundsFunctionArguments* args) {
  const auto* impl = static_cast<const LazyPatchSurface::Impl*>(args->geometryUserPtr);
  const PatchBox& b = (*impl->boxes)[args->primID];
  RTCBounds* o = args->bounds_o;
  if (!b.valid) {  // an empty box far away: never within a query
    o->lower_x = o->lower_y = o->lower_z = 1e30f;
    o->upper_x = o->upper_y = o->upper_z = 1e30f;
    return;
  }
  const Eigen::Vector3d lo = b.lo - impl->origin, hi = b.hi - impl->origin;
  o->lower_x = float(lo.x()) - impl->pad;
  o->lower_y = float(lo.y()) - impl->pad;
  o->lower_z = float(lo.z()) - impl->pad;
  o->upper_x = float(hi.x()) + impl->pad;
  o->upper_y = float(hi.y()) + impl->pad;
  o->upper_z = float(hi.z()) + impl->pad;
}

void obbBounds(const float* o, const Eigen::Vector3d& origin, Eigen::Vector3d& lo, Eigen::Vector3d& hi);

struct Collect {
  const std::vector<PatchBox>* boxes;
  Eigen::Vector3d q;
  double radius;
  FaceDistance* out;
  size_t cap, n, found;
  const FaceDistance* after;  ///< only the faces after it in (distance, face) order; null: all
  /// (distance, face) order, kept in a heap; false: distance order, ties as the BVH meets them, by
  /// insertion (cheap where the traversal meets the boxes nearly in order and ties stay put)
  bool strict;
};

/// (distance, face) order of facesWithin (a function object: inlined in the heap operations).
struct Before {
  bool operator()(const FaceDistance& a, const FaceDistance& b) const noexcept {
    return a.distance < b.distance || (a.distance == b.distance && a.face < b.face);
  }
};
constexpr Before before{};

bool pointQueryFn(RTCPointQueryFunctionArguments* args) {
  auto* c = static_cast<Collect*>(args->userPtr);
  const PatchBox& b = (*c->boxes)[args->primID];
  if (!b.valid) return false;
  const double d = b.distance(c->q);
  if (!(d <= c->radius)) return false;
  const FaceDistance e{static_cast<int>(args->primID), d};
  if (c->after && !before(*c->after, e)) return false;
  ++c->found;
  if (c->cap == 0) return false;
  if (!c->strict) {
    size_t i = c->n;  // insertion into the sorted list, the farthest dropped when full
    if (c->n == c->cap) {
      if (d >= c->out[c->n - 1].distance) return false;
      i = c->n - 1;
    } else {
      ++c->n;
    }
    for (; i > 0 && c->out[i - 1].distance > d; --i) c->out[i] = c->out[i - 1];
    c->out[i] = e;
    return false;
  }
  // a max-heap of the first `cap` in (distance, face) order (its top the last kept), sorted at
  // the end: a HIP inside a hundred boxes gives a hundred ties at distance 0, which a sorted
  // insertion would shift past one another
  if (c->n == c->cap) {
    if (!before(e, c->out[0])) return false;
    std::pop_heap(c->out, c->out + c->n, before);
    c->out[c->n - 1] = e;
  } else {
    c->out[c->n++] = e;
  }
  std::push_heap(c->out, c->out + c->n, before);
  return false;
}

}  // namespace

LazyPatchSurface::LazyPatchSurface(const PatchCache& cache, const PolygonFacets& facets)
    : cache_(cache), facets_(facets), apriori_(patchBoxes(cache)), impl_(std::make_unique<Impl>()) {
  cellBoxes_.assign(static_cast<size_t>(kCellsPerSector) * kObb * cache.numSlots(), 0.f);
  sweptCellBoxes_.assign(static_cast<size_t>(kCellsPerSector) * kObb * cache.numSlots(), 0.f);
  cellCount_.assign(cache.numFaces(), -1);
  sweptBoxes_.assign(static_cast<size_t>(kObb) * cache.numSlots(), 0.f);
  sectorBoxes_.assign(static_cast<size_t>(kObb) * cache.numSlots(), 0.f);
  sectorState_.assign(cache.numFaces(), 0);
  closed_ =
      cache.numFaces() > 0 && std::all_of(cache.slotTwin.begin(), cache.slotTwin.end(), [](int t) { return t >= 0; });
  facetTolerance_.assign(cache.numFaces(), 0.0);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (int f = 0; f < cache.numFaces(); ++f) {
    PatchBox& b = apriori_[f];
    if (!b.valid) continue;
    // the polygon as PolygonScene sees it: a projected facet lies within its tolerance of the
    // face's vertices' box (embree_scene.cpp)
    if (f < facets.numFaces()) {
      const double grow = facetTolerance_[f] = facets.facetTolerance[facets.faceFacetOffsets[f]];
      b.lo.array() -= grow;
      b.hi.array() += grow;
    }
    lo = lo.cwiseMin(b.lo);
    hi = hi.cwiseMax(b.hi);
  }
  impl_->origin = localOrigin(lo, hi);
  if (lo.allFinite() && hi.allFinite() && (lo.array() <= hi.array()).all()) {
    boxLo_ = lo;
    boxHi_ = hi;
  }
  const Eigen::Vector3d llo = lo - impl_->origin, lhi = hi - impl_->origin;
  const double scale =
      lo.allFinite() && hi.allFinite() ? (hi - lo).norm() + llo.cwiseAbs().cwiseMax(lhi.cwiseAbs()).norm() : 1.0;
  impl_->pad = float(1e-5 * scale) + 1e-30f;
  // every face's sector and swept boxes now, in parallel (each face writes only its own slots):
  // 9 evaluations per corner sector, so that no servo step has to compute them
  BatchEvaluators().run(cache.numFaces(), 64, [&](int f) { computeSectors(f); });
  // the BVH's face boxes: the a-priori box, cut down to the box of the face's swept boxes where
  // it has them (5-10 times smaller across on coarse cages, so a HIP near the surface lies in a
  // few faces' boxes instead of a hundred)
  faceBoxes_ = apriori_;
  for (int f = 0; f < cache.numFaces(); ++f) {
    if (!sectors(f)) continue;
    Eigen::Vector3d slo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), shi = -slo;
    for (int k = 0; k < cache.faceSize(f); ++k)
      obbBounds(&sweptBoxes_[static_cast<size_t>(kObb) * (cache.faceOffsets[f] + k)], impl_->origin, slo, shi);
    PatchBox& b = faceBoxes_[f];
    b.lo = b.lo.cwiseMax(slo);
    b.hi = b.hi.cwiseMin(shi);
    if (!(b.lo.array() <= b.hi.array()).all()) b = apriori_[f];  // not finite, or rounding: the proven box
  }
  impl_->boxes = &faceBoxes_;
  impl_->device = newEmbreeDevice(onError, impl_.get(), &impl_->embreeBytes);
  impl_->scene =
      sceneOf(impl_->device,
              cache.numFaces() > 0 ? userGeometry(impl_->device, cache.numFaces(), impl_.get(), boundsFn, pointQueryFn)
                                   : nullptr,
              true);
  if (impl_->error[0]) throw std::runtime_error(std::string("building the patch-box BVH: ") + impl_->error);
}

LazyPatchSurface::~LazyPatchSurface() = default;

size_t LazyPatchSurface::bytes() const noexcept {
  return vectorBytes(apriori_, faceBoxes_, cellBoxes_, sweptCellBoxes_, sectorBoxes_, sectorState_, sweptBoxes_, facetTolerance_, cellCount_) +
         embreeBytes(impl_->embreeBytes);
}

size_t LazyPatchSurface::facesWithin(const Eigen::Vector3d& q, double radius, FaceDistance* out, size_t cap,
                                     size_t* found, const FaceDistance* after) const noexcept {
  Collect c{&faceBoxes_, q, radius, out, std::min(cap, kMaxFaces), 0, 0, after, after != nullptr};
  if (!(cache_.numFaces() > 0 && inCoordinateRange(q) && radius >= 0)) {
    if (found) *found = 0;
    return 0;
  }
  const float r =
      std::isfinite(radius) ? float(radius) * (1.0f + 1e-6f) + impl_->pad : std::numeric_limits<float>::infinity();
  embreePointQuery(impl_->scene, q - impl_->origin, &c, r);
  if (!c.strict && c.found > c.n &&
      c.cap > 0) {  // some were dropped: again in the strict order (a next batch continues it)
    c.n = c.found = 0;
    c.strict = true;
    embreePointQuery(impl_->scene, q - impl_->origin, &c, r);
  }
  if (c.strict) std::sort_heap(out, out + c.n, before);
  if (found) *found = c.found;
  return c.n;
}

bool LazyPatchSurface::inAnyBox(const Eigen::Vector3d& q) const noexcept {
  size_t found = 0;
  facesWithin(q, 0.0, nullptr, 0, &found);
  return found > 0;
}

bool LazyPatchSurface::inAnySweptBox(const Eigen::Vector3d& q) const noexcept {
  FaceDistance in[kMaxFaces];
  size_t found = 0;
  const size_t n = facesWithin(q, 0.0, in, kMaxFaces, &found);
  if (found > n) return true;  // more than kMaxFaces boxes hold q: not looked at, in doubt
  for (size_t i = 0; i < n; ++i) {
    const int f = in[i].face;
    if (!sectors(f)) return true;
    for (int k = 0; k < cache_.faceSize(f); ++k) {
      if (sweptDistance(f, k, q) != 0) continue;
      // the cells' swept boxes only where every face's cells were computed up front
      // (computeAllCells): otherwise the answer would depend on which faces contact reached first
      if (!allCells_ || cellCount_[f] <= 0) return true;
      for (int i = 0; i < kCellsPerSector; ++i)
        if (sweptCellDistance(f, kCellsPerSector * k + i, q) == 0) return true;
    }
  }
  return false;
}

namespace {

/// Domain point at fraction rho along the ray from the centre to the point at fraction t of
/// domain edge k of the n-gon.
Eigen::Vector2d sectorPoint(int n, int k, double rho, double t) {
  // corner k + 1 by its own index (n - 1 + 1 is corner 0 exactly: (1, 0), not a hair outside)
  const Eigen::Vector2d c0 = domainCorner(n, k), c1 = domainCorner(n, (k + 1) % n);
  return rho * (c0 + t * (c1 - c0));
}

/// An oriented box of kObb floats: origin c, stored about the surface's local origin (c - origin:
/// floats of world coordinates 1e4 m from (0,0,0) are 1 mm apart, and the boxes' margins would
/// have to cover that), three axes (unit in exact arithmetic), and the range [lo, hi] of
/// (x - c) . axis for the points x it holds, all as stored (the ranges are computed with the
/// stored origin and axes, rounded outwards): kObb floats.

/// The origin c (m) of oriented box o, stored about the surface's local origin.
Eigen::Vector3d obbOrigin(const float* o, const Eigen::Vector3d& origin) {
  return origin + Eigen::Vector3d(o[0], o[1], o[2]);
}

/// The oriented box with orthonormal frame e of the points pts[0..count), every range widened
/// by margin, into out.
void makeObb(const Eigen::Vector3d* pts, int count, const Eigen::Vector3d* e, double margin,
             const Eigen::Vector3d& origin, float* out) {
  for (int d = 0; d < 3; ++d) out[d] = float(pts[0][d] - origin[d]);
  for (int a = 0; a < 3; ++a)
    for (int d = 0; d < 3; ++d) out[3 + 3 * a + d] = float(e[a][d]);
  const Eigen::Vector3d c = obbOrigin(out, origin);
  for (int a = 0; a < 3; ++a) {
    const Eigen::Vector3d ax(out[3 + 3 * a], out[4 + 3 * a], out[5 + 3 * a]);
    double lo = 1e300, hi = -1e300;
    for (int i = 0; i < count; ++i) {
      const double t = (pts[i] - c).dot(ax);
      lo = std::min(lo, t);
      hi = std::max(hi, t);
    }
    out[12 + a] = std::nextafter(float(lo - margin), -INFINITY);
    out[15 + a] = std::nextafter(float(hi + margin), INFINITY);
  }
}

/// Distance (m) from q to the oriented box o; 0 inside. The stored axes are orthonormal up to
/// float rounding: the result is shrunk by 1e-6 so that it stays a lower bound.
double obbDistance(const float* o, const Eigen::Vector3d& q, const Eigen::Vector3d& origin) {
  const Eigen::Vector3d d = q - obbOrigin(o, origin);
  double s = 0;
  for (int a = 0; a < 3; ++a) {
    const double t = d.dot(Eigen::Vector3d(o[3 + 3 * a], o[4 + 3 * a], o[5 + 3 * a]));
    const double x = t < o[12 + a] ? o[12 + a] - t : t > o[15 + a] ? t - o[15 + a] : 0.0;
    s += x * x;
  }
  return std::sqrt(s) * (1 - 1e-6);
}

/// Grows [lo, hi] (m) to hold oriented box o: its eight corners, each range rounded outwards by a
/// relative 1e-6 and 64 epsilons of the origin's distance (the boxes' own float rounding).
void obbBounds(const float* o, const Eigen::Vector3d& origin, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
  const Eigen::Vector3d c = obbOrigin(o, origin);
  Eigen::Vector3d ext = Eigen::Vector3d::Zero(), mid = c;
  for (int a = 0; a < 3; ++a) {
    const Eigen::Vector3d axis(o[3 + 3 * a], o[4 + 3 * a], o[5 + 3 * a]);
    const double l = o[12 + a], h = o[15 + a];
    mid += 0.5 * (l + h) * axis;
    ext += 0.5 * (h - l) * axis.cwiseAbs();
  }
  const double pad = 1e-6 * ext.norm() + 64 * std::numeric_limits<double>::epsilon() * (c.norm() + ext.norm());
  lo = lo.cwiseMin(mid - ext - Eigen::Vector3d::Constant(pad));
  hi = hi.cwiseMax(mid + ext + Eigen::Vector3d::Constant(pad));
}

/// An orthonormal frame whose third axis is along n (unit), first along u projected.
bool frameFrom(const Eigen::Vector3d& u, const Eigen::Vector3d& v, Eigen::Vector3d* e) {
  const Eigen::Vector3d n = u.cross(v);
  if (!(n.norm() > 1e-12 * u.norm() * v.norm()) || !n.allFinite()) return false;
  e[2] = n.normalized();
  e[0] = (u - u.dot(e[2]) * e[2]).normalized();
  e[1] = e[2].cross(e[0]);
  return e[0].allFinite() && e[1].allFinite();
}

}  // namespace

namespace {

/// The rounding of patch points far from the origin, per metre of the local origin's distance from
/// (0,0,0): 64 epsilons, as evaluationNoise (the spot cage moved by 1e4 to 1e6 m evaluates within 26
/// epsilons of its points at home).
constexpr double kFarRounding = 64 * std::numeric_limits<double>::epsilon();

/// Samples corner sector k of a patch on an (L+1) x (L+1) grid (p[i][j] at ray fraction i/L and
/// edge fraction j/L) and returns the margin of boxes around them: the sector's largest sum of
/// second differences along both grid directions, times `factor` (the patch leaves the samples'
/// bilinear interpolant by about an eighth of that sum), plus 1e-6 of the sector's size (where
/// the surface is flat the second differences vanish), 1e-7 of the distance from `origin` (the
/// surface's local origin: (0,0,0) unless the mesh is far from it) and kFarRounding of the
/// origin's distance from (0,0,0); negative when a sample is not finite.
template <int L>
double sampleSector(const FaceRecords& face, int k, double factor, const Eigen::Vector3d& origin,
                    Eigen::Vector3d (&p)[L + 1][L + 1]) {
  constexpr int kCount = (L + 1) * (L + 1), kGroup = 16;
  if (!tlEvaluator) {  // one at a time: a servo step's face (no allocation)
    const gpd::gp_domain* dom = gpd::gp_domain_of(face.n, nullptr, 1);
    for (int j = 0; j <= L; ++j)
      for (int i = 0; i <= L; ++i) {
        const Eigen::Vector2d X = sectorPoint(face.n, k, double(i) / L, double(j) / L);
        const gpd::gp_eval_result r = gpd::gp_patch_eval_dom(dom, face.recordMajor, face.mode, X.x(), X.y());
        p[i][j] = Eigen::Vector3d(r.pos.x, r.pos.y, r.pos.z);
        if (!p[i][j].allFinite()) return -1;
      }
  }
  for (int first = 0; tlEvaluator && first < kCount; first += kGroup) {  // 16 at a time on SIMD lanes
    const int count = std::min(kGroup, kCount - first);
    double xi[kGroup], eta[kGroup];
    PatchPoint r[kGroup];
    for (int m = 0; m < count; ++m) {  // sample m: i = (first + m) % (L + 1), j = (first + m) / (L + 1)
      const int i = (first + m) % (L + 1), j = (first + m) / (L + 1);
      const Eigen::Vector2d X = sectorPoint(face.n, k, double(i) / L, double(j) / L);
      xi[m] = X.x();
      eta[m] = X.y();
    }
    tlEvaluator->evaluateRecords(face.n, face.mode, 0, face.fieldMajor, xi, eta, count, r);
    for (int m = 0; m < count; ++m) {
      Eigen::Vector3d& q = p[(first + m) % (L + 1)][(first + m) / (L + 1)];
      q = r[m].pos;
      if (!q.allFinite()) return -1;
    }
  }
  double bend = 0;
  for (int j = 0; j <= L; ++j)
    for (int i = 0; i <= L; ++i) {
      double b = 0;
      if (i > 0 && i < L) b += (p[i + 1][j] - 2 * p[i][j] + p[i - 1][j]).norm();
      if (j > 0 && j < L) b += (p[i][j + 1] - 2 * p[i][j] + p[i][j - 1]).norm();
      bend = std::max(bend, factor * b);
    }
  return bend + 1e-6 * ((p[L][0] - p[0][0]).norm() + (p[L][L] - p[0][0]).norm()) + 1e-7 * (p[0][0] - origin).norm() +
         kFarRounding * origin.norm();
}

/// The oriented box of the samples p[i0..i0+h][j0..j0+h], in the frame along the ray and the edge
/// through their middle (the fallback frame where those are parallel), widened by margin.
template <int L>
void gridObb(const Eigen::Vector3d (&p)[L + 1][L + 1], int i0, int j0, int h, const Eigen::Vector3d* fallback,
             double margin, const Eigen::Vector3d& origin, float* out) {
  Eigen::Vector3d pts[(L + 1) * (L + 1)];
  int m = 0;
  for (int i = i0; i <= i0 + h; ++i)
    for (int j = j0; j <= j0 + h; ++j) pts[m++] = p[i][j];
  const int im = i0 + h / 2, jm = j0 + h / 2;
  Eigen::Vector3d e[3];
  if (!frameFrom(p[i0 + h][jm] - p[i0][jm], p[im][j0 + h] - p[im][j0], e)) std::copy(fallback, fallback + 3, e);
  makeObb(pts, m, e, margin, origin, out);
}

/// The fan triangle (centroid, V_k, V_k+1) of corner sector k of face f as PolygonScene sees it:
/// its corners into c, v0, v1 and its frame into e (the face's frame where it is degenerate).
void fanTriangle(const PatchCache& cache, const PolygonFacets& facets, int f, int k, Eigen::Vector3d& c,
                 Eigen::Vector3d& v0, Eigen::Vector3d& v1, Eigen::Vector3d* e) {
  const int first = cache.faceOffsets[f], n = cache.faceSize(f);
  c = facets.faceCentroid[f];
  v0 = Eigen::Map<const Eigen::Vector3d>(&cache.positions[3 * cache.faceVertices[first + k]]);
  v1 = Eigen::Map<const Eigen::Vector3d>(&cache.positions[3 * cache.faceVertices[first + (k + 1) % n]]);
  if (!frameFrom(v1 - v0, c - v0, e)) {
    e[0] = facets.faceU[f];
    e[1] = facets.faceV[f];
    e[2] = facets.faceNormal[f];
  }
}

}  // namespace

bool LazyPatchSurface::computeSectors(int f) noexcept {
  sectorState_[f] = 0;
  const int n = cache_.faceSize(f);
  FaceRecords face;
  if (!apriori_[f].valid || !face.build(cache_, f)) return false;
  const Eigen::Vector3d faceFrame[3] = {facets_.faceU[f], facets_.faceV[f], facets_.faceNormal[f]};
  const int first = cache_.faceOffsets[f];
  for (int k = 0; k < n; ++k) {
    constexpr int L = 2;  // 3 x 3 samples; twice the cells' margin factor: coarser
    Eigen::Vector3d p[L + 1][L + 1];
    const double margin = sampleSector<L>(face, k, 1.0, impl_->origin, p);
    if (margin < 0) return false;
    gridObb<L>(p, 0, 0, L, faceFrame, margin, impl_->origin, &sectorBoxes_[static_cast<size_t>(kObb) * (first + k)]);
    // the swept box: the sector's samples and the polygon's fan triangle (centroid, V_k,
    // V_k+1) as PolygonScene sees it (within the facets' tolerance), in the triangle's frame
    Eigen::Vector3d pts[(L + 1) * (L + 1) + 3];
    int m = 0;
    for (int i = 0; i <= L; ++i)
      for (int j = 0; j <= L; ++j) pts[m++] = p[i][j];
    Eigen::Vector3d centroid, v0, v1, e[3];
    fanTriangle(cache_, facets_, f, k, centroid, v0, v1, e);
    pts[m++] = centroid;
    pts[m++] = v0;
    pts[m++] = v1;
    makeObb(pts, m, e, std::max(margin, facetTolerance_[f]), impl_->origin, &sweptBoxes_[static_cast<size_t>(kObb) * (first + k)]);
  }
  sectorState_[f] = 1;
  return true;
}

int LazyPatchSurface::cells(int f, FacePointEvaluator* evaluator) noexcept {
  if (cellCount_[f] >= 0) return cellCount_[f];
  ++sampledCount_;
  if (!evaluator || tlEvaluator) return computeCells(f);
  tlEvaluator = evaluator;  // lent for this face (computeCells does not throw)
  const int n = computeCells(f);
  tlEvaluator = nullptr;
  return n;
}

int LazyPatchSurface::computeCells(int f) noexcept {
  if (cellCount_[f] >= 0) return cellCount_[f];
  cellCount_[f] = 0;
  const int n = cache_.faceSize(f);
  FaceRecords face;
  if (!apriori_[f].valid || !face.build(cache_, f)) return 0;
  const Eigen::Vector3d faceFrame[3] = {facets_.faceU[f], facets_.faceV[f], facets_.faceNormal[f]};
  float* out = &cellBoxes_[static_cast<size_t>(kCellsPerSector) * kObb * cache_.faceOffsets[f]];
  for (int k = 0; k < n; ++k) {
    constexpr int H = kCellSamples, L = 2 * H;  // cell (a, b): samples i in [aH, (a+1)H], j likewise
    Eigen::Vector3d p[L + 1][L + 1];
    const double margin = sampleSector<L>(face, k, 0.5, impl_->origin, p);
    if (margin < 0) return 0;
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        gridObb<L>(p, a * H, b * H, H, faceFrame, margin, impl_->origin, out + kObb * (kCellsPerSector * k + 2 * a + b));
    // the swept cell boxes: each cell's samples and its part of the polygon's fan triangle (the
    // sector mapped linearly onto the triangle (centroid, V_k, V_k+1): ray fraction rho and edge
    // fraction t go to centroid + rho (V_k + t (V_k+1 - V_k) - centroid)), in the triangle's frame
    Eigen::Vector3d centroid, v0, v1, e[3];
    fanTriangle(cache_, facets_, f, k, centroid, v0, v1, e);
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) {
        Eigen::Vector3d pts[(H + 1) * (H + 1) + 4];
        int m = 0;
        for (int i = a * H; i <= (a + 1) * H; ++i)
          for (int j = b * H; j <= (b + 1) * H; ++j) pts[m++] = p[i][j];
        for (int ri = 0; ri < 2; ++ri)
          for (int ti = 0; ti < 2; ++ti) {
            const double rho = 0.5 * (a + ri), t = 0.5 * (b + ti);
            pts[m++] = centroid + rho * (v0 + t * (v1 - v0) - centroid);
          }
        makeObb(pts, m, e, std::max(margin, facetTolerance_[f]), impl_->origin,
                &sweptCellBoxes_[static_cast<size_t>(kCellsPerSector) * kObb * cache_.faceOffsets[f] +
                                 kObb * (kCellsPerSector * k + 2 * a + b)]);
      }
  }
  cellCount_[f] = static_cast<int16_t>(kCellsPerSector * n);
  return cellCount_[f];
}

void LazyPatchSurface::computeAllCells() noexcept {
  // each face writes only its own slots and count; the count of sampled faces is taken after
  BatchEvaluators().run(cache_.numFaces(), 16, [&](int f) { computeCells(f); });
  sampledCount_ = static_cast<int>(std::count_if(cellCount_.begin(), cellCount_.end(), [](int16_t c) { return c >= 0; }));
  allCells_ = true;
}

double LazyPatchSurface::sectorDistance(int f, int k, const Eigen::Vector3d& q) const noexcept {
  return obbDistance(&sectorBoxes_[static_cast<size_t>(kObb) * (cache_.faceOffsets[f] + k)], q, impl_->origin);
}

double LazyPatchSurface::cellDistance(int f, int i, const Eigen::Vector3d& q) const noexcept {
  return obbDistance(&cellBoxes_[static_cast<size_t>(kCellsPerSector) * kObb * cache_.faceOffsets[f] + kObb * i], q, impl_->origin);
}

double LazyPatchSurface::sweptCellDistance(int f, int i, const Eigen::Vector3d& q) const noexcept {
  return obbDistance(&sweptCellBoxes_[static_cast<size_t>(kCellsPerSector) * kObb * cache_.faceOffsets[f] + kObb * i], q,
                     impl_->origin);
}

double LazyPatchSurface::sweptDistance(int f, int k, const Eigen::Vector3d& q) const noexcept {
  return obbDistance(&sweptBoxes_[static_cast<size_t>(kObb) * (cache_.faceOffsets[f] + k)], q, impl_->origin);
}

Eigen::Vector2d LazyPatchSurface::cellStart(int f, int i, const Eigen::Vector3d& q) const noexcept {
  // the cell's box spans its ray fraction [a/2, (a+1)/2] along its first axis and its edge
  // fraction [b/2, (b+1)/2] along its second (to first order): q's clamped position on both
  const float* o = &cellBoxes_[static_cast<size_t>(kCellsPerSector) * kObb * cache_.faceOffsets[f] + kObb * i];
  const Eigen::Vector3d d = q - obbOrigin(o, impl_->origin);
  double frac[2];
  for (int a = 0; a < 2; ++a) {
    const double t = d.dot(Eigen::Vector3d(o[3 + 3 * a], o[4 + 3 * a], o[5 + 3 * a]));
    const double w = double(o[15 + a]) - o[12 + a];
    frac[a] = w > 0 && std::isfinite(t) ? std::clamp((t - o[12 + a]) / w, 0.05, 0.95) : 0.5;
  }
  const int k = i / kCellsPerSector, a = (i % kCellsPerSector) / 2, b = i % 2;
  return sectorPoint(cache_.faceSize(f), k, 0.5 * (a + frac[0]), 0.5 * (b + frac[1]));
}

}  // namespace sf
