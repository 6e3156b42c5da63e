// SPDX-License-Identifier: Apache-2.0
// The error bound of every triangle of the global query's uniform tessellation holds against
// dense sampling: on every shared mesh, at the level the query chooses, the patch point G(X) lies
// within the triangle's bound of the triangle's point at the same domain coordinates X, at every
// point of a barycentric grid of order 4 but the corners and edge midpoints (9 points: 3 inside,
// 6 on the edges; the estimate samples the centroid and the edge midpoints). The bounds are
// estimates from 7 evaluations (surface_tessellation.cpp); this checks them against 9 others,
// and that they are not vacuous (the median bound within 10 times the median sampled deviation).
#include <gtest/gtest.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdio>
#include <vector>

#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/query/patch_surface.h>
#include "patch_test_support.h"
#include "shared_mesh_files.h"
#include "surface_tessellation.h"

namespace sf {
namespace {

TEST(SurfaceErrorBounds, EveryUniformTriangleBoundsItsPatchOnADenseGrid) {
  constexpr int kOrder = 4;
  std::vector<std::array<double, 3>> grid;  // barycentric weights, corners and edge midpoints left out
  for (int i = 0; i <= kOrder; ++i)
    for (int j = 0; i + j <= kOrder; ++j) {
      const int k = kOrder - i - j;
      const bool corner = std::max({i, j, k}) == kOrder,
                 midpoint = std::max({i, j, k}) == 2 && std::min({i, j, k}) == 0;
      if (!corner && !midpoint) grid.push_back({double(i) / kOrder, double(j) / kOrder, double(k) / kOrder});
    }
  ASSERT_EQ(grid.size(), 9u);
  int meshes = 0;
  long triangles = 0, violations = 0, vacuous = 0;
  for (const std::string& path : test::sharedMeshFiles()) {
    SCOPED_TRACE(path);
    const PatchCache cache = test::cacheFromFile(path);
    PatchSurfaceOptions o;
    o.candidates = false;  // the uniform tessellation with its bounds; the adaptive one uses the same bound
    const PatchSurface surface(cache, o);
    const UniformTessellation& u = surface.uniform();
    const size_t n = u.tri.size();
    std::vector<double> dev(n, 0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 512), [&](const tbb::blocked_range<size_t>& r) {
      std::vector<int32_t> faces;
      std::vector<double> xi, eta;
      for (size_t t = r.begin(); t < r.end(); ++t)
        for (const auto& w : grid) {
          const auto& tr = u.tri[t];
          const Eigen::Vector2d X = w[0] * u.domain[tr[0]] + w[1] * u.domain[tr[1]] + w[2] * u.domain[tr[2]];
          faces.push_back(u.triFace[t]);
          xi.push_back(X.x());
          eta.push_back(X.y());
        }
      std::vector<PatchPoint> p(faces.size());
      evaluatePatches(cache, faces.data(), xi.data(), eta.data(), faces.size(), p.data(), Backend::Serial);
      for (size_t t = r.begin(); t < r.end(); ++t) {
        const auto& tr = u.tri[t];
        for (size_t k = 0; k < grid.size(); ++k) {
          const auto& w = grid[k];
          const Eigen::Vector3d lin = w[0] * u.vertex[tr[0]] + w[1] * u.vertex[tr[1]] + w[2] * u.vertex[tr[2]];
          dev[t] = std::max(dev[t], (p[(t - r.begin()) * grid.size() + k].pos - lin).norm());
        }
      }
    });
    long meshViolations = 0;
    for (size_t t = 0; t < n; ++t) {
      if (dev[t] <= u.error[t]) continue;
      if (meshViolations++ < 3)
        ADD_FAILURE() << "triangle " << t << " of face " << u.triFace[t] << ": sampled deviation " << dev[t]
                      << " m above its bound " << u.error[t] << " m";
    }
    // not vacuous: the median bound within 10 times the median sampled deviation (plus the noise)
    std::vector<double> e(u.error.begin(), u.error.end()), d(dev);
    std::nth_element(e.begin(), e.begin() + n / 2, e.end());
    std::nth_element(d.begin(), d.begin() + n / 2, d.end());
    const bool tight = e[n / 2] <= 10 * d[n / 2] + 10 * evaluationNoise(cache);
    vacuous += !tight;
    EXPECT_TRUE(tight) << "median bound " << e[n / 2] << " m, median sampled deviation " << d[n / 2] << " m";
    std::printf("  %s: level %d, %zu triangles, median bound %.3g m, median deviation %.3g m, %ld above their bound\n",
                path.c_str(), u.level, n, e[n / 2], d[n / 2], meshViolations);
    triangles += static_cast<long>(n);
    violations += meshViolations;
    ++meshes;
  }
  std::printf("%d meshes, %ld triangles: %ld sampled deviations above their bound\n", meshes, triangles, violations);
  EXPECT_EQ(meshes, 28);
  EXPECT_GT(triangles, 1000000);
  EXPECT_EQ(violations, 0);
  EXPECT_EQ(vacuous, 0);
}

}  // namespace
}  // namespace sf
