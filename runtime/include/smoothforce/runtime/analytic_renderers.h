// SPDX-License-Identifier: Apache-2.0
// Analytic force fields behind the ForceRenderer interface: for tests, benchmarks and for
// exercising devices and the loop without patches.
#pragma once

#include <Eigen/Geometry>

#include <smoothforce/force/force_method.h>

namespace sf::rt {

/// The half-space n . x <= d is solid: inside, F = k (d - n . x) n (penalty force towards
/// the plane), SCP = the HIP projected on the plane. Units: m, N/m, N.
class PlaneRenderer final : public ForceRenderer {
 public:
  PlaneRenderer(const Eigen::Vector3d& normal, double offset, double stiffness)
      : n_(normal.normalized()), d_(offset), k_(stiffness) {}
  ForceSample step(const Eigen::Vector3d& hip) noexcept override {
    ForceSample s;
    const double pen = d_ - n_.dot(hip);
    if (pen > 0) {
      s.contact = true;
      s.scp = hip + pen * n_;
      s.normal = n_;
      s.force = k_ * pen * n_;
    }
    return s;
  }
  void reset() noexcept override {}
  int patchesBuilt() const noexcept override { return 0; }

 private:
  Eigen::Vector3d n_;
  double d_, k_;
};

/// A solid sphere: inside, F = k (r - |x - c|) (x - c) / |x - c|, SCP on the sphere.
class SphereRenderer final : public ForceRenderer {
 public:
  SphereRenderer(const Eigen::Vector3d& centre, double radius, double stiffness)
      : c_(centre), r_(radius), k_(stiffness) {}
  ForceSample step(const Eigen::Vector3d& hip) noexcept override {
    ForceSample s;
    const Eigen::Vector3d d = hip - c_;
    const double dist = d.norm();
    if (dist < r_) {
      const Eigen::Vector3d n = dist > 0 ? Eigen::Vector3d(d / dist) : Eigen::Vector3d::UnitZ();
      s.contact = true;
      s.normal = n;
      s.scp = c_ + r_ * n;
      s.force = k_ * (r_ - dist) * n;
    }
    return s;
  }
  void reset() noexcept override {}
  int patchesBuilt() const noexcept override { return 0; }

 private:
  Eigen::Vector3d c_;
  double r_, k_;
};

}  // namespace sf::rt
