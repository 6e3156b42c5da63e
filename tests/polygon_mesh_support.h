// SPDX-License-Identifier: Apache-2.0
// Polygon meshes written in code, for the mesh-level tests (checks, normals).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <utility>
#include <vector>

#include <smoothforce/mesh/mesh.h>

namespace sf::test {

/// A polygon mesh of these positions (m) and faces (vertex indices, in order).
inline PolygonMesh polygonMesh(std::vector<Eigen::Vector3d> p, const std::vector<std::vector<int32_t>>& faces) {
  PolygonMesh m;
  m.positions = std::move(p);
  for (const auto& f : faces) m.addFace(f);
  return m;
}

/// [-1,1]^3 with outward quads.
inline PolygonMesh cubeMesh() {
  std::vector<Eigen::Vector3d> p;
  for (int i = 0; i < 8; ++i) p.emplace_back(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
  return polygonMesh(p, {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}});
}

}  // namespace sf::test
