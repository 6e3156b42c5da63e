// SPDX-License-Identifier: Apache-2.0
// measureSurfaceDistance (surface_distance.h): on every closed shape of the query tests, each
// sample's distance to the polygons checked against brute force (every fan triangle, the sweep
// reference's closest point on a triangle) and to another construction's patch surface against the dense oracle; a
// surface is at distance 0 from itself; the aggregates are those of the per-point distances.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <smoothforce/base/error.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/query/patch_refine.h>
#include <smoothforce/query/surface_distance.h>
#include <smoothforce/sweep/sweep_reference.h>
#include "query_test_support.h"
#include "shared_mesh_files.h"

namespace sf {
namespace {

Eigen::Vector3d vertex(const PatchCache& c, int v) {
  return {c.positions[3 * v], c.positions[3 * v + 1], c.positions[3 * v + 2]};
}

/// Distance from p to the polygons of c, brute force over every polygon's fan triangles from
/// the mean of its corners (for a convex flat polygon the polygon itself).
double bruteForcePolygonDistance(const PatchCache& c, const Eigen::Vector3d& p) {
  double best = INFINITY;
  for (int f = 0; f < c.numFaces(); ++f) {
    const int first = c.faceOffsets[f], n = c.faceSize(f);
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (int k = 0; k < n; ++k) centre += vertex(c, c.faceVertices[first + k]);
    centre /= n;
    for (int k = 0; k < n; ++k)
      best = std::min(best, (closestPointOnTriangle(p, centre, vertex(c, c.faceVertices[first + k]),
                                                  vertex(c, c.faceVertices[first + (k + 1) % n])) -
                             p)
                                .norm());
  }
  return best;
}

/// Every `stride`-th sample, so that brute force stays within about `budget` triangle tests.
size_t strideFor(size_t points, long work, long budget) {
  return std::max<size_t>(1, static_cast<size_t>(double(points) * double(work) / double(budget)));
}

TEST(SurfaceDistance, EverySampleAgreesWithBruteForceAndTheDenseOracle) {
  int shapes = 0;
  size_t polygonChecked = 0, patchChecked = 0;
  for (const std::string& name : test::closedShapes()) {
    SCOPED_TRACE(name);
    const std::shared_ptr<const PatchCache> cache = test::closedShapeCache(name);
    if (cache->numFaces() > 20000) continue;  // the dense oracle's and brute force's cost
    ++shapes;
    long fanTriangles = 0;
    for (int f = 0; f < cache->numFaces(); ++f) fanTriangles += cache->faceSize(f);
    const double diag = boundingDiagonal(*cache);  // the unit of measureSurfaceDistance's fractions

    // patches -> their own polygons, against brute force
    const SurfaceSamples s = sampleSurface(*cache, DistanceSurface::Patches, 3);
    const std::vector<double> d = distancesToSurface(*cache, DistanceSurface::Polygons, s.xyz.data(), s.size());
    ASSERT_EQ(d.size(), s.size());
    const size_t stride = strideFor(s.size(), fanTriangles, 4000000);
    for (size_t i = 0; i < s.size(); i += stride, ++polygonChecked) {
      const Eigen::Vector3d p(s.xyz[3 * i], s.xyz[3 * i + 1], s.xyz[3 * i + 2]);
      ASSERT_NEAR(d[i], bruteForcePolygonDistance(*cache, p), 1e-12 * diag) << "sample " << i;
    }

    // polygons -> the patch surface of another construction (the paper's cross tangents), against
    // the dense oracle's nearest point (a dense tessellation refined by Newton)
    PatchOptions paper = cache->options;
    paper.crossTangent = CrossTangentMode::Paper;
    PatchCache other = preparePatchCache(cacheBaseMesh(*cache), [&] {
      std::vector<Eigen::Vector3d> n(cache->numSlots());
      for (int k = 0; k < cache->numSlots(); ++k)
        n[k] = {cache->cornerNormals[3 * k], cache->cornerNormals[3 * k + 1], cache->cornerNormals[3 * k + 2]};
      return n;
    }(), paper, cache->meshHash);
    constructPatches(other, Backend::Tbb);
    // (about 300 samples spread over every face's rings: the oracle's cost)
    const SurfaceSamples q = sampleSurface(*cache, DistanceSurface::Polygons, 2);
    const size_t qStride = std::max<size_t>(1, q.size() / 300);
    std::vector<double> picked;
    for (size_t i = 0; i < q.size(); i += qStride) picked.insert(picked.end(), &q.xyz[3 * i], &q.xyz[3 * i] + 3);
    const std::vector<double> e = distancesToSurface(other, DistanceSurface::Patches, picked.data(), picked.size() / 3);
    ASSERT_EQ(e.size(), picked.size() / 3);
    const test::DenseOracle oracle(other, 200000);
    PatchRefiner refiner(other);
    for (size_t j = 0; j < e.size(); ++j, ++patchChecked) {
      const Eigen::Vector3d p(picked[3 * j], picked[3 * j + 1], picked[3 * j + 2]);
      const test::DenseOracle::Nearest o = oracle.nearest(p, refiner);
      ASSERT_NEAR(e[j], o.distance, 1e-7 * diag) << "sample " << j * qStride << " of face " << q.face[j * qStride];
    }

    // a surface lies at distance 0 from itself (within the refinement's tolerance), both ways
    const SurfaceDistance self =
        measureSurfaceDistance(*cache, DistanceSurface::Patches, *cache, DistanceSurface::Patches, 2);
    EXPECT_LE(self.aToB.max, 1e-9);
    EXPECT_LE(self.bToA.max, 1e-9);
    EXPECT_EQ(self.aToB.points, self.bToA.points);
  }
  std::printf("surface distance: %d shapes, %zu polygon distances against brute force, %zu patch distances "
              "against the dense oracle\n",
              shapes, polygonChecked, patchChecked);
  EXPECT_GE(shapes, 18);
}

TEST(SurfaceDistance, TheAggregatesAreThoseOfThePointsAndBadInputIsRefused) {
  const std::shared_ptr<const PatchCache> cache = test::closedShapeCache("lagrange/cube.obj");
  const SurfaceDistance r =
      measureSurfaceDistance(*cache, DistanceSurface::Patches, *cache, DistanceSurface::Polygons, 4);
  const SurfaceSamples a = sampleSurface(*cache, DistanceSurface::Patches, 4);
  const SurfaceSamples b = sampleSurface(*cache, DistanceSurface::Polygons, 4);
  // the ring counts: 1 + n L (L+1) / 2 per quad of the cube, on both
  EXPECT_EQ(a.size(), 6u * (1 + 4 * 4 * 5 / 2));
  EXPECT_EQ(b.size(), a.size());
  const std::vector<double> da = distancesToSurface(*cache, DistanceSurface::Polygons, a.xyz.data(), a.size());
  const std::vector<double> db = distancesToSurface(*cache, DistanceSurface::Patches, b.xyz.data(), b.size());
  double maxA = 0, sumA = 0, maxB = 0, sumB = 0;
  for (double x : da) maxA = std::max(maxA, x), sumA += x;
  for (double x : db) maxB = std::max(maxB, x), sumB += x;
  EXPECT_DOUBLE_EQ(r.aToB.max, maxA / r.diagonal);
  EXPECT_DOUBLE_EQ(r.aToB.mean, sumA / double(da.size()) / r.diagonal);
  EXPECT_DOUBLE_EQ(r.bToA.max, maxB / r.diagonal);
  EXPECT_DOUBLE_EQ(r.bToA.mean, sumB / double(db.size()) / r.diagonal);
  EXPECT_GT(r.aToB.max, 0.01);  // the cube's patches bulge off its faces
  EXPECT_GE(r.aToB.worstFace, 0);
  EXPECT_EQ(r.levelA, 4);
  EXPECT_EQ(r.levelB, 4);
  // a surface of many polygons is sampled at a lower level: within kMaxDistanceSamples, and at
  // level 1 however many polygons there are
  PatchCache many;
  many.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  many.faceOffsets = {0};
  for (int f = 0; f < 300000; ++f) {
    many.faceVertices.insert(many.faceVertices.end(), {0, 1, 2});
    many.faceOffsets.push_back(static_cast<int32_t>(many.faceVertices.size()));
  }
  const int lower = sampleLevel(many, 8);
  EXPECT_LT(lower, 8);
  EXPECT_LE(300000.0 * 3 * lower * (lower + 1) / 2 + 300000, kMaxDistanceSamples);
  EXPECT_GT(300000.0 * 3 * (lower + 1) * (lower + 2) / 2 + 300000, kMaxDistanceSamples);
  EXPECT_EQ(sampleLevel(*cache, 8), 8);
  many.faceOffsets.resize(2000001, 0);  // 2 million faces: level 1, the least
  for (size_t f = 300001; f < many.faceOffsets.size(); ++f) many.faceOffsets[f] = many.faceOffsets[f - 1] + 3;
  many.faceVertices.resize(many.faceOffsets.back(), 0);
  EXPECT_EQ(sampleLevel(many, 8), 1);
  EXPECT_THROW(measureSurfaceDistance(*cache, DistanceSurface::Patches, *cache, DistanceSurface::Polygons, 0),
               InputError);
  EXPECT_THROW(measureSurfaceDistance(*cache, DistanceSurface::Patches, *cache, DistanceSurface::Polygons, 65),
               InputError);
  const double bad[3] = {NAN, 0, 0};
  EXPECT_TRUE(std::isnan(distancesToSurface(*cache, DistanceSurface::Polygons, bad, 1)[0]));
  EXPECT_TRUE(std::isnan(distancesToSurface(*cache, DistanceSurface::Patches, bad, 1)[0]));
  PatchCache skeleton = preparePatchSkeleton(loadMesh(test::sharedMesh("lagrange/cube.obj"), PatchOptions{}),
                                             PatchOptions{});
  EXPECT_THROW(measureSurfaceDistance(skeleton, DistanceSurface::Patches, *cache, DistanceSurface::Polygons, 2),
               InputError);
  EXPECT_NO_THROW(measureSurfaceDistance(*cache, DistanceSurface::Patches, skeleton, DistanceSurface::Polygons, 2));
}

}  // namespace
}  // namespace sf
