// SPDX-License-Identifier: Apache-2.0
// visitRingPoints (tessellate.h), the bounded-batch evaluation of the level-L ring points that the
// sweep's section loop and projection seeds use: every built face is visited once, in order, with
// the very points tessellatePatches evaluates (the same bits), whatever the batches.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/patch/tessellate.h>
#include "patch_test_support.h"

namespace sf {
namespace {

BatchEvaluator cpuEvaluator(const PatchCache& c) {
  return [&c](const int32_t* f, const double* x, const double* y, size_t n, PatchPoint* out) {
    evaluatePatches(c, f, x, y, n, out, Backend::Tbb);
  };
}

bool sameBits(const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return std::memcmp(a.data(), b.data(), 24) == 0; }

/// Visits c's built faces at `level` and checks them against tessellatePatches: the number of
/// faces and points, and every point's position, normal and status bit for bit. Returns the
/// points visited and counts the batches (calls of the evaluator).
size_t expectVisitsAsTessellation(const PatchCache& c, int level, size_t* batches) {
  const TriangleMesh tm = tessellatePatches(c, level, cpuEvaluator(c));
  const std::vector<int32_t> faces = builtFaces(c);
  size_t next = 0, visited = 0, mismatched = 0;
  std::vector<size_t> order;
  *batches = 0;
  const BatchEvaluator counting = [&](const int32_t* f, const double* x, const double* y, size_t n, PatchPoint* out) {
    ++*batches;
    evaluatePatches(c, f, x, y, n, out, Backend::Tbb);
  };
  std::vector<Eigen::Vector2d> dom;
  visitRingPoints(c, level, faces.data(), faces.size(), counting,
                  [&](size_t i, const Eigen::Vector2d* X, const PatchPoint* p, size_t m) {
    order.push_back(i);
    dom.clear();
    domainRingPoints(c.faceSize(faces[i]), level, dom);
    EXPECT_EQ(dom.size(), m);
    for (size_t v = 0; v < m && v < dom.size(); ++v) mismatched += dom[v] != X[v];
    const int n = c.faceSize(faces[i]);
    EXPECT_EQ(m, size_t(1 + n * level * (level + 1) / 2)) << "face " << faces[i];
    EXPECT_EQ(tm.firstVertex[faces[i]], int32_t(next)) << "face " << faces[i];
    for (size_t v = 0; v < m && next + v < tm.positions.size(); ++v)
      mismatched += !sameBits(p[v].pos, tm.positions[next + v]) || !sameBits(p[v].normal, tm.normals[next + v]) ||
                    p[v].status != tm.status[next + v];
    next += m;
    visited += m;
  });
  EXPECT_EQ(order.size(), faces.size());
  for (size_t i = 0; i < order.size(); ++i) EXPECT_EQ(order[i], i);
  EXPECT_EQ(visited, tm.positions.size());
  EXPECT_EQ(mismatched, 0u);
  return visited;
}

TEST(RingPoints, EveryBuiltFaceVisitedWithTessellatePatchesPoints) {
  int meshes = 0;
  size_t points = 0, batches = 0;
  for (const std::string& path : test::sharedMeshFiles(600'000)) {
    SCOPED_TRACE(path);
    const PatchCache c = test::cacheFromFile(path);
    for (int level : {1, 4}) {
      size_t b = 0;
      points += expectVisitsAsTessellation(c, level, &b);
      batches += b;
    }
    ++meshes;
  }
  std::printf("%d meshes, levels 1 and 4: %zu ring points in %zu batches\n", meshes, points, batches);
  EXPECT_GE(meshes, 20);
}

// At level 64 a quad has 8,321 ring points: the spot cage's 180 faces take several batches of
// about 2^18 points, and the faces at their seams are visited whole.
TEST(RingPoints, LargeLevelsSplitIntoBatchesWithoutSplittingFaces) {
  const PatchCache c = test::cacheFromFile(std::string(SF_DATA_DIR) + "/spot_control_mesh.obj");
  size_t batches = 0;
  const size_t points = expectVisitsAsTessellation(c, 64, &batches);
  EXPECT_GT(points, size_t(1) << 20);
  EXPECT_GE(batches, points >> 18);
  EXPECT_LE(batches, (points >> 18) + 2);
}

// A face that is not built (more sides than GP_MAX_N) is neither listed nor visited.
TEST(RingPoints, FacesNotBuiltAreLeftOut) {
  ref::RefMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  m.faces = {{0, 1, 2, 3}};
  const int sides = GP_MAX_N + 2;
  std::vector<int> big;
  for (int k = 0; k < sides; ++k) {
    const double a = 2 * M_PI * k / sides;
    big.push_back(static_cast<int>(m.positions.size()));
    m.positions.emplace_back(3 + std::cos(a), std::sin(a), 0);
  }
  m.faces.push_back(big);
  m.normals.assign(m.positions.size(), Eigen::Vector3d::UnitZ());
  const PatchCache c = test::cacheFromShape(m);
  ASSERT_TRUE(c.faceStatus[1] & GP_ST_TOO_MANY_SIDES);
  EXPECT_EQ(builtFaces(c), std::vector<int32_t>{0});
  size_t batches = 0;
  EXPECT_EQ(expectVisitsAsTessellation(c, 3, &batches), 1u + 4 * 3 * 4 / 2);
}

}  // namespace
}  // namespace sf
