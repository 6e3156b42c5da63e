// SPDX-License-Identifier: Apache-2.0
// The patch surface as triangle BVHs (Embree): tessellations of every built patch with bounds
// on their distance from the patches, for the global nearest-point query (candidates and
// starting points for refinement) and the inside test (winding number) of Algorithm 1, line 3.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include <smoothforce/base/coordinate_range.h>
#include <smoothforce/patch/patch_cache.h>

namespace sf {

struct UniformTessellation;
struct AdaptiveTessellation;

/// A tessellation triangle whose part of the patch may hold the point nearest a query: its
/// point nearest the query (face, domain coordinates X) and lower = that distance minus the
/// triangle's error bound (a lower bound of the distance to the patch over the triangle).
struct SurfaceCandidate {
  int face = -1, triangle = -1;
  Eigen::Vector2d X{0, 0};  ///< domain point of the triangle's point nearest the query
  double distance = 0;      ///< m, to the triangle
  double lower = 0;         ///< m
};

/// The strict order of candidates: by lower bound, then by `triangle` (PatchSurface::candidates
/// keeps the first `cap` in it and continues it after `after`; the lazy query's cells use it with
/// their own place in `triangle`). Whether (lowerA, triangleA) comes before (lowerB, triangleB).
inline bool candidateBefore(double lowerA, int triangleA, double lowerB, int triangleB) noexcept {
  return lowerA < lowerB || (lowerA == lowerB && triangleA < triangleB);
}
inline bool candidateBefore(const SurfaceCandidate& a, const SurfaceCandidate& b) noexcept {
  return candidateBefore(a.lower, a.triangle, b.lower, b.triangle);
}

/// Options of PatchSurface. Errors are fractions of the mesh's bounding-box diagonal.
struct PatchSurfaceOptions {
  int level = 0;  ///< uniform tessellation level (each polygon edge split in L), 1..64; 0: chosen
  /// level 0: the smallest L (<= 32) whose 90th-percentile triangle error is at most this (the
  /// error estimated over the longest domain edge, not the bound's enclosing circle), unless
  /// that takes more than triangleBudget triangles (then the largest L that fits); and the
  /// adaptive tessellation subdivides triangles while their error exceeds it
  double targetError = 1e-3;
  int64_t triangleBudget = 1'000'000;
  int subdivision = 6;  ///< at most this many halvings of a triangle, 0..8
  /// the adaptive tessellation stops subdividing at this many triangles (a piece of a split
  /// triangle holds 136 bytes, one kept whole 4, plus Embree's BVH), the worst error bounds split
  /// first: normals that disagree with the geometry bulge every patch, and 4 such faces took 9 GB
  /// unbounded. The bundled meshes need at most 3.5 million (bun_zipper.ply); a triangle left
  /// coarser keeps its wider, valid bound.
  int64_t adaptiveBudget = 4'000'000;
  /// false: only what winding() and inErrorBand() need (an inside test, as the sweep's): no
  /// adaptive tessellation and no BVH over it; candidates() then finds none
  bool candidates = true;
  /// true: only what winding() needs (implies no candidates): no error-band BVH and no error
  /// bounds either (uniform().error all 0; the same vertices), so inErrorBand() finds no band
  /// (false everywhere); not for force rendering, whose inside test needs the band. The fault
  /// measure of `cache info --faults` and the normal search (normal_search.h) use it.
  bool windingOnly = false;
};

/// The patch surface for queries, from a prebuilt cache.
///
/// Two tessellations (surface_tessellation.h), each triangle with an error bound on the distance
/// between a patch point G(X) and the triangle's point at the same X: the larger of twice the
/// largest such distance at its centroid and edge midpoints, and a bound from the patch's
/// Jacobian J: the quadratic the corners' Jacobians predict (at most max |(J_a - J_b)(V_a - V_b)|
/// / 6 over the domain edges) plus r max|J - Jl| (r the radius of the smallest circle holding the
/// domain triangle, Jl the linear interpolation of the corners' Jacobians, the difference taken
/// at the centroid and edge midpoints: it sees the folds the midpoints miss), plus the evaluation
/// noise of the cache's precision. These are estimates, not proofs: the tests check the queries
/// they serve against dense sampling and an independent inside test.
/// - uniform: every face at one level L (domainRingPoints: n L^2 triangles per n-gon; one L, so
///   that neighbouring patches share their boundary vertices up to rounding and the
///   tessellation is closed where the patch surface is): the rays of winding() and inErrorBand();
/// - adaptive: the uniform triangles subdivided while their error bound exceeds the target: the
///   point queries of candidates(), on boxes inflated by the bounds (Embree user geometry). A
///   triangle kept whole is read from the uniform tessellation (surface_tessellation.h,
///   AdaptiveTessellation), and one BVH serves both point queries: its primitives are the
///   adaptive triangles and then the uniform triangles they split, so that the band's (the uniform
///   triangles) are those kept whole and the split ones. On dense meshes, where almost none is
///   split, the surface holds about half the bytes of separate copies and BVHs.
/// Queries are const and thread-safe (state on the stack), and do not allocate, lock or throw.
/// The cache must outlive the surface.
class PatchSurface {
 public:
  /// The most candidates() collects.
  static constexpr size_t kMaxCandidates = 256;
  /// Needs a prebuilt cache (hasPatchData); throws InputError for a skeleton or bad options,
  /// and std::runtime_error with Embree's message when Embree fails.
  explicit PatchSurface(const PatchCache& cache, const PatchSurfaceOptions& options = {});
  ~PatchSurface();
  PatchSurface(const PatchSurface&) = delete;
  PatchSurface& operator=(const PatchSurface&) = delete;

