// SPDX-License-Identifier: Apache-2.0
// How the refinement ends where the angle test cannot be met. (1) At a fold of a patch: where the
// nearest patch point lies on a fold line (the patch folds over itself and the Jacobian has rank
// 1 there), G - HIP is along no normal. Found on pmp/L.off: of 600 global queries (HIPs uniform
// in its box and pressed in), 34 nearest points ended on the iteration cap (50 evaluations each,
// and a tracker held there ran to the cap at every servo step) after Newton had converged to the
// fold point in 3-5 iterations; the refinement now also stops at a singular point that is a
// strict local minimum of its model within the tolerance (gp_rf_stationary, kernels/gp_refine.h).
// (2) On a boundary edge: an iterate at a corner of two boundary edges, or on a boundary edge, up
// to the last bits of its domain point, took a step of a few eps, which the ratio test rejected
// at the noise of f, and the radius shrank until the refinement stalled (keenan_crane/semi6.obj:
// 11 of 600 nearest points STALLED at boundary corners, tetris.obj and L-plane.obj one each on an
// edge); such a step is now the corner's KKT point, or holds the iterate on the edge at once.
//
// Independent check: each nearest point that converged without meeting the angle test is a local
// minimum of the distance on its patch by dense sampling of the domain around it.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include <smoothforce/force/force_tracking.h>
#include <smoothforce/query/patch_surface.h>
#include "patch_test_support.h"
#include "pressed_hips_support.h"

namespace sf {
namespace {

/// The smallest distance from `hip` to face f's patch over a grid of domain points within `radius`
/// (domain units) of X, spacing radius / 40, inside the domain; infinity where none is.
double sampledNearby(const PatchCache& cache, int f, const Eigen::Vector2d& X, double radius,
                     const Eigen::Vector3d& hip) {
  const int n = cache.faceSize(f);
  double best = std::numeric_limits<double>::infinity();
  for (int i = -40; i <= 40; ++i)
    for (int j = -40; j <= 40; ++j) {
      const Eigen::Vector2d Y = X + radius / 40 * Eigen::Vector2d(i, j);
      if (!insideDomain(n, Y.x(), Y.y())) continue;
      const PatchPoint p = evaluatePatch(cache, f, Y.x(), Y.y());
      if (p.status & SF_ST_OUTSIDE) continue;
      best = std::min(best, (p.pos - hip).norm());
    }
  return best;
}

TEST(RefineEndings, EveryNearestPointConvergesAndThoseOffTheAngleTestAreLocalMinima) {
  constexpr int kHips = 200;  // per mesh, uniform in the bounding box grown by 5% of its diagonal
  const ForceOptions options;
  int meshes = 0;
  long hips = 0, notConverged = 0, onFolds = 0, onEdges = 0, notMinima = 0, foldIterations = 0, edgeIterations = 0,
       edgesIterating = 0;
  for (const std::string& path : test::sharedMeshFiles()) {
    SCOPED_TRACE(path);
    const PatchCache cache = test::cacheFromFile(path);
    const PatchSurface surface(cache);
    PatchRefiner refiner(cache), held(cache);
    const double diag = boundingDiagonal(cache);
    long meshFolds = 0, meshEdges = 0;
    for (const Eigen::Vector3d& hip : test::uniformHipsInBox(cache, kHips, 11)) {
      const RefineResult r = nearestOnPatches(surface, refiner, hip, options).nearest;
      ++hips;
      if (!(r.status & SF_TRACK_CONVERGED)) {
        if (notConverged++ < 3)
          ADD_FAILURE() << "HIP " << hip.transpose() << ": nearest point not converged (face " << r.face
                        << ", status 0x" << std::hex << r.status << std::dec << ")";
        continue;
      }
      // converged without the angle test: on a held edge (its residual along the edge, or a KKT
      // corner), or by the stationarity test at a singular point
      const double tol = std::min(std::sin(options.angleTolerance) * r.distance, options.positionTolerance * diag);
      const double noise = 64 * std::numeric_limits<double>::epsilon() * (hip.cwiseAbs().maxCoeff() + diag);
      if ((r.scp - hip).cross(r.normal).norm() <= std::max(tol, noise)) continue;
      const PatchPoint p = evaluatePatch(cache, r.face, r.xi, r.eta);
      if (r.edge >= 0) {
        ++meshEdges;
      } else {
        ++meshFolds;
        EXPECT_LE(p.dxi.cross(p.deta).norm(), 1e-3 * p.dxi.norm() * p.deta.norm())
            << "HIP " << hip.transpose() << ": converged off the angle test at a regular point";
      }
      const double nearby = std::min(sampledNearby(cache, r.face, {r.xi, r.eta}, 0.02, hip),
                                     sampledNearby(cache, r.face, {r.xi, r.eta}, 2e-4, hip));
      if (!(nearby >= r.distance - 1e-9 * diag)) {
        if (notMinima++ < 3)
          ADD_FAILURE() << "HIP " << hip.transpose() << ": point on face " << r.face << " (edge " << r.edge << ") at "
                        << r.distance << " m, a sampled point nearby at " << nearby << " m";
      }
      // a tracker held there: its next step, from the SCP its last one ended at, does no iteration
      // (on an edge at a singular point the idle rule may take its 6 steps)
      const RefineResult first = held.refine(hip, r.face, r.xi, r.eta, options, r.edge);
      const RefineResult again = held.refineNext(hip, first.face, first.xi, first.eta, options, first.edge);
      (r.edge >= 0 ? edgeIterations : foldIterations) += again.iterations;
      if (r.edge >= 0) {
        edgesIterating += again.iterations > 0;
        EXPECT_LE(again.iterations, 6) << "HIP " << hip.transpose() << ": held on edge " << r.edge;
        if (again.iterations > 0) {
          EXPECT_TRUE(first.status & SF_ST_SINGULAR)
              << "HIP " << hip.transpose() << ": held on edge " << r.edge << " at a regular point, iterates again";
        }
      }
      EXPECT_TRUE(again.status & SF_TRACK_CONVERGED);
    }
    if (meshFolds || meshEdges)
      std::printf("  %s: of %d nearest points, %ld on a fold line, %ld held on a boundary or fold edge\n", path.c_str(),
                  kHips, meshFolds, meshEdges);
    onFolds += meshFolds;
    onEdges += meshEdges;
    ++meshes;
  }
  std::printf(
      "%d meshes, %ld HIPs: %ld nearest points not converged; off the angle test %ld on fold lines, %ld on "
      "edges (%ld not local minima); held there: %ld iterations on folds, %ld on edges (%ld edge points "
      "iterate)\n",
      meshes, hips, notConverged, onFolds, onEdges, notMinima, foldIterations, edgeIterations, edgesIterating);
  EXPECT_EQ(meshes, 28);
  EXPECT_EQ(hips, 28L * kHips);
  EXPECT_EQ(notConverged, 0);
  EXPECT_GT(onFolds, 0);  // the fold points were checked (L.off)
  EXPECT_GT(onEdges, 0);  // and the boundary ones (the open meshes)
  EXPECT_EQ(notMinima, 0);
  EXPECT_EQ(foldIterations, 0);
}

}  // namespace
}  // namespace sf
