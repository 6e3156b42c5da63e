// SPDX-License-Identifier: Apache-2.0
// A similarity transform (uniform scale, rotation, translation): object and device poses.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace sf::rt {

/// A similarity from a local frame to the world: world = translation + rotation * (scale * local).
/// Objects use it object-to-world (scene.h), the device device-to-world (device_transform.h).
struct Pose {
  Eigen::Vector3d translation{0, 0, 0};                          ///< m
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();  ///< unit quaternion
  double scale = 1;                                              ///< uniform, > 0
};

/// The scales a scene file may give (an object's pose, the device transform; scene.h): 1e-9 to
/// 1e9, enough to convert units (a model in nanometres, a device in millimetres, a model in
/// kilometres) with room to spare. Within them a workspace of metres maps far inside the
/// coordinate range (1e15 m), and a scaled model keeps its double-precision detail; beyond
/// them 1e300 overflowed the HIP to infinity and 1e-300 shrank a model to nothing.
inline constexpr double kMinSceneScale = 1e-9, kMaxSceneScale = 1e9;

/// True when every component is finite, the scale is > 0 and the quaternion is not zero and
/// normalises (it is normalised where it is used): its norm within [1e-12, 1e150], so that the
/// squared norm neither underflows nor overflows.
inline bool isValid(const Pose& p) noexcept {
  const double n = p.rotation.coeffs().stableNorm();
  return p.scale > 0 && std::isfinite(p.scale) && p.translation.allFinite() && p.rotation.coeffs().allFinite() &&
         n > 1e-12 && n < 1e150;
}

}  // namespace sf::rt
