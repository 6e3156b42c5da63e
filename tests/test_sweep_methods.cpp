// Sweeps with the real force methods (makeForceRenderer) on the generated quad-sphere.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>

#include <smoothforce/sweep/sweep_metrics.h>
#include <smoothforce/sweep/sweep_run.h>
#include "test_sweep_support.h"

namespace sf {
namespace {

struct MethodMetrics {
  Discontinuity disc;
  size_t contact = 0;
};

/// Discontinuity of one method and depth group, as the summary computes it.
MethodMetrics metrics(const SweepData& d, size_t method, size_t group) {
  const size_t n = d.config.samples;
  std::vector<Eigen::Vector3d> pos, dir;
  std::vector<char> valid;
  MethodMetrics m;
  for (size_t s = 0; s < n; ++s) {
    const HipResult& r = d.results[method][group * n + s];
    const Eigen::Vector3d f(r.force[0], r.force[1], r.force[2]);
    pos.push_back(d.hips[group * n + s]);
    dir.push_back(f);
    valid.push_back(r.contact && f.norm() > 0);
    m.contact += r.contact;
  }
  const double spacing = std::sqrt(d.config.area / static_cast<double>(n));
  m.disc = forceDiscontinuity(pos, dir, valid, 8, 10 * std::numbers::pi / 180, spacing);
  return m;
}

SweepInputs sphereInputs() {
  SweepInputs in;
  in.cache = sweeptest::sphereCache(1.0, 3);  // 54 quads: 30 degrees between neighbouring faces
  in.config.source = "quad-sphere";
  in.config.methods = {"patch", "direct", "shading"};
  in.config.samples = 4000;
  in.config.seed = 5;
  in.config.trajectories = {};
  in.depths = parseDepthList("2%");
  return in;
}

TEST(SweepMethods, PatchIsSmoothDirectIsNot) {
  const SweepData d = runSweep(sphereInputs(), {});
  const MethodMetrics patch = metrics(d, 0, 0), direct = metrics(d, 1, 0);
  EXPECT_GT(patch.contact, 3900u);
  EXPECT_GT(direct.contact, 3900u);
  // Patch: the force turns with the surface, about 1 / (R - depth) ~ 1.07 rad/m here, and no
  // neighbour pair differs by 10 degrees within a sample spacing (0.056 m ~ 3.4 degrees).
  EXPECT_EQ(patch.disc.flaggedPairs, 0u);
  EXPECT_LT(patch.disc.stats.max, 10.0);
  EXPECT_LT(patch.disc.maxAngle, 10 * std::numbers::pi / 180);
  // Direct (god-object on the quads): the face normal jumps by up to 30 degrees across edges.
  EXPECT_GT(direct.disc.flaggedPairs, 10u);
  EXPECT_GT(direct.disc.stats.max, 3 * patch.disc.stats.max);
  EXPECT_GT(direct.disc.maxAngle, 20 * std::numbers::pi / 180);
  // The sweep's trajectory half-step test tells the same (checked by the summary elsewhere).
}

TEST(SweepMethods, ThreadCountsGiveIdenticalResults) {
  SweepInputs a = sphereInputs(), b = sphereInputs();
  a.config.samples = b.config.samples = 800;
  SweepControl one, two;
  one.threads = 1;
  two.threads = 2;
  const SweepData x = runSweep(a, one), y = runSweep(b, two);
  for (size_t m = 0; m < x.results.size(); ++m) {
    ASSERT_EQ(x.results[m].size(), y.results[m].size());
    EXPECT_EQ(0, std::memcmp(x.results[m].data(), y.results[m].data(), x.results[m].size() * sizeof(HipResult)))
        << x.config.methods[m];
  }
}

}  // namespace
}  // namespace sf
