// SPDX-License-Identifier: Apache-2.0
// Small closed polyhedra for reference tests: vertices, CCW-from-outside faces, unit
// vertex normals. Independent of host/ mesh types on purpose (tests only).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "gregory_reference.h"

namespace sf::ref {

struct RefMesh {
  std::vector<Eigen::Vector3d> positions;  ///< #V by 3
  std::vector<std::vector<int>> faces;     ///< #F polygons, CCW seen from outside
  std::vector<Eigen::Vector3d> normals;    ///< #V by 3, unit vertex normals
};

/// Cube with vertices (+-1, +-1, +-1)/sqrt(3) on the unit sphere, radial normals. 6 quads.
RefMesh refUnitSphereCube();
/// Regular icosahedron on the unit sphere, radial normals. 20 triangles.
RefMesh refIcosahedron();
/// Regular dodecahedron on the unit sphere, radial normals. 12 pentagons.
RefMesh refDodecahedron();
/// Irregular closed polytope: the unit-sphere cube (base = 0, quads, non-planar after the
/// jitter) or the icosahedron (base = 1, triangles), each vertex moved by a random vector
/// of length <= `jitter`, each radial normal tilted by `normalTiltDeg` degrees in a
/// random direction. Deterministic for a given seed (std::mt19937 raw output only).
RefMesh refJitteredPolytope(unsigned seed, int base = 0, double jitter = 0.1, double normalTiltDeg = 10.0);

/// A backward printed end tangent: a 2x2 grid of unit quads in z = 0 (vertex j*3+i at
/// (i, j, 0), faces CCW from +z) with +z normals except N4 (at (1,1,0)), tilted 75 degrees
/// towards V5 = (2,1,0) and then turned 60 degrees about the edge towards +y, and N5, turned
/// 60 degrees about the edge towards -y. Tilting along the edge alone cannot do it: with P
/// the projection perpendicular to e, t_s . e has the sign of P N_k . (P N_k + P N_{k+1}).
/// The guard fires on edge V4 -> V5 (edge 0 of face 3, edge 2 of face 1).
RefMesh refTwistedStrip();

/// Patch of face f of a mesh.
RefPatch refFacePatch(const RefMesh& m, int f, CrossTangent mode = CrossTangent::Corrected);

/// Across edge k of face f (V_k -> V_{k+1}) lies edge `edge` of face `face`, run the
/// other way (W_edge = V_{k+1}, W_{edge+1} = V_k); face = -1 on a boundary edge.
struct RefEdgeNeighbour {
  int face = -1, edge = -1;
};
/// result[f][k] for every face f and edge k.
std::vector<std::vector<RefEdgeNeighbour>> refEdgeNeighbours(const RefMesh& m);

/// Rotate unit vector n by `deg` degrees towards unit direction `dir` (in the plane of n
/// and dir; dir need not be perpendicular to n).
Eigen::Vector3d refTiltToward(const Eigen::Vector3d& n, const Eigen::Vector3d& dir, double deg);

}  // namespace sf::ref
