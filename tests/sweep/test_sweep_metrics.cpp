// SPDX-License-Identifier: Apache-2.0
// Sweep metrics and helpers: discontinuity on synthetic force fields, percentiles, reference
// distances, parsers, shards, polylines.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include <smoothforce/mesh/mesh.h>
#include <smoothforce/sweep/sweep_io.h>
#include <smoothforce/sweep/sweep_metrics.h>
#include <smoothforce/sweep/sweep_reference.h>
#include <smoothforce/sweep/sweep_sampling.h>

namespace sf {
namespace {

constexpr double kDeg = std::numbers::pi / 180;

/// n random points on the unit square in z = 0 and a force field over them.
struct Field {
  std::vector<Eigen::Vector3d> pos, dir;
  std::vector<char> valid;
  double spacing;
};

Field makeField(size_t n, double jumpDeg) {
  Field f;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d p(u(rng), u(rng), 0);
    // smooth part: tilts by 1 rad per metre along x; jump: extra tilt for x > 0.5
    const double a = 0.3 * p.x() + (p.x() > 0.5 ? jumpDeg * kDeg : 0.0);
    f.pos.push_back(p);
    f.dir.push_back(Eigen::Vector3d(std::sin(a), 0, std::cos(a)) * 3.0);
    f.valid.push_back(1);
  }
  f.spacing = std::sqrt(1.0 / static_cast<double>(n));
  return f;
}

TEST(SweepMetrics, SmoothFieldPasses) {
  const Field f = makeField(20000, 0);
  const Discontinuity d = forceDiscontinuity(f.pos, f.dir, f.valid, 8, 10 * kDeg, f.spacing);
  EXPECT_EQ(d.flaggedPairs, 0u);
  EXPECT_EQ(d.stats.count, 20000u);
  EXPECT_LE(d.stats.max, 0.3 * (1 + 1e-6));  // angle / distance <= the field's gradient
  EXPECT_GT(d.stats.p50, 0.05);
}

TEST(SweepMetrics, PlantedJumpIsFlagged) {
  const Field f = makeField(20000, 20);
  const Discontinuity d = forceDiscontinuity(f.pos, f.dir, f.valid, 8, 10 * kDeg, f.spacing);
  EXPECT_GT(d.flaggedPairs, 50u);  // along the whole line x = 0.5
  EXPECT_GT(d.stats.max, 20 * kDeg / f.spacing);
  EXPECT_NEAR(d.maxAngle, 20 * kDeg, 0.01);
  // Only HIPs near the line carry a large local value.
  for (size_t i = 0; i < f.pos.size(); ++i) {
    if (std::abs(f.pos[i].x() - 0.5) > 5 * f.spacing) {
      EXPECT_LE(d.local[i], 0.3 * (1 + 1e-6)) << i;
    }
  }
  // A 5-degree jump stays under the 10-degree flag, but still dominates the tail.
  const Discontinuity small = forceDiscontinuity(f.pos, makeField(20000, 5).dir, f.valid, 8, 10 * kDeg, f.spacing);
  EXPECT_EQ(small.flaggedPairs, 0u);
  EXPECT_GT(small.stats.p999, 1.0);
}

TEST(SweepMetrics, InvalidHipsAreSkipped) {
  Field f = makeField(2000, 0);
  for (size_t i = 0; i < f.valid.size(); i += 2) f.valid[i] = 0;
  const Discontinuity d = forceDiscontinuity(f.pos, f.dir, f.valid, 8, 10 * kDeg, f.spacing);
  EXPECT_EQ(d.stats.count, 1000u);
  EXPECT_TRUE(std::isnan(d.local[0]));
  EXPECT_FALSE(std::isnan(d.local[1]));
}

TEST(SweepMetrics, PercentilesNearestRank) {
  std::vector<double> v;
  for (int i = 1; i <= 1000; ++i) v.push_back(i);
  v.push_back(NAN);
  const Percentiles p = percentiles(v);
  EXPECT_EQ(p.count, 1000u);
  EXPECT_EQ(p.p50, 500);
  EXPECT_EQ(p.p99, 990);
  EXPECT_EQ(p.p999, 999);
  EXPECT_EQ(p.max, 1000);
  EXPECT_TRUE(std::isnan(percentiles({}).p50));
}

TEST(SweepMetrics, ConsecutiveDifferences) {
  const std::vector<float> f = {0, 0, 1, 0, 0, 1, 0, 3, 5};
  const auto d = consecutiveDifferences(f);
  ASSERT_EQ(d.size(), 2u);
  EXPECT_EQ(d[0], 0);
  EXPECT_NEAR(d[1], 5, 1e-12);
}

TEST(SweepReference, MeshDistanceMatchesBruteForce) {
  TriangleSoup s;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 300; ++i) s.positions.emplace_back(u(rng), u(rng), 0.2 * u(rng));
  for (int t = 0; t < 200; ++t) {
    s.triangles.push_back({3 * (t % 100), 3 * (t % 100) + 1, 3 * (t % 100) + 2});
    const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
    s.cornerNormals.push_back({z, z, z});
  }
  const TriangleSoup copy = s;
  const MeshDistance md(std::move(s), "random");
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d p(2 * u(rng), 2 * u(rng), 2 * u(rng));
    double best = 1e300;
    for (const auto& t : copy.triangles)
      best = std::min(
          best,
          (closestPointOnTriangle(p, copy.positions[t[0]], copy.positions[t[1]], copy.positions[t[2]]) - p).norm());
    EXPECT_NEAR(md.distance(p), best, 1e-14) << i;
  }
}