  /// Every adaptive triangle whose lower bound (distance to q - its error bound) is at most the
  /// smallest (distance + error bound) over all triangles, so that the patch point nearest q lies
  /// over one of them; sorted by lower bound, at most `cap` (the smallest kept; at most 256 are
  /// collected). Returns how many.
  /// reach: an upper bound (m) of the distance from q to the patch surface, when the caller knows
  /// one (its distance to a patch point, or inErrorBand's); the BVH traversal then starts at
  /// radius reach + 2 maxError() instead of infinity (that patch point lies within its
  /// triangle's error of the triangle, so the triangle's distance + error is below that): the same
  /// candidates, fewer BVH nodes visited. Infinite: none known.
  /// reachFace: the face of the patch point that gives reach, when known (-1: not known): the
  /// radius is then reach + 2 error(reachFace), which a face far from the patch surface's worst
  /// error bounds keeps near reach.
  /// after: the last candidate of an earlier call for the same q that returned 256 (or `cap`):
  /// only candidates after it in (lower bound, triangle) order are collected, the next ones
  /// (null: from the first). A wide error bound (a bulging patch) can give more than 256
  /// triangles a lower bound below the nearest patch point's distance.
  size_t candidates(const Eigen::Vector3d& q, SurfaceCandidate* out, size_t cap,
                    double reach = std::numeric_limits<double>::infinity(), int reachFace = -1,
                    const SurfaceCandidate* after = nullptr) const noexcept;
  /// The record candidates() writes for adaptive triangle t at q (its exact distance, lower bound
  /// and domain point), whether or not t is a candidate there: for a search run elsewhere that
  /// returns triangles only (OpenCLCandidateSearch). A default record for t out of range.
  SurfaceCandidate candidateOf(const Eigen::Vector3d& q, int t) const noexcept;
  /// The radius candidates() starts its search at for (reach, reachFace): reach + 2 error(reachFace),
  /// or reach + 2 maxError() where reachFace is -1 or out of range (m; infinite without a reach).
  double searchRadius(double reach, int reachFace = -1) const noexcept {
    const bool onFace = reachFace >= 0 && static_cast<size_t>(reachFace) < error_.size();
    return reach + 2 * (onFace ? error_[reachFace] : maxError_);
  }

  /// Whether q lies within the error bound of a uniform triangle: then winding() may differ from
  /// the patch surface's own winding number around q. reach, when given and q is in a band: set to
  /// an upper bound (m) of q's distance to the patch surface (that triangle's distance plus its
  /// error bound), and *reachFace (when given) to that triangle's face, the face of the patch
  /// point that bound is measured to; untouched otherwise.
  /// hintFace, hintX: a patch point near q when the caller knows one (a tracker's last point, a
  /// sweep's surface sample; -1: none): the uniform triangle over it is tested first, and where q
  /// lies in its band the BVH query is skipped (the same answer; reach then from that triangle).
  /// hintPoint: that point's position (m) when known (NaN: not known): where q lies farther from
  /// it than twice the face's widest band, q cannot be in that triangle's band and it is not tested.
  bool inErrorBand(const Eigen::Vector3d& q, double* reach = nullptr, int* reachFace = nullptr, int hintFace = -1,
                   const Eigen::Vector2d& hintX = Eigen::Vector2d::Zero(),
                   const Eigen::Vector3d& hintPoint =
                       Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN())) const noexcept;

  /// Winding number of the uniform tessellation around q: signed crossings of a ray from q (+1
  /// leaving through a triangle's front). The first of three rays in fixed skew directions decides
  /// where every crossing it makes is clean (transversal, barycentric coordinates >= 1e-4, not at
  /// the ray's start: the watertight scene counts each once); otherwise the majority of the three
  /// (a ray that grazes an edge or vertex can miscount). 1 inside a closed outward surface, 0
  /// outside.
  int winding(const Eigen::Vector3d& q) const noexcept;

