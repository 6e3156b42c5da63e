// SPDX-License-Identifier: Apache-2.0
// A cube whose file normal at one corner is turned until its patches overlap: the fold repair's
// normal search has something to remove in milliseconds (test_normal_search.cpp, test_capi.cpp).
#pragma once

#include <Eigen/Geometry>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

namespace sf::test {

/// Writes cube_<tilt>.obj into `dir`: a cube (2 m) with radial file normals, vertex 7's turned by
/// `tiltDeg` about (1, -1, 0) (past about 80 degrees its patches overlap). Returns its path.
inline std::string writeTiltedCube(const std::filesystem::path& dir, double tiltDeg) {
  const std::filesystem::path p = dir / ("cube_" + std::to_string(int(tiltDeg)) + ".obj");
  std::ofstream o(p);
  std::vector<Eigen::Vector3d> v;
  for (int x : {-1, 1})
    for (int y : {-1, 1})
      for (int z : {-1, 1}) v.emplace_back(x, y, z);
  const Eigen::AngleAxisd tilt(tiltDeg * std::numbers::pi / 180, Eigen::Vector3d(1, -1, 0).normalized());
  char line[160];
  for (const auto& p3 : v) o << "v " << p3.x() << ' ' << p3.y() << ' ' << p3.z() << '\n';
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d n = i == 7 ? Eigen::Vector3d(tilt * v[i].normalized()) : v[i].normalized();
    std::snprintf(line, sizeof line, "vn %.17g %.17g %.17g\n", n.x(), n.y(), n.z());
    o << line;
  }
  for (const auto& f : {std::array{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}}) {
    o << 'f';
    for (int k : f) o << ' ' << k + 1 << "//" << k + 1;
    o << '\n';
  }
  return p.string();
}

}  // namespace sf::test
