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

/// True when every component is finite, the scale is > 0 and the quaternion is not zero
/// (it is normalised where it is used).
inline bool isValid(const Pose& p) noexcept {
  return p.scale > 0 && std::isfinite(p.scale) && p.translation.allFinite() && p.rotation.coeffs().allFinite() &&
         p.rotation.norm() > 1e-12;
}

}  // namespace sf::rt
