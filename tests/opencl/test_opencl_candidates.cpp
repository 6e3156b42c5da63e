// SPDX-License-Identifier: Apache-2.0
// OpenCLCandidateSearch against PatchSurface::candidates: for every query of every mesh, the same
// triangles in the same order, and the same records (PatchSurface::candidateOf against the host
// search's own), for several caps.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <smoothforce/opencl/opencl_backend.h>
#include <smoothforce/opencl/opencl_candidates.h>
#include <smoothforce/query/global_query.h>
#include <smoothforce/query/patch_surface.h>
#include <smoothforce/sweep/sweep_sampling.h>
#include "patch_test_support.h"

namespace sf {
namespace {

class OpenCLCandidates : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string why;
    if (!openclAvailable(&why)) GTEST_SKIP() << "no OpenCL device: " << why;
  }
};

/// Queries around a surface: its patch points moved along their normals by 0, +-0.1%, +-1%,
/// +-5% and +-20% of the diagonal; points anywhere in its box grown by half the diagonal; and,
/// not searched on the device, a few outside the coordinate range.
std::vector<Eigen::Vector3d> queriesAround(const PatchCache& c, size_t samples, uint64_t seed, size_t* unsearched) {
  const PatchSurfaceSampler sampler(c);
  const double diag = boundingDiagonal(c);
  std::vector<Eigen::Vector3d> q;
  for (const SurfaceSample& s : sampler.sample(samples, seed))
    for (double f : {0.0, 1e-3, -1e-3, 1e-2, -1e-2, 5e-2, -5e-2, 0.2, -0.2}) q.push_back(s.point + f * diag * s.normal);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (int v = 0; v < c.numVertices(); ++v) {
    const Eigen::Vector3d p(c.positions[3 * v], c.positions[3 * v + 1], c.positions[3 * v + 2]);
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> u(-0.5, 1.5);
  for (size_t i = 0; i < samples; ++i)
    q.emplace_back(lo.x() + u(g) * (hi.x() - lo.x()), lo.y() + u(g) * (hi.y() - lo.y()),
                   lo.z() + u(g) * (hi.z() - lo.z()));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(nan, 0, 0), Eigen::Vector3d(1e300, 0, 0)}) q.push_back(p);
  *unsearched = 2;
  return q;
}

TEST_F(OpenCLCandidates, SameTrianglesAndRecordsAsTheHostSearch) {
  size_t meshes = 0;
  for (const char* rel : {"keenan_crane/spot_control_mesh.obj", "polygon_laplacian/quad-sphere.off",
                          "polygon_laplacian/tetris.obj", "polygon_laplacian/L-plane.obj", "pmp/chamfer-cube.off",
                          "geomview/snub_dodecahedron.off", "odedstein/torus.obj"}) {
    for (Precision p : {Precision::Double, Precision::Float}) {
      const PatchCache c = test::cacheFromFile(test::sharedMesh(rel), CrossTangentMode::Corrected, p);
      const PatchSurface surface(c, patchSurfaceOptions(RefineOptions{}));
      OpenCLCandidateSearch device(surface);
      ASSERT_TRUE(device.usable()) << rel;
      EXPECT_EQ(device.numTriangles(), surface.numPointTriangles()) << rel;
      size_t unsearched = 0;
      const std::vector<Eigen::Vector3d> q = queriesAround(c, 150, 7, &unsearched);
      const size_t n = q.size();
      for (int cap : {1, 4, 16, 64}) {
        std::vector<int32_t> ids, count(n, -7);
        std::vector<uint32_t> offset(n, 7);
        device.search(q.data(), n, cap, count.data(), offset.data(), ids);
        size_t compared = 0, notSearched = 0, full = 0, idDiff = 0, recordDiff = 0, countDiff = 0;
        std::vector<SurfaceCandidate> host(static_cast<size_t>(cap));
        for (size_t i = 0; i < n; ++i) {
          if (count[i] < 0) {
            ++notSearched;
            continue;
          }
          const size_t m = surface.candidates(q[i], host.data(), static_cast<size_t>(cap));
          ++compared;
          if (static_cast<size_t>(count[i]) != m) {
            ++countDiff;
            continue;
          }
          full += m == static_cast<size_t>(cap);
          for (size_t j = 0; j < m; ++j) {
            ASSERT_LT(offset[i] + j, ids.size()) << rel;
            const int32_t t = ids[offset[i] + j];
            if (t != host[j].triangle) {
              ++idDiff;
              break;
            }
            const SurfaceCandidate r = surface.candidateOf(q[i], t);
            if (std::memcmp(&r.X, &host[j].X, sizeof r.X) || std::memcmp(&r.distance, &host[j].distance, 8) ||
                std::memcmp(&r.lower, &host[j].lower, 8) || r.face != host[j].face)
              ++recordDiff;
          }
        }
        EXPECT_EQ(notSearched, unsearched) << rel << " cap " << cap;
        EXPECT_EQ(compared, n - unsearched) << rel << " cap " << cap;
        EXPECT_EQ(countDiff, 0u) << rel << " cap " << cap;
        EXPECT_EQ(idDiff, 0u) << rel << " cap " << cap;
        EXPECT_EQ(recordDiff, 0u) << rel << " cap " << cap;
        if (cap == 1) EXPECT_EQ(full, compared) << rel;  // every searched query has a candidate
        if (cap == 64) EXPECT_LT(full, compared) << rel;  // and complete lists among them
      }
      ++meshes;
    }
  }
  EXPECT_EQ(meshes, 14u);
}

TEST_F(OpenCLCandidates, RefusesBadCapsAndHandlesEmptyBatches) {
  const PatchCache c = test::cacheFromFile(test::sharedMesh("geomview/dodecahedron.off"));
  const PatchSurface surface(c);
  OpenCLCandidateSearch device(surface);
  std::vector<int32_t> ids;
  int32_t count[1] = {-7};
  uint32_t offset[1] = {7};
  const Eigen::Vector3d q(0, 0, 0);
  EXPECT_THROW(device.search(&q, 1, 0, count, offset, ids), std::invalid_argument);
  EXPECT_THROW(device.search(&q, 1, 65, count, offset, ids), std::invalid_argument);
  device.search(&q, 0, 4, count, offset, ids);  // nothing to do
  EXPECT_TRUE(ids.empty());
  device.search(&q, 1, 16, count, offset, ids);
  EXPECT_GE(count[0], 1);
  EXPECT_EQ(ids.size(), static_cast<size_t>(count[0]));
  EXPECT_EQ(offset[0], 0u);
}

}  // namespace
}  // namespace sf
