// SPDX-License-Identifier: Apache-2.0
// Where the device's workspace sits in the scene: the device-to-world similarity.
#pragma once

#include <Eigen/Core>
#include <string>

#include <smoothforce/runtime/pose.h>

namespace sf::rt {

/// Maps device coordinates to the world: world = translation + rotation * (scale * device),
/// a Pose read device-to-world. The servo step maps every HIP read from the device with
/// toWorld() and every force it commands with forceToDevice().
///
/// Forces only rotate: newtons are not scaled. A device displacement d moves the HIP by
/// scale * d in the world, so a surface of stiffness k (N per world metre, the objects'
/// `stiffness`) is felt at the device as k * scale N per device metre. To present stiffness
/// K at the handle (bounded by what the device renders stably, e.g. about 1-2 kN/m for a
/// 3D Systems Touch), give the objects k = K / scale. The safety limits (maxForce,
/// maxForceStep, newtons) apply to the commanded force and are not scaled either. Example:
/// an OpenHaptics device reports millimetres, so scale = 0.001 maps them to metres.
class DeviceTransform {
 public:
  /// The identity (device frame = world frame).
  DeviceTransform() = default;
  /// Throws InputError ("device transform: ...") unless the pose is finite with scale > 0
  /// and a non-zero quaternion (normalised here).
  explicit DeviceTransform(const Pose& deviceToWorld);

  /// Device point (m, device frame) to world point (m).
  Eigen::Vector3d toWorld(const Eigen::Vector3d& device) const noexcept { return t_ + s_ * (r_ * device); }
  /// World point to device point: rotation^T (world - translation) / scale.
  Eigen::Vector3d toDevice(const Eigen::Vector3d& world) const noexcept { return (r_.transpose() * (world - t_)) / s_; }
  /// World force (N) to device force (N): rotation^T f (no scaling, see above).
  Eigen::Vector3d forceToDevice(const Eigen::Vector3d& f) const noexcept { return r_.transpose() * f; }
  /// Device force to world force: rotation f.
  Eigen::Vector3d forceToWorld(const Eigen::Vector3d& f) const noexcept { return r_ * f; }

  const Pose& pose() const noexcept { return pose_; }
  double scale() const noexcept { return s_; }
  bool isIdentity() const noexcept;
  /// "identity" or "scale S, rotation A rad about (x, y, z), translation (x, y, z) m".
  std::string describe() const;

 private:
  Pose pose_;
  Eigen::Matrix3d r_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t_ = Eigen::Vector3d::Zero();
  double s_ = 1;
};

}  // namespace sf::rt
