// SPDX-License-Identifier: Apache-2.0
// The adaptive tessellation of the patch surface stays within its triangle budget
// (PatchSurfaceOptions::adaptiveBudget). A tetrahedron whose file normals are axis directions
// that disagree with its faces bulges every patch (up to 512 face sizes); unbounded, its
// adaptive tessellation took 68 million triangles and 9 GB before the first query. Checked:
// the budget holds, the triangles still tile every face's domain (their domain areas sum to the
// domain's), the largest error bounds were split first, and the global query over the budgeted
// surface finds the same nearest points as over the unbounded one where both refinements
// converged (the bounds left wider are still bounds).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <smoothforce/force/force_tracking.h>
#include <smoothforce/query/patch_surface.h>
#include "patch_test_support.h"
#include "surface_tessellation.h"

namespace sf {
namespace {

PatchCache mismatchedNormalsTetrahedron() {
  ref::RefMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.faces = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
  m.normals = {{0, 0, -1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  return test::cacheFromShape(m);
}

double domainArea(const SurfaceTriangle& t) {
  const Eigen::Vector2d a = t.X[1] - t.X[0], b = t.X[2] - t.X[0];
  return 0.5 * std::abs(a.x() * b.y() - a.y() * b.x());
}

TEST(SurfaceBudget, AdaptiveTessellationStaysWithinItsBudgetAndStillBoundsThePatches) {
  const PatchCache cache = mismatchedNormalsTetrahedron();
  PatchSurfaceOptions unbounded;
  unbounded.subdivision = 3;  // at most 64 children per uniform triangle: the unbounded one stays small
  PatchSurfaceOptions budgeted = unbounded;
  budgeted.adaptiveBudget = 60000;
  const PatchSurface big(cache, unbounded), small(cache, budgeted);
  const size_t uniform = small.numTriangles();
  ASSERT_GT(big.numPointTriangles(), 60000u);  // the budget binds
  EXPECT_LE(small.numPointTriangles(), 60000u);
  EXPECT_GE(small.numPointTriangles(), uniform);
  // every adaptive triangle, read back, as the surface holds it
  auto triangles = [](const PatchSurface& s) {
    std::vector<SurfaceTriangle> out(s.numPointTriangles());
    for (size_t t = 0; t < out.size(); ++t) out[t] = adaptiveTriangle(s.uniform(), s.adaptive(), t);
    return out;
  };
  const std::vector<SurfaceTriangle> bigTriangles = triangles(big), smallTriangles = triangles(small);

  // the triangles tile each face's domain, as the uniform ones do
  std::vector<double> areaBig(cache.numFaces(), 0), areaSmall(cache.numFaces(), 0);
  for (const SurfaceTriangle& t : bigTriangles) areaBig[t.face] += domainArea(t);
  for (const SurfaceTriangle& t : smallTriangles) areaSmall[t.face] += domainArea(t);
  for (int f = 0; f < cache.numFaces(); ++f) EXPECT_NEAR(areaSmall[f], areaBig[f], 1e-9 * areaBig[f]) << "face " << f;

  // the worst bounds went first: every triangle left at a coarser depth than the unbounded one's
  // deepest has a bound no larger than the largest one split (within a factor: a child's bound is
  // measured afresh), i.e. the budget did not leave the worst bounds unsplit
  double worstBig = 0, worstSmall = 0;
  for (const SurfaceTriangle& t : bigTriangles) worstBig = std::max(worstBig, t.error);
  for (const SurfaceTriangle& t : smallTriangles) worstSmall = std::max(worstSmall, t.error);
  double worstUniform = 0;
  for (double e : small.uniform().error) worstUniform = std::max(worstUniform, e);
  EXPECT_LT(worstSmall, worstUniform);  // the worst uniform triangles were split
  EXPECT_GE(worstSmall, worstBig);

  // the same nearest points: 400 HIPs around the tetrahedron, inside and out
  PatchRefiner refiner(cache);
  const ForceOptions options;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-0.5, 1.5);
  int queries = 0, found = 0, converged = 0;
  for (int i = 0; i < 400; ++i) {
    const Eigen::Vector3d hip(u(rng), u(rng), u(rng));
    const PatchNearest a = nearestOnPatches(big, refiner, hip, options);
    const PatchNearest b = nearestOnPatches(small, refiner, hip, options);
    ++queries;
    if (!(a.nearest.distance < 1e300)) continue;
    ++found;
    // on these folded, bulging patches a refinement can stop short of its tolerance (iteration
    // cap, stall) a few 1e-5 from where another start stops, or be held on a fold edge (stopped by
    // the idle rule, 1e-8): compared where both converged off the fold edges
    const uint32_t both = a.nearest.status & b.nearest.status, either = a.nearest.status | b.nearest.status;
    if (!(both & SF_TRACK_CONVERGED) || (either & SF_TRACK_FOLD_EDGE)) continue;
    ++converged;
    EXPECT_NEAR(b.nearest.distance, a.nearest.distance, 1e-9 * (1 + a.nearest.distance))
        << "HIP " << hip.transpose() << ", status 0x" << std::hex << a.nearest.status << " / 0x" << b.nearest.status;
  }
  std::printf(
      "%zu adaptive triangles unbounded, %zu within the budget; %d of %d nearest points converged in both, off fold "
      "edges\n",
      big.numPointTriangles(), small.numPointTriangles(), converged, found);
  EXPECT_EQ(queries, 400);
  EXPECT_EQ(found, 400);
  EXPECT_GE(converged, 200);
}

}  // namespace
}  // namespace sf
