// SPDX-License-Identifier: Apache-2.0
// Domain sampling and G1 measurement helpers for reference tests (tests only).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "gregory_reference.h"
#include "ref_shapes.h"

namespace sf::ref {

/// Triangular-fan samples of the regular n-gon domain: for each triangle (O, C_k, C_{k+1})
/// the points (i C_k + j C_{k+1}) / m, i + j <= m. Contains the centre, the corners and,
/// for even m, the edge midpoints; points on the spokes appear more than once.
std::vector<Eigen::Vector2d> refDomainSamples(int n, int m);

/// Point at parameter s in [0, 1] along domain edge k (C_k -> C_{k+1}), moved `inset`
/// into the domain along -m_k.
Eigen::Vector2d refDomainEdgePoint(int n, int k, double s, double inset);

/// Angle between two tangent planes given their normals: arccos |n0 . n1|, computed as
/// atan2(|n0 x n1|, |n0 . n1|) so that tiny angles keep their precision. Radians.
double refTangentPlaneAngle(const Eigen::Vector3d& n0, const Eigen::Vector3d& n1);

/// max |r - 1| (r = distance from the origin) over the patches of a mesh, sampled with
/// refDomainSamples(n, grid) (face centres, corners and, for even grid, edge midpoints
/// included), at the face centres alone, and over the flat faces (the same fan grid laid on
/// each polygon around its vertex centroid).
struct RefSphereDeviation {
  double patch = 0, centre = 0, flat = 0;
};
RefSphereDeviation refSphereDeviation(const RefMesh& m, CrossTangent mode, int grid);

/// Tangent-plane jump across shared edges of a closed or open mesh, every face using
/// `mode`. Edge k of face f at s = (i + 0.5) / samples, i < samples, is matched with
/// s' = 1 - s on the neighbour's edge; both points are `inset` inside their domains.
class RefEdgeJumpMeter {
 public:
  RefEdgeJumpMeter(const RefMesh& m, CrossTangent mode);
  /// Max over the samples of one edge (face f, edge k); 0 on a boundary edge.
  double edgeJump(int f, int k, double inset, int samples = 9) const;
  /// Max over all shared edges.
  double maxJump(double inset, int samples = 9) const;

 private:
  std::vector<RefPatchEvaluator> eval_;
  std::vector<std::vector<RefEdgeNeighbour>> nb_;
};

}  // namespace sf::ref