  /// winding() at `back` and at back + length * dir (m; unit dir, length > 0) in *atBack and
  /// *atFront, from one ray from back along dir where every crossing it makes is clean (also at
  /// the far point: the winding number changes by each crossing between the two points), else
  /// as winding() at each. For two nearby points (a surface's probes either side of it), one ray
  /// instead of two or more.
  void windingsAlong(const Eigen::Vector3d& back, const Eigen::Vector3d& dir, double length, int* atBack,
                     int* atFront) const noexcept;

  /// Level of the uniform tessellation, and its triangle count.
  int level() const noexcept;
  size_t numTriangles() const noexcept;
  /// Spacing of the uniform tessellation's vertices in the domain (1 / level): refinements that
  /// start closer than this on one face fall into the same basin.
  double spacing() const noexcept { return 1.0 / level(); }
  /// Whether domain point X of face f lies in the domain triangle of adaptive triangle t
  /// (SurfaceCandidate::triangle; every barycentric coordinate >= -1e-12). False for an
  /// out-of-range t, another face or a degenerate domain triangle.
  bool overTriangle(int t, int f, const Eigen::Vector2d& X) const noexcept;
  /// The largest error bound of face f's adaptive triangles, and of all, m (0 without candidates).
  double error(int f) const noexcept { return error_[f]; }
  double maxError() const noexcept { return maxError_; }
  /// Whether q lies outside the uniform tessellation's box grown by its widest error band: then
  /// q is in no band, and outside the surface where it is closed (exact double comparisons).
  bool beyondBands(const Eigen::Vector3d& q) const noexcept {
    return !((q.array() >= bandLo_.array()).all() && (q.array() <= bandHi_.array()).all());
  }
  /// Whether q lies farther from that box than its diagonal (farBeyondBox): no contact there.
  bool farBeyond(const Eigen::Vector3d& q) const noexcept { return farBeyondBox(q, bandLo_, bandHi_); }
  /// True when every face is built and every edge has a twin: the patch surface is closed.
  bool closed() const noexcept { return closed_; }
  const PatchCache& cache() const noexcept { return cache_; }

  const UniformTessellation& uniform() const noexcept { return *uniform_; }
  /// Bytes the surface holds: both tessellations, their error bounds and the two BVHs (Embree's
  /// own count of what its device allocated); the cache not counted.
  size_t bytes() const noexcept;
  /// The adaptive tessellation candidates() searches (surface_tessellation.h: uniform triangles
  /// kept whole by reference, the pieces of split ones by value).
  const AdaptiveTessellation& adaptive() const noexcept { return *points_; }
  /// The adaptive triangles candidates() searches: how many, and triangle t's corners (m) and
  /// error bound (m), for a search run elsewhere (OpenCLCandidateSearch). t < numPointTriangles().
  size_t numPointTriangles() const noexcept;
  void pointTriangle(size_t t, Eigen::Vector3d corners[3], double* error) const noexcept;

  struct Impl;  ///< Embree device and scenes (opaque)

 private:
  const PatchCache& cache_;
  bool windingOnly_ = false;  ///< PatchSurfaceOptions::windingOnly: no band BVH
  bool closed_ = false;
  double maxError_ = 0;
  std::vector<double> error_;      ///< #F, m (0 for faces not built)
  std::vector<double> bandError_;  ///< #F, m: the largest uniform triangle error per face (the widest band)
  Eigen::Vector3d bandLo_{0, 0, 0}, bandHi_{-1, -1, -1};  ///< m: beyondBands' box (empty: none)
  std::unique_ptr<UniformTessellation> uniform_;
  std::unique_ptr<AdaptiveTessellation> points_;
  std::unique_ptr<Impl> impl_;
};

/// Stack room for N candidates, left uninitialised: the writer fills the entries it reports
/// (PatchSurface::candidates writes out[0..count)). A plain SurfaceCandidate[256] constructs
/// every element, about as many stores per query as the whole candidate search otherwise makes.
template <size_t N = PatchSurface::kMaxCandidates>
struct CandidateBuffer {
  CandidateBuffer() noexcept {}  // leaves c uninitialised on purpose
  union {
    SurfaceCandidate c[N];
  };
  SurfaceCandidate* data() noexcept { return c; }
  const SurfaceCandidate* data() const noexcept { return c; }
  SurfaceCandidate& operator[](size_t i) noexcept { return c[i]; }
  const SurfaceCandidate& operator[](size_t i) const noexcept { return c[i]; }
  static constexpr size_t size() noexcept { return N; }
};

/// The uniform tessellation level PatchSurface uses for `cache` with these options.
int choosePatchSurfaceLevel(const PatchCache& cache, const PatchSurfaceOptions& options);

}  // namespace sf
