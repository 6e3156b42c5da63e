// SPDX-License-Identifier: Apache-2.0
// The a-priori patch boxes (patch_bounds.h, kernels/gp_bound.h) hold their whole patches: every
// patch of every mesh in shared/meshes, sampled densely over its domain, in every cross-tangent
// mode and both precisions on the spot cage; computed from vertices and normals alone, so a
// skeleton gives the same boxes as a built cache.
#include <gtest/gtest.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <utility>
#include <vector>

#include <smoothforce/patch/patch_bounds.h>
#include "patch_test_support.h"

namespace sf {
namespace {

struct BoxCheck {
  long points = 0, outside = 0, faces = 0;
  double looseness = 0;  ///< sum over faces of box diagonal / sampled patch box diagonal
  double worst = 0;      ///< largest distance outside a box / the face's box diagonal
};

/// Samples every patch of c on `rings` rings of `perEdge` points per domain edge (plus the centre)
/// and checks each point against the face's box.
BoxCheck checkBoxes(const PatchCache& c, int rings, int perEdge) {
  const std::vector<PatchBox> boxes = patchBoxes(c);
  EXPECT_EQ(static_cast<int>(boxes.size()), c.numFaces());
  return tbb::parallel_reduce(
      tbb::blocked_range<int>(0, c.numFaces()), BoxCheck{},
      [&](const tbb::blocked_range<int>& r, BoxCheck acc) {
        for (int f = r.begin(); f < r.end(); ++f) {
          const int n = c.faceSize(f);
          if (n > GP_MAX_N || !boxes[f].valid) continue;
          Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
          for (int ring = 0; ring <= rings; ++ring)
            for (int k = 0; k < (ring == 0 ? 1 : n); ++k)
              for (int j = 0; j < (ring == 0 ? 1 : perEdge); ++j) {
                const Eigen::Vector2d x = (double(ring) / rings) * test::edgePoint(n, k, double(j) / perEdge, 0.0);
                const PatchPoint p = evaluatePatch(c, f, x.x(), x.y());
                ++acc.points;
                lo = lo.cwiseMin(p.pos);
                hi = hi.cwiseMax(p.pos);
                const double out = boxes[f].distance(p.pos);
                if (out > 0) {
                  ++acc.outside;
                  acc.worst = std::max(acc.worst, out / (boxes[f].hi - boxes[f].lo).norm());
                }
              }
          ++acc.faces;
          acc.looseness += (boxes[f].hi - boxes[f].lo).norm() / std::max((hi - lo).norm(), 1e-300);
        }
        return acc;
      },
      [](BoxCheck a, const BoxCheck& b) {
        a.points += b.points;
        a.outside += b.outside;
        a.faces += b.faces;
        a.looseness += b.looseness;
        a.worst = std::max(a.worst, b.worst);
        return a;
      });
}

TEST(PatchBounds, EveryPatchOfEverySharedMeshLiesInItsBox) {
  int meshes = 0;
  long points = 0;
  for (const std::string& path : test::sharedMeshFiles()) {
    SCOPED_TRACE(path);
    const PatchCache c = test::cacheFromFile(path);
    // about 2 * 10^5 samples per mesh, at least 2 rings of 3 points per edge
    const int dense = c.numFaces() < 2000 ? 8 : c.numFaces() < 20000 ? 4 : 2;
    const BoxCheck b = checkBoxes(c, dense, dense + 1);
    std::printf("  %-50s %6d faces, %8ld samples: %ld outside; box / sampled patch box diagonal %.2f\n",
                std::filesystem::path(path).lexically_relative(SF_SHARED_MESHES).string().c_str(), c.numFaces(),
                b.points, b.outside, b.looseness / std::max<long>(b.faces, 1));
    EXPECT_EQ(b.outside, 0) << "worst: " << b.worst << " of the box diagonal outside";
    EXPECT_GT(b.faces, 0);
    points += b.points;
    ++meshes;
  }
  EXPECT_GE(meshes, 20);
  EXPECT_GT(points, 1'000'000);
}

TEST(PatchBounds, EveryCrossTangentModeAndPrecisionOnTheSpotCage) {
  const std::string spot = test::sharedMesh("keenan_crane/spot_control_mesh.obj");
  for (CrossTangentMode mode : {CrossTangentMode::Corrected, CrossTangentMode::Paper, CrossTangentMode::Blend})
    for (Precision precision : {Precision::Double, Precision::Float}) {
      const PatchCache c = test::cacheFromFile(spot, mode, precision);
      const BoxCheck b = checkBoxes(c, 16, 17);
      EXPECT_EQ(b.faces, 180);
      EXPECT_EQ(b.outside, 0) << toString(mode) << ", " << toString(precision) << ": worst " << b.worst;
    }
}

TEST(PatchBounds, ASkeletonGivesTheBoxesOfTheBuiltCache) {
  const std::string spot = test::sharedMesh("keenan_crane/spot_control_mesh.obj");
  const std::vector<PatchBox> built = patchBoxes(test::cacheFromFile(spot)),
                              lazy = patchBoxes(test::skeletonFromFile(spot));
  ASSERT_EQ(built.size(), lazy.size());
  for (size_t f = 0; f < built.size(); ++f) {
    EXPECT_TRUE(built[f].valid && lazy[f].valid) << f;
    EXPECT_EQ(built[f].lo, lazy[f].lo) << f;
    EXPECT_EQ(built[f].hi, lazy[f].hi) << f;
  }
}

}  // namespace
}  // namespace sf
