// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/query/polygon_facets.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace sf {
namespace {

/// Faces of up to this many corners get their exact diameter (all pairs); larger ones (no patch
/// is built beyond GP_MAX_N = 64 sides) their corners' box diagonal: a face of 10^6 corners took
/// hours in the pairwise loop.
constexpr int kExactDiameterCorners = 256;

Eigen::Vector3d vertexOf(const PatchCache& c, int v) {
  return {c.positions[3 * v], c.positions[3 * v + 1], c.positions[3 * v + 2]};
}

/// Unit vector perpendicular to n, preferring the direction of `hint`.
Eigen::Vector3d perpendicular(const Eigen::Vector3d& n, const Eigen::Vector3d& hint) {
  Eigen::Vector3d u = hint - hint.dot(n) * n;
  if (u.norm() > 1e-300 && u.norm() > 1e-12 * hint.norm()) return u.normalized();
  u = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return (u - u.dot(n) * n).normalized();
}

void addFacet(PolygonFacets& pf, int f, const Eigen::Vector3d& origin, const Eigen::Vector3d& normal,
              const Eigen::Vector3d* verts, int n, double tolerance) {
  const Eigen::Vector3d u = perpendicular(normal, verts[0] - origin), v = normal.cross(u);
  pf.facetOrigin.push_back(origin);
  pf.facetNormal.push_back(normal);
  pf.facetU.push_back(u);
  pf.facetV.push_back(v);
  pf.facetFace.push_back(f);
  pf.facetTolerance.push_back(tolerance);
  for (int k = 0; k < n; ++k) {
    pf.facetVert3d.push_back(verts[k]);
    pf.facetVert2d.emplace_back((verts[k] - origin).dot(u), (verts[k] - origin).dot(v));
  }
  pf.facetVertOffsets.push_back(static_cast<int32_t>(pf.facetVert3d.size()));
}

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

double segmentDistance2d(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& q) {
  const Eigen::Vector2d e = b - a;
  const double l2 = e.squaredNorm();
  const double t = l2 > 0 ? std::clamp((q - a).dot(e) / l2, 0.0, 1.0) : 0.0;
  return (a + t * e - q).norm();
}

Eigen::Vector2d inPlane(const PolygonFacets& pf, int i, const Eigen::Vector3d& p) {
  const Eigen::Vector3d d = p - pf.facetOrigin[i];
  return {d.dot(pf.facetU[i]), d.dot(pf.facetV[i])};
}

}  // namespace

PolygonFacets buildPolygonFacets(const PatchCache& cache, double planarTolerance) {
  PolygonFacets pf;
  const int nf = cache.numFaces();
  referencedBox(cache, pf.boxMin, pf.boxMax);
  pf.planeTolerance = 1e-10 * pf.extent() + 1e-300;
  pf.faceCentroid.resize(nf);
  pf.faceNormal.resize(nf);
  pf.faceU.resize(nf);
  pf.faceV.resize(nf);
  pf.facePlanarity.resize(nf);
  pf.faceDiameter.resize(nf);
  pf.corner2d.resize(cache.numSlots());
  std::vector<Eigen::Vector3d> V;
  for (int f = 0; f < nf; ++f) {
    const int n = cache.faceSize(f), first = cache.faceOffsets[f];
    V.resize(n);
    Eigen::Vector3d c = Eigen::Vector3d::Zero(), N = Eigen::Vector3d::Zero();
    for (int k = 0; k < n; ++k) c += (V[k] = vertexOf(cache, cache.faceVertices[first + k]));
    c /= n;
    for (int k = 0; k < n; ++k) N += (V[k] - c).cross(V[(k + 1) % n] - c);  // Newell, about the centroid
    double diam = 0;
    if (n <= kExactDiameterCorners) {
      for (int a = 0; a < n; ++a)
        for (int b = a + 1; b < n; ++b) diam = std::max(diam, (V[a] - V[b]).norm());
    } else {  // the corners' box diagonal: between 1 and sqrt(3) diameters, in linear time
      Eigen::Vector3d lo = V[0], hi = V[0];
      for (int k = 1; k < n; ++k) {
        lo = lo.cwiseMin(V[k]);
        hi = hi.cwiseMax(V[k]);
      }
      diam = (hi - lo).norm();
    }
    const bool flat = !(N.norm() > 1e-14 * diam * diam);  // zero-area face: any frame
    N = flat ? Eigen::Vector3d::UnitZ() : N.normalized();
    const Eigen::Vector3d u = perpendicular(N, V[0] - c), v = N.cross(u);
    double dev = 0;
    for (int k = 0; k < n; ++k) {
      dev = std::max(dev, std::abs((V[k] - c).dot(N)));
      pf.corner2d[first + k] = {(V[k] - c).dot(u), (V[k] - c).dot(v)};
    }
    pf.faceCentroid[f] = c;
    pf.faceNormal[f] = N;
    pf.faceU[f] = u;
    pf.faceV[f] = v;
    pf.faceDiameter[f] = diam;
    pf.facePlanarity[f] = diam > 0 ? dev / diam : 0;
    const double baseTol = 1e-7 * diam + pf.planeTolerance;
    if (flat || pf.facePlanarity[f] <= planarTolerance || n == 3) {
      addFacet(pf, f, c, N, V.data(), n, baseTol + 2 * dev);
    } else {
      for (int k = 0; k < n; ++k) {
        const Eigen::Vector3d tri[3] = {c, V[k], V[(k + 1) % n]};
        Eigen::Vector3d tn = (tri[1] - c).cross(tri[2] - c);
        tn = tn.norm() > 1e-14 * diam * diam ? tn.normalized() : N;
        addFacet(pf, f, c, tn, tri, 3, baseTol);
      }
    }
    pf.faceFacetOffsets.push_back(static_cast<int32_t>(pf.facetFace.size()));
  }
  return pf;
}

