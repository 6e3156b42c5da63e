// SPDX-License-Identifier: Apache-2.0
// Sweeps with the real force methods (makeForceRenderer) on the generated quad-sphere.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <cstring>
#include <numbers>

#include <Eigen/Eigenvalues>

#include <smoothforce/patch/patch_eval.h>
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

/// Smallest and largest principal curvature (1/m, by magnitude) of the patch surface, sampled on
/// a grid of `grid` x `grid` domain points per face (those inside the domain, at least `inset`
/// from its boundary): the shape operator from central differences of the unit normal,
/// dN = -S dG in the tangent basis (G_xi, G_eta).
struct CurvatureRange {
  double min = 1e300, max = 0;
  int points = 0;
};
CurvatureRange principalCurvatures(const PatchCache& c, int grid, double inset) {
  CurvatureRange r;
  const double h = 1e-5;
  for (int f = 0; f < c.numFaces(); ++f) {
    const int n = c.faceSize(f);
    for (int i = 0; i < grid; ++i)
      for (int j = 0; j < grid; ++j) {
        const double x = -1 + 2 * (i + 0.5) / grid, y = -1 + 2 * (j + 0.5) / grid;
        if (!insideDomain(n, x, y, -inset)) continue;
        const PatchPoint p = evaluatePatch(c, f, x, y);
        const Eigen::Vector3d dNx =
            (evaluatePatch(c, f, x + h, y).normal - evaluatePatch(c, f, x - h, y).normal) / (2 * h);
        const Eigen::Vector3d dNy =
            (evaluatePatch(c, f, x, y + h).normal - evaluatePatch(c, f, x, y - h).normal) / (2 * h);
        Eigen::Matrix<double, 3, 2> J, D;
        J << p.dxi, p.deta;
        D << dNx, dNy;
        const Eigen::Matrix2d S = -(J.transpose() * J).ldlt().solve(J.transpose() * D);
        const Eigen::Vector2cd k = S.eigenvalues();
        for (int e = 0; e < 2; ++e) {
          r.min = std::min(r.min, std::abs(k[e].real()));
          r.max = std::max(r.max, std::abs(k[e].real()));
        }
        ++r.points;
      }
  }
  return r;
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
  const SweepInputs in = sphereInputs();
  const SweepData d = runSweep(in, {});
  const MethodMetrics patch = metrics(d, 0, 0), direct = metrics(d, 1, 0);
  EXPECT_GT(patch.contact, 3900u);
  EXPECT_GT(direct.contact, 3900u);
  // Patch: the force is the patch normal at the SCP, the foot point of a HIP at depth d, so
  // between neighbouring HIPs it turns at most at kappa / (1 - d kappa) rad/m for the largest
  // principal curvature kappa of the patch surface (the HIP moves by (1 - d kappa) of the SCP's
  // step), and at least at that rate of the smallest. On the unit sphere it would be
  // 1 / (1 - d) ~ 1.07 rad/m; the 54 patches' curvature ranges over about 0.48 .. 1.26 1/m.
  // Bounds with a 10% margin (the grid's sampling of the curvature, chords for arcs).
  const CurvatureRange k = principalCurvatures(*in.cache, 64, 0.0);
  const double depth = 0.02 * d.config.diagonal;
  const double upper = k.max / (1 - depth * k.max), lower = k.min / (1 - depth * k.min);
  std::printf(
      "  principal curvatures %.4f .. %.4f 1/m at %d points; depth %.4f m; turn rate %.4f .. %.4f rad/m; "
      "measured p50 %.4f, p99 %.4f, max %.4f rad/m\n",
      k.min, k.max, k.points, depth, lower, upper, patch.disc.stats.p50, patch.disc.stats.p99, patch.disc.stats.max);
  int strictly = 0, onBoundary = 0;  // grid points inside a quad's domain |xi| + |eta| <= 1, counted here
  for (int i = 0; i < 64; ++i)
    for (int j = 0; j < 64; ++j) {
      const double l1 = std::abs(-1 + (i + 0.5) / 32) + std::abs(-1 + (j + 0.5) / 32);
      strictly += l1 < 1 - 1e-12;
      onBoundary += std::abs(l1 - 1) <= 1e-12;
    }
  EXPECT_GE(k.points, 54 * strictly);
  EXPECT_LE(k.points, 54 * (strictly + onBoundary));
  EXPECT_LT(patch.disc.stats.max, 1.1 * upper);
  EXPECT_GT(patch.disc.stats.p50, 0.9 * lower);
  // and no neighbour pair differs by 10 degrees within a sample spacing (0.056 m ~ 3.4 degrees)
  EXPECT_EQ(patch.disc.flaggedPairs, 0u);
  EXPECT_LT(patch.disc.maxAngle, 10 * std::numbers::pi / 180);
  // Direct (god-object on the quads): the face normal jumps by up to 30 degrees across edges.
  EXPECT_GT(direct.disc.flaggedPairs, 10u);
  EXPECT_GT(direct.disc.stats.max, 3 * patch.disc.stats.max);
  EXPECT_GT(direct.disc.maxAngle, 20 * std::numbers::pi / 180);
  // The sweep's trajectory half-step test tells the same (checked by the summary elsewhere).
}

// probeOrder is a permutation of the HIPs, along the Morton curve (consecutive HIPs close:
// the mean step is far below the mean distance of random pairs), non-finite HIPs last.
TEST(SweepMethods, ProbeOrderIsAMortonPermutation) {
  HipSet set;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 5000; ++i) {
    SurfaceSample s;
    s.point = Eigen::Vector3d(u(rng), u(rng), u(rng));
    s.normal = Eigen::Vector3d::UnitZ();
    if (i % 1000 == 7) s.point.x() = std::numeric_limits<double>::quiet_NaN();
    set.samples.push_back(s);
  }
  set.groups.push_back(HipGroup{"1 mm", 0.001, {}});
  set.groups.push_back(HipGroup{"2 mm", 0.002, {}});
  set.diagonal = 2 * std::sqrt(3.0);
  for (size_t begin : {size_t(0), size_t(1234)}) {
    const size_t end = set.size() - 17;
    const std::vector<uint32_t> order = probeOrder(set, begin, end);
    ASSERT_EQ(order.size(), end - begin);
    std::vector<uint32_t> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    for (size_t i = 0; i < sorted.size(); ++i) ASSERT_EQ(sorted[i], i);
    size_t finite = 0;
    double step = 0, random = 0;
    for (size_t i = 0; i < order.size(); ++i) {
      const Eigen::Vector3d h = set.hip(begin + order[i]);
      if (!h.allFinite()) {
        for (size_t j = i; j < order.size(); ++j) EXPECT_FALSE(set.hip(begin + order[j]).allFinite()) << j;
        break;
      }
      ++finite;
      if (i > 0) step += (h - set.hip(begin + order[i - 1])).norm();
      const Eigen::Vector3d other = set.hip(begin + (i * 7919) % order.size());
      if (other.allFinite()) random += (h - other).norm();
    }
    EXPECT_EQ(order.size() - finite, begin == 0 ? 10u : 8u);  // one segment: all non-finite last
    EXPECT_LT(step, 0.1 * random) << "consecutive probes should be neighbours";
  }
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
