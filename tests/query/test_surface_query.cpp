// SPDX-License-Identifier: Apache-2.0
// The batch surface query (SurfaceQuery) on every closed mesh of ../shared/meshes and the
// generated shapes, checked against the dense oracle (its own ray parity and nearest point,
// independent of the production query): for points pressed in and out along the patch normal
// at three depths and points spread over the box around the shape, the sign of the distance is
// the oracle's inside verdict and |distance| is the oracle's nearest distance (within 1e-6 of
// the diagonal), except at surface faults (counted; only the spot cage has any). The answers
// do not depend on the thread count or the order of the points (bit for bit).
#include <gtest/gtest.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>

#include <smoothforce/query/surface_query.h>
#include <smoothforce/sweep/sweep_sampling.h>
#include "gp_config.h"
#include "patch_test_support.h"
#include "query_test_support.h"

namespace sf {
namespace {

class SurfaceQueryShapes : public ::testing::TestWithParam<std::string> {};

bool sameBits(const SurfaceQueryResult& a, const SurfaceQueryResult& b) {
  return std::memcmp(&a.signedDistance, &b.signedDistance, sizeof(double)) == 0 && a.point == b.point &&
         a.normal == b.normal && a.face == b.face && a.xi == b.xi && a.eta == b.eta && a.status == b.status;
}

TEST_P(SurfaceQueryShapes, SignedDistanceIsTheOraclesNearestDistanceWithItsInsideVerdict) {
  const std::string shape = GetParam();
  const auto cache = test::closedShapeCache(shape);
  const double diag = boundingDiagonal(*cache);
  const test::DenseOracle oracle(*cache);
  const SurfaceQuery query(cache);
  // points: 3 depths in and out at surface samples, and uniform points in the box grown by 20%
  const PatchSurfaceSampler sampler(*cache, cache->numFaces() > 4000 ? 2 : 6);
  constexpr int kSamples = 200, kBox = 300;
  const std::vector<SurfaceSample> samples = sampler.sample(kSamples, 20261125);
  std::vector<double> pts;
  for (const SurfaceSample& s : samples)
    for (const double d : {-0.01, -0.0025, 0.001, 0.005}) {
      const Eigen::Vector3d p = s.point + d * diag * s.normal;
      pts.insert(pts.end(), {p.x(), p.y(), p.z()});
    }
  Eigen::Vector3d lo, hi;
  referencedBox(*cache, lo, hi);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-0.1, 1.1);
  for (int i = 0; i < kBox; ++i)
    for (int a = 0; a < 3; ++a) pts.push_back(lo[a] + U(rng) * (hi[a] - lo[a]));
  const size_t n = pts.size() / 3;
  std::vector<SurfaceQueryResult> out(n), serial(n), reversed(n);
  query.query(pts.data(), n, out.data());
  query.query(pts.data(), n, serial.data(), 1);
  std::vector<double> rev(pts.size());
  for (size_t i = 0; i < n; ++i) std::copy_n(&pts[3 * (n - 1 - i)], 3, &rev[3 * i]);
  query.query(rev.data(), n, reversed.data(), 2);
  int unlike = 0;
  for (size_t i = 0; i < n; ++i) unlike += !sameBits(out[i], serial[i]) || !sameBits(out[i], reversed[n - 1 - i]);
  EXPECT_EQ(unlike, 0) << shape << ": answers depend on the thread count or the order";

  tbb::enumerable_thread_specific<std::unique_ptr<PatchRefiner>> refiners(
      [&] { return std::make_unique<PatchRefiner>(*cache); });
  std::atomic<int> tested{0}, faults{0}, wrongSide{0}, notNearest{0}, inside{0}, raysDisagree{0}, notOnSurface{0};
  tbb::parallel_for(size_t(0), n, [&](size_t i) {
    const Eigen::Vector3d p(pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]);
    const SurfaceQueryResult& r = out[i];
    bool agree = true;
    const bool truth = oracle.winding(p, &agree) >= 1;
    if (!agree) {
      ++raysDisagree;
      return;
    }
    const test::DenseOracle::Nearest q = oracle.nearest(p, *refiners.local());
    // a surface fault (as QueryProperties): the true nearest point sees the point on the side its
    // normal does not predict, or sheets within 1.5x of that distance see it on both sides
    if (((p - q.point).dot(q.normal) < 0) != truth || q.conflicting(1.5)) {
      ++faults;
      return;
    }
    ++tested;
    inside += truth;
    if ((r.signedDistance < 0) != truth) ++wrongSide;
    if (std::abs(std::abs(r.signedDistance) - q.distance) > 1e-6 * diag) ++notNearest;
    if (std::abs((r.point - p).norm() - std::abs(r.signedDistance)) > 1e-12 * diag || r.face < 0 ||
        std::abs(r.normal.norm() - 1) > 1e-9 || ((r.status & SF_TRACK_INSIDE) != 0) != (r.signedDistance < 0))
      ++notOnSurface;
  });
  std::printf("  %s: %zu points, %d checked (%d inside), %d at surface faults, %d rays disagree\n", shape.c_str(), n,
              tested.load(), inside.load(), faults.load(), raysDisagree.load());
  EXPECT_EQ(tested.load() + faults.load() + raysDisagree.load(), int(n));
  EXPECT_LE(raysDisagree.load(), int(n) / 100);
  // the spot cage's overlapping sheets: 29 of these 1,100 points (2.6%; QueryProperties' pressed
  // HIPs alone 1.7%); no other shape has a fault
  EXPECT_LE(faults.load(), (shape == "keenan_crane/spot_control_mesh.obj" ? 0.03 : 0.0) * n) << shape;
  EXPECT_GE(inside.load(), tested.load() / 4) << shape;
  EXPECT_EQ(wrongSide.load(), 0) << shape;
  EXPECT_EQ(notNearest.load(), 0) << shape;
  EXPECT_EQ(notOnSurface.load(), 0) << shape;
}

INSTANTIATE_TEST_SUITE_P(Shapes, SurfaceQueryShapes, ::testing::ValuesIn(test::closedShapes()),
                         [](const ::testing::TestParamInfo<std::string>& i) { return test::shapeTestName(i.param); });

// Points the query cannot take get NaN and a status, never a crash; a skeleton cache is refused.
TEST(SurfaceQuery, BadPointsAndSkeletonsAreNamed) {
  const auto cache = test::closedShapeCache("polygon_laplacian/quad-sphere.off");
  const SurfaceQuery query(cache);
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> pts = {nan, 0, 0, 0, inf, 0, 0, 0, 1e300, 0, 0, 0};
  std::vector<SurfaceQueryResult> out(4);
  query.query(pts.data(), 4, out.data());
  for (int i = 0; i < 3; ++i) {
    EXPECT_TRUE(std::isnan(out[i].signedDistance)) << i;
    EXPECT_EQ(out[i].face, -1);
    EXPECT_EQ(out[i].status, SF_TRACK_BAD_HIP);
  }
  EXPECT_LT(out[3].signedDistance, 0);  // the sphere's centre
  EXPECT_NEAR(out[3].signedDistance, query.query(Eigen::Vector3d::Zero()).signedDistance, 0.0);
  EXPECT_THROW(query.query(nullptr, 1, out.data()), std::invalid_argument);
  EXPECT_THROW(SurfaceQuery(std::make_shared<const PatchCache>(test::skeletonOf(*cache))), InputError);
}

}  // namespace
}  // namespace sf