bool insidePolygon2d(const Eigen::Vector2d* poly, int n, const Eigen::Vector2d& q) noexcept {
  int wn = 0;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d& a = poly[i];
    const Eigen::Vector2d& b = poly[(i + 1) % n];
    const double side = cross2(b - a, q - a);
    if (a.y() <= q.y()) {
      if (b.y() > q.y() && side > 0) ++wn;
    } else if (b.y() <= q.y() && side < 0) {
      --wn;
    }
  }
  return wn != 0;
}

Eigen::Vector3d nearestOnSegment(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                 const Eigen::Vector3d& p) noexcept {
  const Eigen::Vector3d e = b - a;
  const double l2 = e.squaredNorm();
  const double t = l2 > 0 ? std::clamp((p - a).dot(e) / l2, 0.0, 1.0) : 0.0;
  return a + t * e;
}

bool nearestOnFace(const PolygonFacets& pf, int f, const Eigen::Vector3d& p, Eigen::Vector3d& best, double& bestDist2,
                   int& bestFacet) noexcept {
  bool improved = false;
  for (int i = pf.faceFacetOffsets[f]; i < pf.faceFacetOffsets[f + 1]; ++i) {
    const int v0 = pf.facetVertOffsets[i], n = pf.facetVertOffsets[i + 1] - v0;
    const double s = (p - pf.facetOrigin[i]).dot(pf.facetNormal[i]);
    if (s * s >= bestDist2) continue;  // the plane is already farther than the best point
    if (insidePolygon2d(&pf.facetVert2d[v0], n, inPlane(pf, i, p))) {
      best = p - s * pf.facetNormal[i];
      bestDist2 = s * s;
      bestFacet = i;
      improved = true;
      continue;
    }
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector3d q = nearestOnSegment(pf.facetVert3d[v0 + k], pf.facetVert3d[v0 + (k + 1) % n], p);
      const double d2 = (q - p).squaredNorm();
      if (d2 < bestDist2) {
        best = q;
        bestDist2 = d2;
        bestFacet = i;
        improved = true;
      }
    }
  }
  return improved;
}

double facetOutsideDistance(const PolygonFacets& pf, int i, const Eigen::Vector3d& p) noexcept {
  const int v0 = pf.facetVertOffsets[i], n = pf.facetVertOffsets[i + 1] - v0;
  const Eigen::Vector2d q = inPlane(pf, i, p);
  const Eigen::Vector2d* poly = &pf.facetVert2d[v0];
  if (insidePolygon2d(poly, n, q)) return 0;
  double d = 1e300;
  for (int k = 0; k < n; ++k) d = std::min(d, segmentDistance2d(poly[k], poly[(k + 1) % n], q));
  return d;
}

bool segmentEntersFacet(const PolygonFacets& pf, int i, const Eigen::Vector3d& a, const Eigen::Vector3d& b, double& t,
                        bool through) noexcept {
  const double tol = pf.planeTolerance;
  const double sa = (a - pf.facetOrigin[i]).dot(pf.facetNormal[i]);
  const double sb = (b - pf.facetOrigin[i]).dot(pf.facetNormal[i]);
  if (!(sa >= -tol && sb < -tol)) return false;
  t = sa <= 0 ? 0.0 : std::min(1.0, sa / (sa - sb));
  if (facetOutsideDistance(pf, i, a + t * (b - a)) > pf.facetTolerance[i]) return false;
  if (!through || sa > tol) return true;
  // a on the plane: a touch of the facet's boundary counts only when the segment goes on
  // through the facet, not when it dives behind the plane beside it (a proxy at a shared
  // vertex or edge that moves away from this facet). The probe may pass outside by 1/20 of
  // its length (3 degrees): along a fold between two facets it projects outside both.
  const double len = (b - a).norm(), probe = std::min(len, 1e-3 * pf.faceDiameter[pf.facetFace[i]]);
  return facetOutsideDistance(pf, i, a + (probe / len) * (b - a)) <= pf.facetTolerance[i] + 0.05 * probe;
}

}  // namespace sf