TEST(SweepReference, AnalyticSpecs) {
  EXPECT_NEAR(makeAnalyticSurface("sphere:2")->distance({0, 3, 0}), 1, 1e-15);
  EXPECT_NEAR(makeAnalyticSurface("torus:1,0.25")->distance({1, 0, 0}), 0.25, 1e-15);
  for (const char* bad : {"sphere", "sphere:", "sphere:-1", "torus:1", "torus:1,2", "cube:1", "sphere:1x",
                          "torus-knot:2,3,1,0.4", "torus-knot:2.5,3,1,0.4,0.1"})
    EXPECT_THROW(makeAnalyticSurface(bad), InputError) << bad;
}

TEST(SweepParse, DepthsShardsTags) {
  const auto d = parseDepthList("2%,0.004");
  ASSERT_EQ(d.size(), 2u);
  EXPECT_TRUE(d[0].relative);
  EXPECT_NEAR(d[0].metres(0.5), 0.01, 1e-15);
  EXPECT_EQ(d[1].metres(0.5), 0.004);
  EXPECT_EQ(depthTag("2%"), "2pct");
  EXPECT_EQ(depthTag("0.004"), "0.004m");
  for (const char* bad : {"", "x", "-1", "0", "2%%", "1e400"}) {
    EXPECT_THROW(parseDepthList(bad), InputError) << bad;
    try {  // the message names the option the text came from
      parseDepthList(bad, "--trajectory-step");
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("--trajectory-step: ", 0), 0u) << e.what();
    }
  }
  int i = 0, n = 0;
  parseShard("3/8", i, n);
  EXPECT_EQ(i, 3);
  EXPECT_EQ(n, 8);
  for (const char* bad : {"8/8", "-1/2", "1/0", "1", "a/b", "1/2x"})
    EXPECT_THROW(parseShard(bad, i, n), InputError) << bad;
  uint64_t prev = 0;
  for (int k = 0; k < 7; ++k) {
    uint64_t b, e;
    shardRange(100, k, 7, b, e);
    EXPECT_EQ(b, prev);
    EXPECT_GE(e - b, 14u);
    EXPECT_LE(e - b, 15u);
    prev = e;
  }
  EXPECT_EQ(prev, 100u);
}

TEST(SweepParse, ResamplePolyline) {
  const std::vector<Eigen::Vector3d> pts = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}};
  const auto r = resamplePolyline(pts, 0.3);
  ASSERT_EQ(r.size(), 7u);  // 0, 0.3, ..., 1.8
  for (size_t i = 1; i < r.size(); ++i) {
    const double s = 0.3 * static_cast<double>(i);
    const Eigen::Vector3d want = s <= 1 ? Eigen::Vector3d(s, 0, 0) : Eigen::Vector3d(1, s - 1, 0);
    EXPECT_LT((r[i] - want).norm(), 1e-12) << i;
  }
}

// Every polyline below and at the resampling limit resamples to about length / step + 1 points;
// above it (far points, a tiny step, coordinates whose squared distance overflows) the error
// names the length, the step and the count before anything is allocated.
TEST(SweepParse, ResampleLimit) {
  const std::vector<Eigen::Vector3d> line = {{0, 0, 0}, {3, 0, 0}, {3, 4, 0}};
  EXPECT_DOUBLE_EQ(polylineLength(line), 7.0);
  EXPECT_DOUBLE_EQ(polylineLength({{0, 0, 0}, {1e200, 0, 0}}), 1e200);  // no overflow to inf
  EXPECT_EQ(polylineLength({{1, 2, 3}}), 0.0);
  int checked = 0;
  for (const double step : {7.0, 0.5, 1e-3, 7.0 / kMaxResampledPoints}) {
    EXPECT_TRUE(resampleLimitError(line, step, "f.csv").empty()) << step;
    if (step < 1e-5) continue;  // 10^7 points: the bound, not resampled here
    const auto r = resamplePolyline(line, step);
    EXPECT_NEAR(static_cast<double>(r.size()), std::floor(7.0 / step) + 1, 1.0) << step;
    ++checked;
  }
  EXPECT_EQ(checked, 3);
  const std::vector<std::vector<Eigen::Vector3d>> tooLong = {
      {{0, 0, 0}, {1e200, 0, 0}}, {{-1e308, 0, 0}, {1e308, 0, 0}}, {{0, 0, 0}, {1, 0, 0}, {0, 0, 0}, {1e6, 0, 0}}};
  for (const auto& pts : tooLong) {
    const std::string e = resampleLimitError(pts, 1e-3, "f.csv");
    EXPECT_EQ(e.rfind("f.csv: the polyline is ", 0), 0u) << e;
    EXPECT_NE(e.find("more than 1e+07"), std::string::npos) << e;
    EXPECT_THROW(resamplePolyline(pts, 1e-3), InputError);
  }
  EXPECT_FALSE(resampleLimitError(line, 7.0 / kMaxResampledPoints / 2, "f.csv").empty());
  EXPECT_TRUE(resamplePolyline(line, 0).empty());
  EXPECT_TRUE(resamplePolyline(line, std::nan("")).empty());
}

}  // namespace
}  // namespace sf
