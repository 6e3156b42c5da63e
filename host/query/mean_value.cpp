// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/query/mean_value.h>

#include <algorithm>
#include <cmath>

namespace sf {

void meanValueCoordinates(const Eigen::Vector2d* poly, int n, const Eigen::Vector2d& x, double* lambda) noexcept {
  // s_i = v_i - x, r_i = |s_i|, A_i = det(s_i, s_{i+1}), D_i = s_i . s_{i+1};
  // w_i = tan(alpha_{i-1}/2)/r_i + tan(alpha_i/2)/r_i with tan(alpha_i/2) = (r_i r_{i+1} - D_i)/A_i.
  double scale = 0;
  int nearest = 0;
  for (int i = 0; i < n; ++i) {
    const double r = (poly[i] - x).norm();
    scale = std::max(scale, r);
    if (r < (poly[nearest] - x).norm()) nearest = i;
  }
  const double vertexTol = 1e-15 * scale;
  for (int i = 0; i < n; ++i) lambda[i] = 0;
  if (!(scale > 0) || !std::isfinite(scale) || (poly[nearest] - x).norm() <= vertexTol) {
    lambda[nearest] = 1;  // on a vertex (or all vertices coincide)
    return;
  }
  auto S = [&](int i) { return Eigen::Vector2d(poly[(i + n) % n] - x); };
  auto A = [&](int i) {
    const Eigen::Vector2d a = S(i), b = S(i + 1);
    return a.x() * b.y() - a.y() * b.x();
  };
  for (int i = 0; i < n; ++i) {  // on edge i: linear interpolation of its ends
    const Eigen::Vector2d a = S(i), b = S(i + 1);
    const double ra = a.norm(), rb = b.norm();
    if (std::abs(A(i)) <= 1e-14 * ra * rb && a.dot(b) < 0) {
      lambda[i] = rb / (ra + rb);
      lambda[(i + 1) % n] += ra / (ra + rb);
      return;
    }
  }
  auto tanHalfOverA = [&](int i) {  // (r_i r_{i+1} - D_i) / A_i, 0 on the edge's line outside it
    const Eigen::Vector2d a = S(i), b = S(i + 1);
    const double ai = A(i);
    if (std::abs(ai) <= 1e-14 * a.norm() * b.norm()) return 0.0;
    return (a.norm() * b.norm() - a.dot(b)) / ai;
  };
  double W = 0, prev = tanHalfOverA(n - 1);
  for (int i = 0; i < n; ++i) {
    const double cur = tanHalfOverA(i);
    lambda[i] = (prev + cur) / S(i).norm();
    W += lambda[i];
    prev = cur;
  }
  if (!std::isfinite(W) || std::abs(W) < 1e-300) {
    for (int i = 0; i < n; ++i) lambda[i] = i == nearest ? 1 : 0;
    return;
  }
  for (int i = 0; i < n; ++i) lambda[i] /= W;
}

Eigen::Vector2d polygonToDomain(const PolygonFacets& pf, const PatchCache& cache, int f, const Eigen::Vector3d& p,
                                double* lambda) noexcept {
  const int n = cache.faceSize(f), first = cache.faceOffsets[f];
  const Eigen::Vector3d d = p - pf.faceCentroid[f];
  meanValueCoordinates(&pf.corner2d[first], n, {d.dot(pf.faceU[f]), d.dot(pf.faceV[f])}, lambda);
  Eigen::Vector2d X(0, 0);
  for (int k = 0; k < n; ++k) X += lambda[k] * domainCorner(n, k);
  return clampToDomain(n, X);
}

Eigen::Vector3d interpolateCornerNormal(const PolygonFacets& pf, const PatchCache& cache, int f,
                                        const Eigen::Vector3d& p, double* lambda) noexcept {
  const int n = cache.faceSize(f), first = cache.faceOffsets[f];
  const Eigen::Vector3d d = p - pf.faceCentroid[f];
  meanValueCoordinates(&pf.corner2d[first], n, {d.dot(pf.faceU[f]), d.dot(pf.faceV[f])}, lambda);
  Eigen::Vector3d N = Eigen::Vector3d::Zero();
  for (int k = 0; k < n; ++k)
    N += lambda[k] * Eigen::Vector3d(cache.cornerNormals[3 * (first + k)], cache.cornerNormals[3 * (first + k) + 1],
                                     cache.cornerNormals[3 * (first + k) + 2]);
  const double len = N.norm();
  return len > 1e-12 ? Eigen::Vector3d(N / len) : pf.faceNormal[f];
}

}  // namespace sf
