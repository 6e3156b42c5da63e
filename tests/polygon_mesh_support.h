// SPDX-License-Identifier: Apache-2.0
// Polygon meshes written in code, for the mesh-level tests (checks, normals) and the creased
// solids of the crease and fold repair tests.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <string>
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

/// A closed solid of revolution over a regular n-gon: rings of n vertices at the profile's
/// (radius, height) points, side quads between consecutive rings, an n-gon cap at each end.
/// The rings listed in `creased` are tagged crease rims (OpenSubdiv `t crease`, 0-based), as
/// are the caps' rims: flat caps and annuli meet curved sides at ridges, and a step in (a
/// smaller radius above a larger) at a valley.
inline std::string turnedObj(int n, const std::vector<std::array<double, 2>>& profile,
                             const std::vector<int>& creased) {
  std::string s;
  const int rings = static_cast<int>(profile.size());
  for (const auto& [radius, z] : profile)
    for (int i = 0; i < n; ++i) {
      const double a = 2 * std::numbers::pi * i / n;
      char buf[96];
      std::snprintf(buf, sizeof buf, "v %.17g %.17g %.17g\n", radius * std::cos(a), radius * std::sin(a), z);
      s += buf;
    }
  for (int r : creased)
    for (int i = 0; i < n; ++i)
      s += "t crease 2/1/0 " + std::to_string(r * n + i) + " " + std::to_string(r * n + (i + 1) % n) + " 10\n";
  s += "f";
  for (int i = n - 1; i >= 0; --i) s += " " + std::to_string(i + 1);
  s += "\nf";
  for (int i = 0; i < n; ++i) s += " " + std::to_string((rings - 1) * n + i + 1);
  s += "\n";
  for (int r = 0; r + 1 < rings; ++r)
    for (int i = 0; i < n; ++i) {
      const int j = (i + 1) % n;
      s += "f " + std::to_string(r * n + i + 1) + " " + std::to_string(r * n + j + 1) + " " +
           std::to_string((r + 1) * n + j + 1) + " " + std::to_string((r + 1) * n + i + 1) + "\n";
    }
  return s;
}

}  // namespace sf::test
