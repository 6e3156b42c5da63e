// SPDX-License-Identifier: Apache-2.0
// The base polygons as planar pieces ("facets") with exact double-precision point and
// segment queries: what the Embree scene, the god-object and the MVC mapping share.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include <smoothforce/base/memory_bytes.h>
#include <smoothforce/patch/patch_cache.h>

namespace sf {

/// Faces whose max distance to their best-fit plane is at most this fraction of their
/// diameter are one facet: the polygon projected on that plane (n-gon, not triangulated).
/// Faces above it (strongly non-planar; on the spot cage the median is 1.8%) are a fan of n
/// triangles (centroid, V_k, V_{k+1}), whose outer edges are the real mesh edges.
inline constexpr double kPlanarTolerance = 1e-3;

/// The god-object's facets (god_object.h): only faces flat to rounding stay one facet, so
/// that adjacent facets meet on the real 3D edges. A projected facet lies up to
/// planarity * diameter off its face's vertices, which leaves a gap or an overlap of about
/// that much / sin(dihedral angle) at every edge it shares: on the 5 mm tube of the 10 cm
/// torus knot (kPlanarTolerance facets) the proxy slid off a facet through such a gap into
/// the solid and lost contact. At 1e-12 the gaps stay below the facets' in-plane tolerance
/// (1e-7 diameter) down to dihedral angles of 1e-5 rad.
inline constexpr double kWatertightPlanarTolerance = 1e-12;

/// Facets of all faces, struct of arrays. #F faces, #C corners, #P facets.
/// Face frame: centroid c, Newell normal n (outward for counter-clockwise faces), axes u, v;
/// corner2d[c] = ((V - c).u, (V - c).v) for corner c (#C) - the projected polygon.
/// Facet i: plane (origin, normal) and axes; vertices facetVert3d/2d[facetVertOffsets[i]..];
/// for a one-facet face these are the face's real vertices and their projections.
struct PolygonFacets {
  std::vector<Eigen::Vector3d> faceCentroid, faceNormal, faceU, faceV;  ///< #F
  std::vector<double> facePlanarity;         ///< #F: max |distance to best-fit plane| / diameter
  std::vector<double> faceDiameter;          ///< #F, m (beyond 256 corners: the corners' box diagonal)
  std::vector<int32_t> faceFacetOffsets{0};  ///< #F+1
  std::vector<Eigen::Vector2d> corner2d;     ///< #C
  std::vector<Eigen::Vector3d> facetOrigin, facetNormal, facetU, facetV;  ///< #P
  std::vector<int32_t> facetFace;                                         ///< #P
  std::vector<double> facetTolerance;        ///< #P: inflation (m) of the closed in-facet test for crossings
  std::vector<int32_t> facetVertOffsets{0};  ///< #P+1
  std::vector<Eigen::Vector3d> facetVert3d;
  std::vector<Eigen::Vector2d> facetVert2d;
  Eigen::Vector3d boxMin{0, 0, 0}, boxMax{0, 0, 0};  ///< of the referenced vertices (referencedBox)
  double planeTolerance = 0;                         ///< m: |signed distance| below this counts as on a plane

  int numFaces() const { return static_cast<int>(faceFacetOffsets.size()) - 1; }
  int numFacets() const { return static_cast<int>(facetFace.size()); }
  /// Bytes held by the arrays.
  size_t bytes() const noexcept {
    return vectorBytes(faceCentroid, faceNormal, faceU, faceV, facePlanarity, faceDiameter, faceFacetOffsets, corner2d,
                       facetOrigin, facetNormal, facetU, facetV, facetFace, facetTolerance, facetVertOffsets,
                       facetVert3d, facetVert2d);
  }
  bool isFan(int f) const { return faceFacetOffsets[f + 1] - faceFacetOffsets[f] > 1; }
  double extent() const { return (boxMax - boxMin).norm(); }
};

/// Builds the facets of the cache's base mesh. Zero-area faces keep a fallback frame and
/// are handled by the boundary distance. Never throws for geometry.
PolygonFacets buildPolygonFacets(const PatchCache& cache, double planarTolerance = kPlanarTolerance);

/// Nearest point of face f to p, exact in double: for a one-facet face the projection on the
/// best-fit plane when it falls inside the projected polygon (winding number, so non-convex
/// faces work), else the nearest point on the real 3D boundary edges; for a fan face the
/// nearest point over its triangles. Updates best/bestDist2/bestFacet when closer than bestDist2.
/// Returns true when it improved.
bool nearestOnFace(const PolygonFacets& pf, int f, const Eigen::Vector3d& p, Eigen::Vector3d& best, double& bestDist2,
                   int& bestFacet) noexcept;

/// The segment a -> b entering facet i from its front side: a on or in front of the plane
/// (signed distance >= -planeTolerance), b behind it (< -planeTolerance), the crossing point
/// inside the facet closed and inflated by facetTolerance. t in [0, 1] is the parameter.
/// through: when a lies on the plane (within planeTolerance) the segment must also go on
/// through the facet: its point q at 1e-3 of the face's diameter from a (or b) must project
/// into the facet inflated by facetTolerance + |q - a| / 20 (3 degrees of slack for folds),
/// so that a proxy sliding on other planes that only touches this facet's boundary (at a
/// shared vertex or edge) and moves away beside it does not enter it.
bool segmentEntersFacet(const PolygonFacets& pf, int facet, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                        double& t, bool through = false) noexcept;

/// Distance (m) in facet i's plane from the projection of p to the facet (0 inside).
double facetOutsideDistance(const PolygonFacets& pf, int facet, const Eigen::Vector3d& p) noexcept;

/// Nearest point to p on segment [a, b].
Eigen::Vector3d nearestOnSegment(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& p) noexcept;

/// Winding-number inside test of q in the polygon poly[0..n) (non-convex allowed).
bool insidePolygon2d(const Eigen::Vector2d* poly, int n, const Eigen::Vector2d& q) noexcept;

}  // namespace sf
