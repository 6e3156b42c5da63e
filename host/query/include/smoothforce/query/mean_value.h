// SPDX-License-Identifier: Apache-2.0
// Mean value coordinates on n-gons, and the map from a polygon point to its patch's domain
// point (design page, "Polygon point -> domain point"; paper Section 4.1, step 3).
#pragma once

#include <Eigen/Core>

#include <smoothforce/patch/patch_eval.h>  // the domain: domainCorner, clampToDomain
#include <smoothforce/query/polygon_facets.h>

namespace sf {

/// Mean value coordinates (Floater 2003; the robust form of Hormann & Floater 2006) of x with
/// respect to the planar polygon poly[0..n) (any simple polygon, convex or not): writes n
/// weights lambda summing to 1 with sum lambda_k poly_k = x. Exact on the boundary: a vertex
/// gives the unit vector, a point on an edge the linear interpolation of its two ends (no
/// NaN). A degenerate configuration (zero total weight) gives the nearest vertex.
void meanValueCoordinates(const Eigen::Vector2d* poly, int n, const Eigen::Vector2d& x, double* lambda) noexcept;

/// The domain point of a point p on (or near) face f: p is projected on the face's best-fit
/// plane, lambda = its mean value coordinates w.r.t. the projected polygon (lambda: scratch of
/// at least faceSize(f) doubles, receives them), X = sum lambda_k C_k, clamped into the
/// domain (a non-convex face can give negative weights and a point outside).
Eigen::Vector2d polygonToDomain(const PolygonFacets& pf, const PatchCache& cache, int f, const Eigen::Vector3d& p,
                                double* lambda) noexcept;

/// Normal interpolated at p on face f from its corner normals with the mean value coordinates
/// of polygonToDomain (force shading): unit(sum lambda_k N_k); the face normal if that vanishes.
Eigen::Vector3d interpolateCornerNormal(const PolygonFacets& pf, const PatchCache& cache, int f,
                                        const Eigen::Vector3d& p, double* lambda) noexcept;

}  // namespace sf
