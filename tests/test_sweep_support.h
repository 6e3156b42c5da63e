// SPDX-License-Identifier: Apache-2.0
// Shared pieces of the sweep tests: a quad-sphere patch cache and analytic fake renderers.
#pragma once

#include <Eigen/Geometry>
#include <atomic>
#include <memory>
#include <string>

#include <smoothforce/force/force_method.h>
#include <smoothforce/mesh/normals.h>
#include <smoothforce/patch/patch_cache.h>
#include <smoothforce/sweep/generators.h>

namespace sf::sweeptest {

/// Patches of the generated quad-sphere (radius r, 6 n^2 quads, exact normals).
inline std::shared_ptr<const PatchCache> sphereCache(double radius = 1, int n = 3) {
  const PolygonMesh mesh = quadSphere(radius, n).toPolygonMesh();
  PatchCache c = preparePatchCache(mesh, cornerNormals(mesh, NormalMode::Auto), PatchOptions{}, 0);
  constructPatches(c, Backend::Serial);
  return std::make_shared<const PatchCache>(std::move(c));
}

/// A solid sphere at the origin: F = k (r - |x|) x / |x| inside. Counts its calls, and checks
/// the sweep's protocol: every probe starts with reset() and an out-of-contact step.
class FakeSphere final : public ForceRenderer {
 public:
  FakeSphere(double radius, double k, bool faceted = false, std::atomic<int>* protocolErrors = nullptr)
      : r_(radius), k_(k), faceted_(faceted), errors_(protocolErrors) {}
  ForceSample step(const Eigen::Vector3d& hip) noexcept override {
    ++steps;
    ForceSample s;
    const double d = hip.norm();
    if (sinceReset == 0 && d < r_ && errors_) ++*errors_;   // the approach step must be outside
    if (sinceReset == 1 && d >= r_ && errors_) ++*errors_;  // the second step is the pressed-in HIP
    if (sinceReset >= 2 && errors_) ++*errors_;             // and then the next probe resets
    ++sinceReset;
    if (d >= r_ || d == 0) return s;
    Eigen::Vector3d n = hip / d;
    if (faceted_) {  // the normal of the cube face region: jumps across the cube's edges
      int a = 0;
      n.cwiseAbs().maxCoeff(&a);
      n = Eigen::Vector3d::Unit(a) * (hip[a] > 0 ? 1 : -1);
    }
    s.contact = true;
    s.normal = n;
    s.scp = hip + (r_ - d) * n;
    s.force = k_ * (r_ - d) * n;
    s.iterations = 1;
    return s;
  }
  void reset() noexcept override { sinceReset = 0; }
  int patchesBuilt() const noexcept override { return 0; }
  int steps = 0, sinceReset = 0;

 private:
  double r_, k_;
  bool faceted_;
  std::atomic<int>* errors_;
};

}  // namespace sf::sweeptest
