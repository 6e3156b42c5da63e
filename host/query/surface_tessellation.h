// SPDX-License-Identifier: Apache-2.0
// Tessellations of the patch surface with per-triangle error bounds, for PatchSurface: a
// uniform one (closed where the surface is, for rays) and an adaptive one (subdivided where the
// patch bends away from its triangles, for point queries).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include <smoothforce/base/memory_bytes.h>
#include <smoothforce/patch/patch_cache.h>

namespace sf {

/// Every built face at level L (domainRingPoints, n L^2 triangles per n-gon; tessellatePatches'
/// layout), vertices shared within a face. error[t] bounds the distance between G(X) and the
/// triangle's point at the same X (see triangleError).
struct UniformTessellation {
  int level = 1;
  std::vector<Eigen::Vector3d> vertex;  ///< m
  std::vector<Eigen::Vector2d> domain;  ///< the vertices' domain points
  std::vector<std::array<int32_t, 3>> tri;
  std::vector<int32_t> triFace;
  std::vector<double> error;          ///< m, per triangle
  std::vector<int64_t> faceFirstTri;  ///< #F: index of each face's first triangle, -1 for a face not built
  size_t bytes() const noexcept { return vectorBytes(vertex, domain, tri, triFace, error, faceFirstTri); }
};

/// The triangle of `u` on face f whose domain triangle holds X (found from the ring layout, no
/// search: sector, then lattice cell; X outside the domain is clamped onto it), or -1 where the
/// face is not built or X is not finite. Points on a shared edge go to either triangle.
int64_t uniformTriangleAt(const UniformTessellation& u, const PatchCache& cache, int f, const Eigen::Vector2d& X);

/// One triangle of the adaptive tessellation (its own corners).
struct SurfaceTriangle {
  int32_t face = -1;
  std::array<Eigen::Vector2d, 3> X;  ///< domain corners
  std::array<Eigen::Vector3d, 3> P;  ///< G at the corners, m
  double error = 0;                  ///< m
};

/// Tessellates every built face of a prebuilt cache at level L (CPU, oneTBB); with `only`, just
/// the built faces it lists (faceFirstTri -1 for the others). errors false leaves every error 0
/// (a tessellation for rays alone, about a fifth of the evaluations); the vertices are the same
/// bits either way, and a face's vertices and triangles do not depend on which others are there.
/// With errors and `levelEstimate`, that receives per triangle the estimate the level is chosen
/// from (the error's residual term over the longest domain edge instead of the smallest
/// enclosing circle's radius: at least the error, see triangleError).
UniformTessellation tessellateUniform(const PatchCache& cache, int L, bool errors = true,
                                      const std::vector<int>* only = nullptr,
                                      std::vector<double>* levelEstimate = nullptr);

/// The adaptive tessellation over a uniform one: per triangle, in the order tessellateAdaptive
/// makes them, either a uniform triangle it keeps whole (ref[i] >= 0, its index in the uniform
/// tessellation: the same corners, domain corners and error) or a piece of a split one (ref[i] <
/// 0: children[-1 - ref[i]]). On dense meshes almost every triangle is kept whole, so each costs
/// 4 bytes here instead of a SurfaceTriangle's 136. `pad` (m) is added to every error bound.
struct AdaptiveTessellation {
  std::vector<int32_t> ref;
  std::vector<SurfaceTriangle> children;
  double pad = 0;
  size_t size() const noexcept { return ref.size(); }
  size_t bytes() const noexcept { return vectorBytes(ref, children); }
};

/// Triangle t (< a.size()) of the adaptive tessellation a over u read in place: its corners (m)
/// and domain corners (in u's arrays, or in the piece's own), its face, and its error bound (m,
/// a.pad included).
struct AdaptiveTriangleRef {
  const Eigen::Vector3d* P[3];
  const Eigen::Vector2d* X[3];
  int face;
  double error;
};
inline AdaptiveTriangleRef adaptiveTriangleRef(const UniformTessellation& u, const AdaptiveTessellation& a, size_t t) {
  AdaptiveTriangleRef p;
  const int32_t r = a.ref[t];
  if (r < 0) {
    const SurfaceTriangle& s = a.children[static_cast<size_t>(-1 - r)];
    for (int k = 0; k < 3; ++k) p.P[k] = &s.P[k], p.X[k] = &s.X[k];
    p.face = s.face;
    p.error = s.error + a.pad;
  } else {
    for (int k = 0; k < 3; ++k) p.P[k] = &u.vertex[u.tri[r][k]], p.X[k] = &u.domain[u.tri[r][k]];
    p.face = u.triFace[r];
    p.error = u.error[r] + a.pad;
  }
  return p;
}

/// The same triangle as a copy.
inline SurfaceTriangle adaptiveTriangle(const UniformTessellation& u, const AdaptiveTessellation& a, size_t t) {
  const AdaptiveTriangleRef p = adaptiveTriangleRef(u, a, t);
  SurfaceTriangle s;
  s.face = p.face;
  for (int k = 0; k < 3; ++k) s.X[k] = *p.X[k], s.P[k] = *p.P[k];
  s.error = p.error;
  return s;
}

/// The uniform triangles, each subdivided into 4 (at its domain edge midpoints) while its error
/// exceeds `maxError` (m), at most `maxDepth` times, and while the result stays within `budget`
/// triangles: where a round would exceed it, only the triangles of largest error (ties: the
/// earlier) are split that fit, and subdivision stops. The result's pad is 0. Needs fewer than
/// 2^31 uniform triangles and children (std::length_error otherwise).
AdaptiveTessellation tessellateAdaptive(const PatchCache& cache, const UniformTessellation& uniform, double maxError,
                                        int maxDepth, size_t budget = SIZE_MAX);

/// The evaluation noise (m) added to every triangle's error bound: the larger of the rounding of
/// the cache's precision relative to the mesh's bounding-box diagonal (1e-13 in double, 2e-6 in
/// float) and relative to its largest coordinate (64 double or 16 float epsilons: a mesh far
/// from the origin rounds at its coordinates).
/// The tessellations never aim below a few times it (choosePatchSurfaceLevel, PatchSurface).
double evaluationNoise(const PatchCache& cache);

/// Triangles of a level-L tessellation of the cache's built faces.
int64_t trianglesAtLevel(const PatchCache& cache, int L);

}  // namespace sf
