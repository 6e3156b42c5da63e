// SPDX-License-Identifier: Apache-2.0
// WindingRays (winding_rays.h) and the partial tessellations the normal search traces: over
// every triangle of the spot cage's uniform tessellation, the crossings of each ray with two
// disjoint halves of the surface add up to the whole's, clean where and only where both halves
// are, so the winding number from the halves is the whole surface's (and PatchSurface's), the
// same for the ray along each triangle's normal that gives both its probes' winding numbers; a
// tessellation of some faces, or without error bounds, has the full one's vertices bit for bit.
#include <gtest/gtest.h>

#include <tbb/parallel_for.h>
#include <Eigen/Geometry>

#include <atomic>
#include <memory>

#include <smoothforce/query/patch_surface.h>
#include "embree_point_query.h"
#include "patch_test_support.h"
#include "surface_tessellation.h"
#include "winding_rays.h"

namespace sf {
namespace {

TEST(WindingRays, CrossingsOfDisjointPartsAddUpToTheWholeSurfaces) {
  const PatchCache c = test::cacheFromFile(test::sharedMesh("keenan_crane/spot_control_mesh.obj"));
  const int L = 8;
  const UniformTessellation whole = tessellateUniform(c, L), bare = tessellateUniform(c, L, /*errors=*/false);
  ASSERT_EQ(whole.vertex, bare.vertex);
  ASSERT_EQ(whole.tri, bare.tri);
  for (const double e : bare.error) ASSERT_EQ(e, 0.0);
  // one part: the faces at vertex 5 and every third face, as a star and scattered faces; the other: the rest
  std::vector<int> partFaces;
  std::vector<char> inPart(c.numFaces(), 0);
  for (int f = 0; f < c.numFaces(); ++f) {
    bool atVertex5 = false;
    for (int s = c.faceOffsets[f]; s < c.faceOffsets[f + 1]; ++s) atVertex5 = atVertex5 || c.faceVertices[s] == 5;
    if (atVertex5 || f % 3 == 0) {
      partFaces.push_back(f);
      inPart[f] = 1;
    }
  }
  const UniformTessellation part = tessellateUniform(c, L, /*errors=*/false, &partFaces);
  int partTriangles = 0;
  for (const int f : partFaces) {  // the part's faces: the whole's triangles and vertices, face by face
    const int64_t a = whole.faceFirstTri[f], b = part.faceFirstTri[f];
    ASSERT_GE(b, 0);
    for (int64_t i = 0; a + i < int64_t(whole.tri.size()) && whole.triFace[a + i] == f; ++i, ++partTriangles)
      for (int k = 0; k < 3; ++k) ASSERT_EQ(whole.vertex[whole.tri[a + i][k]], part.vertex[part.tri[b + i][k]]);
  }
  EXPECT_EQ(partTriangles, static_cast<int>(part.tri.size()));
  std::vector<int64_t> rest;
  for (size_t t = 0; t < whole.tri.size(); ++t)
    if (!inPart[whole.triFace[t]]) rest.push_back(static_cast<int64_t>(t));
  EXPECT_EQ(rest.size() + part.tri.size(), whole.tri.size());

  char error[256] = {0};
  RTCDevice device = newEmbreeDevice([](void* e, RTCError, const char* s) { std::snprintf(static_cast<char*>(e), 256, "%s", s); },
                                     error);
  const std::unique_ptr<RTCDeviceTy, void (*)(RTCDevice)> owner(device, rtcReleaseDevice);
  const WindingRays all(device, whole, nullptr, Eigen::Vector3d::Zero());
  const WindingRays restRays(device, whole, &rest, Eigen::Vector3d::Zero());
  const WindingRays partRays(device, part, nullptr, Eigen::Vector3d::Zero());
  ASSERT_EQ(error[0], 0) << error;
  PatchSurfaceOptions so;
  so.level = L;
  so.windingOnly = true;
  const PatchSurface surface(c, so);

  const double h = 1e-5 * boundingDiagonal(c);
  std::atomic<int> probes{0}, sums{0}, cleanAgree{0}, windingAgree{0}, unclean{0}, inside{0};
  std::atomic<int> pairs{0}, splitSums{0}, splitCleanAgree{0}, oneRay{0}, pairAgree{0};
  tbb::parallel_for(size_t(0), whole.tri.size(), [&](size_t t) {
    const auto& tr = whole.tri[t];
    const Eigen::Vector3d a = whole.vertex[tr[0]], b = whole.vertex[tr[1]], cc = whole.vertex[tr[2]];
    const Eigen::Vector3d n = (b - a).cross(cc - a).normalized(), mid = (a + b + cc) / 3.0;
    // both probes from one ray along the normal: split at the front probe, over the whole scene
    // and over the parts; the winding numbers as PatchSurface::winding's at each probe
    {
      const Eigen::Vector3d back = mid - h * n;
      ++pairs;
      int nearAll = 0, farAll = 0, nearParts = 0, farParts = 0;
      bool cleanAll = true, cleanParts = true;
      all.splitCrossings(back, n, 2 * h, &nearAll, &farAll, &cleanAll);
      restRays.splitCrossings(back, n, 2 * h, &nearParts, &farParts, &cleanParts);
      partRays.splitCrossings(back, n, 2 * h, &nearParts, &farParts, &cleanParts);
      splitSums += nearAll == nearParts && farAll == farParts;
      splitCleanAgree += cleanAll == cleanParts;
      int atBack = 0, atFront = 0;
      oneRay += windingsAlongRay(
          back, n, 2 * h,
          [&](const Eigen::Vector3d& q, const Eigen::Vector3d& d, double l, int* nearSum, int* farSum, bool* clean) {
            restRays.splitCrossings(q, d, l, nearSum, farSum, clean);
            partRays.splitCrossings(q, d, l, nearSum, farSum, clean);
          },
          [&](const Eigen::Vector3d& q, int k, bool* clean) {
            return restRays.crossings(q, k, clean) + partRays.crossings(q, k, clean);
          },
          &atBack, &atFront);
      int surfaceBack = 0, surfaceFront = 0;
      surface.windingsAlong(back, n, 2 * h, &surfaceBack, &surfaceFront);
      pairAgree += atBack == surface.winding(back) && atFront == surface.winding(mid + h * n) &&
                   surfaceBack == atBack && surfaceFront == atFront;
    }
    for (const double side : {1.0, -1.0}) {
      const Eigen::Vector3d q = mid + side * h * n;
      ++probes;
      for (int k = 0; k < 3; ++k) {
        bool cleanAll = true, cleanParts = true;
        const int w = all.crossings(q, k, &cleanAll);
        const int w2 = restRays.crossings(q, k, &cleanParts) + partRays.crossings(q, k, &cleanParts);
        sums += w == w2;
        cleanAgree += cleanAll == cleanParts;
        unclean += !cleanAll;
      }
      const int fromParts = windingFromRays([&](int k, bool* clean) {
        return restRays.crossings(q, k, clean) + partRays.crossings(q, k, clean);
      });
      windingAgree += fromParts == surface.winding(q);
      inside += fromParts == 1;
    }
  });
  std::printf("%d probes, %d unclean rays, %d inside\n", probes.load(), unclean.load(), inside.load());
  EXPECT_EQ(probes, 2 * static_cast<int>(whole.tri.size()));
  EXPECT_EQ(sums, 3 * probes);
  EXPECT_EQ(cleanAgree, 3 * probes);
  EXPECT_EQ(windingAgree, probes);
  EXPECT_GT(inside, probes / 3);  // about half the probes lie inside (the back sides)
  EXPECT_GT(unclean, 0);          // and the rule meets rays that graze an edge
  std::printf("%d probe pairs, %d decided by the one ray along the normal\n", pairs.load(), oneRay.load());
  EXPECT_EQ(pairs, static_cast<int>(whole.tri.size()));
  EXPECT_EQ(splitSums, pairs);
  EXPECT_EQ(splitCleanAgree, pairs);
  EXPECT_EQ(pairAgree, pairs);
  EXPECT_GE(oneRay, pairs * 99 / 100);  // the ray along the normal crosses cleanly almost everywhere
}

}  // namespace
}  // namespace sf
