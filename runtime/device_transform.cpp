// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/runtime/device_transform.h>

#include <cstdio>

#include <smoothforce/mesh/mesh.h>

namespace sf::rt {

DeviceTransform::DeviceTransform(const Pose& p) {
  if (!isValid(p))
    throw InputError("device transform: expected a finite translation, a non-zero rotation and a scale > 0");
  pose_ = p;
  pose_.rotation.normalize();
  r_ = pose_.rotation.toRotationMatrix();
  t_ = pose_.translation;
  s_ = pose_.scale;
}

bool DeviceTransform::isIdentity() const noexcept { return s_ == 1 && t_.isZero(0) && r_.isIdentity(0); }

std::string DeviceTransform::describe() const {
  if (isIdentity()) return "identity";
  const Eigen::AngleAxisd aa(pose_.rotation);
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "scale %g, rotation %.6g rad about (%.4g, %.4g, %.4g), translation (%.6g, %.6g, %.6g) m", s_,
                aa.angle(), aa.axis().x(), aa.axis().y(), aa.axis().z(), t_.x(), t_.y(), t_.z());
  return buf;
}

}  // namespace sf::rt
