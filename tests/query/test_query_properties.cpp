// SPDX-License-Identifier: Apache-2.0
// Properties of the SCP query over whole meshes: for every closed mesh of
// ../shared/meshes and generated analytic shapes, 10^4 HIPs pressed in along the patch normal at
// three depths, each a contact start (and, on the tessellation, a global query without a seed);
// and constant-depth trajectories across many patch
// boundaries. Checked against DenseOracle (its own ray parity and nearest point on a dense
// tessellation), never against the production query's own decisions.
#include <gtest/gtest.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <map>
#include <mutex>
#include <random>

#include <smoothforce/force/force_method.h>
#include <smoothforce/force/force_tracking.h>
#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/query/embree_scene.h>
#include <smoothforce/query/global_query.h>
#include <smoothforce/sweep/sweep_sampling.h>
#include "gp_config.h"
#include "patch_test_support.h"
#include "query_test_support.h"

namespace sf {
namespace {

/// The HIPs at surface faults of the mesh itself, at most: a HIP whose true nearest patch point
/// has the HIP on the side its normal does not predict (the winding number disagrees with the
/// tangent plane there), or pressed into a folded patch (GP_ST_FOLD) where sheets about as near
/// see it on both sides, lies at a folded or overlapping part of the patch surface, where no
/// nearest-point rule can render a consistent force. Measured: the spot control cage (16 patches
/// fold where its vertex normals oppose the face normals) 1.7% (171 of 10,002); none elsewhere.
double faultBound(const std::string& shape) { return shape == "keenan_crane/spot_control_mesh.obj" ? 0.025 : 0.0; }

class QueryProperties : public ::testing::TestWithParam<std::string> {};

// Contact iff inside (the dense oracle's ray parity), at a contact start, for every HIP not at
// a surface fault; the SCP of a contact start is the global nearest point (within 1e-6 of the
// diagonal of the oracle's refined nearest point); every SCP in contact is stationary
// (|(HIP - SCP) x n| <= 1e-9 of the diagonal) unless it is held on a fold edge (counted).
/// Where the contact-start tests run: the built cache with the tessellation index (PatchSurface)
/// or the bounds index (LazyPatchSurface over the built patches), or a skeleton of it whose
/// patches are built lazily (LazyPatchSurface).
enum class Query { Tessellation, Bounds, Lazy };

/// The HIPs of the contact-start tests on one shape and the dense oracle's answers there (its
/// ray parity and refined nearest point), computed once for the three queries.
struct ContactStarts {
  static constexpr int kPerDepth = 3334;  // 10,002 HIPs
  std::shared_ptr<const PatchCache> cache;
  double diag = 0;
  std::vector<SurfaceSample> samples;
  double depths[3] = {0, 0, 0};
  std::vector<char> truth, agree;                   ///< per HIP: inside by the oracle's rays; the rays agree
  std::vector<test::DenseOracle::Nearest> nearest;  ///< per HIP
  int level = 0;
  size_t triangles = 0;

  explicit ContactStarts(const std::string& shape) : cache(test::closedShapeCache(shape)) {
    diag = boundingDiagonal(*cache);
    const test::DenseOracle oracle(*cache);
    level = oracle.level();
    triangles = oracle.numTriangles();
    const PatchSurfaceSampler sampler(*cache, cache->numFaces() > 4000 ? 2 : 6);
    samples = sampler.sample(kPerDepth, 20261121);
    const double d[3] = {0.001 * diag, 0.0025 * diag, 0.01 * diag};
    std::copy(d, d + 3, depths);
    truth.assign(3 * kPerDepth, 0);
    agree.assign(3 * kPerDepth, 0);
    nearest.resize(3 * kPerDepth);
    tbb::enumerable_thread_specific<std::unique_ptr<PatchRefiner>> refiners(
        [&] { return std::make_unique<PatchRefiner>(*cache); });
    tbb::parallel_for(0, 3 * kPerDepth, [&](int g) {
      const Eigen::Vector3d h = hip(g);
      bool rays = true;
      truth[g] = oracle.winding(h, &rays) >= 1;
      agree[g] = rays;
      nearest[g] = oracle.nearest(h, *refiners.local());
    });
  }
  const SurfaceSample& sample(int g) const { return samples[g % kPerDepth]; }
  double depth(int g) const { return depths[g / kPerDepth]; }
  Eigen::Vector3d hip(int g) const { return sample(g).point - depth(g) * sample(g).normal; }
};

/// The body of the contact-start tests, on every `stride`-th HIP of c.
void checkContactStarts(const std::string& shape, const ContactStarts& c, Query query, int stride) {
  const bool lazy = query == Query::Lazy;
  // both box queries decide inside by the nearest point's side (no winding number near the surface)
  const bool boxes = query != Query::Tessellation;
  const std::shared_ptr<const PatchCache>& cache = c.cache;
  const auto skeleton = lazy ? std::make_shared<const PatchCache>(test::skeletonOf(*cache)) : nullptr;
  const double diag = c.diag;
  auto surface = boxes ? nullptr : std::make_shared<const PatchSurface>(*cache);
  ForceOptions options;
  options.surfaceIndex = query == Query::Bounds ? SurfaceIndex::Bounds : SurfaceIndex::Auto;
  tbb::enumerable_thread_specific<std::unique_ptr<ForceRenderer>> renderers([&] {
    if (lazy)
      return makeForceRenderer(skeleton, std::make_shared<const PolygonScene>(*skeleton), ForceMethod::Patch, options);
    return makeForceRenderer(cache, std::make_shared<const PolygonScene>(*cache), ForceMethod::Patch, options, surface);
  });
  tbb::enumerable_thread_specific<std::unique_ptr<PatchRefiner>> refiners(
      [&] { return std::make_unique<PatchRefiner>(*cache); });
  std::atomic<int> tested{0}, faults{0}, lazyFaults{0}, mismatches{0}, inside{0}, contacts{0}, notNearest{0},
      notStationary{0}, foldEdges{0}, raysDisagree{0}, globalFarther{0};
  std::mutex printMutex;
  int printed = 0;
  tbb::parallel_for(0, 3 * ContactStarts::kPerDepth, [&](int g) {
    if (g % stride != 0) return;
    const SurfaceSample& p = c.sample(g);
    const double depth = c.depth(g);
    const Eigen::Vector3d hip = c.hip(g);
    ForceRenderer& R = *renderers.local();
    R.reset();
    R.step(p.point + 1e-3 * depth * p.normal);  // the approach, out of contact
    const ForceSample s = R.step(hip);
    const bool truth = c.truth[g];
    raysDisagree += !c.agree[g];
    const test::DenseOracle::Nearest& q = c.nearest[g];
    ++tested;
    // a surface fault here (excluded, counted): the true nearest point has the HIP on the side its
    // normal does not predict, or, at a folded patch, sheets within 1.5x of that distance see the
    // HIP on both sides
    const bool folded = cache->faceStatus[p.face] & GP_ST_FOLD;
    if (((hip - q.point).dot(q.normal) < 0) != truth || (folded && q.conflicting(1.5))) {
      ++faults;
      return;
    }
    // box queries: no winding number near the surface (lazy_surface.h); where sheets within 3x
    // of the nearest distance see the HIP on both sides (folded or overlapping patches), a wrong
    // contact start or SCP counts as a surface fault too (bounded like the others)
    const bool lazyWrong = s.contact != truth || (s.contact && (s.scp - hip).norm() > q.distance + 1e-6 * diag);
    if (boxes && q.conflicting(3.0) && lazyWrong) {
      ++faults;
      ++lazyFaults;
      return;
    }
    // the batch query's global nearest point (no seed, no state): never farther than the oracle's
    if (surface) {
      const PatchNearest global = nearestOnPatches(*surface, *refiners.local(), hip, options);
      if (!(global.nearest.distance <= q.distance + 1e-6 * diag)) {
        ++globalFarther;
        std::lock_guard<std::mutex> lock(printMutex);
        if (printed++ < 5)
          ADD_FAILURE() << shape << ": HIP " << g << " at depth " << depth / diag << " x diagonal: global query "
                        << global.nearest.distance / diag << " x diagonal on face " << global.nearest.face
                        << ", nearest face " << q.face << " at " << q.distance / diag;
      }
    }
    inside += truth;
    contacts += s.contact;
    if (s.contact != truth) {
      ++mismatches;
      std::lock_guard<std::mutex> lock(printMutex);
      if (printed++ < 5)
        ADD_FAILURE() << shape << ": HIP " << g << " at depth " << depth / diag << " x diagonal: contact " << s.contact
                      << ", inside " << truth << ", status " << std::hex << s.status << std::dec << "; sample face "
                      << p.face << ", nearest face " << q.face << " at " << q.distance / diag << " x diagonal"
                      << (cache->faceStatus[q.face] & GP_ST_FOLD ? " (folded)" : "");
    }
    if (!s.contact) return;
    if (s.status & SF_TRACK_FOLD_EDGE) {
      ++foldEdges;
    } else if ((hip - s.scp).cross(s.normal).norm() > 1e-9 * diag) {
      ++notStationary;
    }
    if ((s.scp - hip).norm() > q.distance + 1e-6 * diag) {
      ++notNearest;
      std::lock_guard<std::mutex> lock(printMutex);
      if (printed++ < 5)
        ADD_FAILURE() << shape << ": HIP " << g << " at depth " << depth / diag << " x diagonal: SCP on face " << s.face
                      << " at " << (s.scp - hip).norm() / diag << " x diagonal, nearest face " << q.face << " at "
                      << q.distance / diag << (cache->faceStatus[q.face] & GP_ST_FOLD ? " (folded)" : "");
    }
  });
  const int n = tested.load();
  std::printf(
      "  %s%s: %d HIPs (dense level %d, %zu triangles): %d inside, %d in contact; surface faults %d; "
      "fold-edge SCPs %d; rays disagreeing %d; lazy faults %d; global queries (no seed) farther %d\n",
      shape.c_str(),
      lazy    ? " (lazy patches)"
      : boxes ? " (bounds index)"
              : "",
      n, c.level, c.triangles, inside.load(), contacts.load(), faults.load(), foldEdges.load(), raysDisagree.load(),
      lazyFaults.load(), globalFarther.load());
  ::testing::Test::RecordProperty(lazy    ? "surface_faults_lazy"
                                  : boxes ? "surface_faults_bounds"
                                          : "surface_faults",
                                  faults.load());
  ASSERT_EQ(n, (3 * ContactStarts::kPerDepth + stride - 1) / stride);
  EXPECT_EQ(mismatches.load(), 0) << shape;
  EXPECT_EQ(notNearest.load(), 0) << shape;
  EXPECT_EQ(globalFarther.load(), 0) << shape;
  EXPECT_EQ(notStationary.load(), 0) << shape;
  EXPECT_LE(faults.load(), faultBound(shape) * n) << shape;
  EXPECT_LE(foldEdges.load(), faultBound(shape) * n) << shape << ": SCPs held on fold edges";
  EXPECT_GE(inside.load(), n * 9 / 10) << shape << ": the HIPs should mostly be inside";
}

// The three queries on the same 10,002 HIPs and oracle answers: the tessellation index at every
// HIP; the bounds index on the built cache (what the servo loop holds) and a skeleton of the mesh,
// patches built lazily where the query needs them, at every third HIP (the three depths of each
// sample in turn).
TEST_P(QueryProperties, ContactStartsIffInsideAtTheNearestStationaryPointOnEveryIndex) {
  const ContactStarts c(GetParam());
  {
    SCOPED_TRACE("tessellation index");
    checkContactStarts(GetParam(), c, Query::Tessellation, 1);
  }
  {
    SCOPED_TRACE("bounds index");
    checkContactStarts(GetParam(), c, Query::Bounds, 3);
  }
  {
    SCOPED_TRACE("lazy patches");
    checkContactStarts(GetParam(), c, Query::Lazy, 3);
  }
}

/// Largest angle between the normals of neighbouring points of a path, rad.
double maxTurn(const test::SurfacePath& p) {
  double t = 0;
  for (size_t i = 1; i < p.normal.size(); ++i)
    t = std::max(t, std::acos(std::clamp(p.normal[i].dot(p.normal[i - 1]), -1.0, 1.0)));
  return t;
}

// Constant-depth slides across many patch boundaries, generated on the surface itself
// (walkSurface, 15% of the diagonal long), at 0.1% and 0.25% of the diagonal: every step in
// contact with |F| within 1.5x of k x depth, no refinement at its iteration cap, every SCP
// stationary, and the largest consecutive force change halves (ratio <= 0.6) when the step
// halves. The step is the largest (from 0.2% of the diagonal down, halving) at which the half-step
// path resolves the surface: its normal turns by at most 1 degree between neighbouring points
// (Gregory patches are G1, but their curvature grows without bound towards the corners, so some
// turns are sharp). Left out, and counted: slides that cross a folded patch or stop at a fold edge,
// slides that even 1/128 of that step does not resolve, and per depth, slides where the depth
// exceeds the local feature size (the SCP leaves the foot point where the dense oracle finds a
// surface point nearer the HIP than the foot point), where the nearest point itself jumps.
TEST_P(QueryProperties, SlidesAtConstantDepthAreSmooth) {
  const std::string shape = GetParam();
  const auto cache = test::closedShapeCache(shape);
  const double diag = boundingDiagonal(*cache);
  const test::DenseOracle oracle(*cache);
  PatchRefiner walker(*cache);
  const PatchSurfaceSampler sampler(*cache, cache->numFaces() > 4000 ? 2 : 6);
  const std::vector<SurfaceSample> starts = sampler.sample(12, 7);
  auto surface = std::make_shared<const PatchSurface>(*cache);
  const ForceOptions options;
  auto R = makeForceRenderer(cache, std::make_shared<const PolygonScene>(*cache), ForceMethod::Patch, options, surface);
  std::mt19937 rng(3);
  std::normal_distribution<double> gauss;
  int slides = 0, folded = 0, unresolved = 0, tooDeep = 0, notFoot = 0, crossings = 0, capHits = 0, notStationary = 0,
      outOfContact = 0, badForce = 0;
  double worstRatio = 0, smallestStep = 1;
  const double length = 0.15 * diag;
  for (const SurfaceSample& s0 : starts) {
    const Eigen::Vector3d dir(gauss(rng), gauss(rng), gauss(rng));
    double step = 0.002 * diag;
    test::SurfacePath coarse, fine;
    bool resolved = false;
    for (int halvings = 0; halvings <= 7 && !resolved; ++halvings, step /= 2) {
      coarse = test::walkSurface(*cache, walker, s0.face, {s0.xi, s0.eta}, dir, step, int(length / step) + 1);
      fine = test::walkSurface(*cache, walker, s0.face, {s0.xi, s0.eta}, dir, step / 2, 2 * int(length / step) + 1);
      resolved = maxTurn(fine) <= 1 * M_PI / 180;
    }
    step *= 2;  // the loop halved it once more
    bool onFold = coarse.point.size() < size_t(length / step) + 1 || fine.point.size() < 2 * size_t(length / step) + 1;
    for (int f : coarse.face) onFold = onFold || (cache->faceStatus[f] & GP_ST_FOLD);
    for (int f : fine.face) onFold = onFold || (cache->faceStatus[f] & GP_ST_FOLD);
    if (onFold) {
      ++folded;
      continue;
    }
    if (!resolved) {
      ++unresolved;
      continue;
    }
    smallestStep = std::min(smallestStep, step / diag);
    crossings += coarse.faceChanges;
    for (double depth : {0.001 * diag, 0.0025 * diag}) {
      double maxDf[2] = {0, 0};
      bool deep = false;
      int wrongScp = 0;
      size_t maxAt[2] = {0, 0};
      ForceSample maxS[2][2];
      for (int h = 0; h < 2; ++h) {
        const test::SurfacePath& path = h ? fine : coarse;
        R->reset();
        R->step(path.point[0] + 1e-3 * depth * path.normal[0]);
        Eigen::Vector3d prev(0, 0, 0);
        for (size_t i = 0; i < path.point.size(); ++i) {
          const Eigen::Vector3d hip = path.point[i] - depth * path.normal[i];
          const ForceSample s = R->step(hip);
          // the SCP should be the foot point; where it is not, either the depth exceeds the local
          // feature size there (a surface point nearer than the foot point: left out) or the
          // tracker is wrong
          if (s.contact && (s.scp - path.point[i]).norm() > 1e-6 * diag) {
            if (oracle.nearest(hip, walker).distance < depth * (1 - 1e-6))
              deep = true;
            else
              ++wrongScp;
          }
          outOfContact += !s.contact;
          capHits += (s.status & SF_TRACK_MAX_ITER) != 0;
          if (s.contact && (hip - s.scp).cross(s.normal).norm() > 1e-9 * diag) ++notStationary;
          const double k = s.force.norm() / (options.stiffness * depth);
          badForce += s.contact && !(k <= 1.5 && k >= 1 / 1.5);
          if (i > 0 && (s.force - prev).norm() > maxDf[h]) {
            maxDf[h] = (s.force - prev).norm();
            maxAt[h] = i;
            maxS[h][1] = s;
          }
          if (i + 1 == maxAt[h] + 1) maxS[h][0] = maxS[h][1];
          prev = s.force;
        }
      }
      if (deep) {
        ++tooDeep;
        continue;
      }
      ++slides;
      notFoot += wrongScp;
      worstRatio = std::max(worstRatio, maxDf[1] / maxDf[0]);
      if (maxDf[1] / maxDf[0] > 0.6)
        std::printf(
            "    slide from face %d, depth %.4g: max |dF| %.4g N at point %zu (face %d) / %.4g N at %zu (face %d) "
            "of the half step; step %.3g x diagonal\n",
            s0.face, depth / diag, maxDf[0], maxAt[0], maxS[0][1].face, maxDf[1], maxAt[1], maxS[1][1].face,
            step / diag);
    }
  }
  std::printf(
      "  %s: %d slides of 24 (%d starts on folded patches, %d not resolved, %d too deep for the local "
      "feature size), %d patch crossings per depth, smallest step %.3g x diagonal; worst half-step ratio "
      "%.3f; out of contact %d, cap hits %d, not stationary %d, |F| off %d, SCP off the foot point %d\n",
      shape.c_str(), slides, folded, unresolved, tooDeep, crossings, smallestStep, worstRatio, outOfContact, capHits,
      notStationary, badForce, notFoot);
  ::testing::Test::RecordProperty("slides", slides);
  // at least half of the 24 generated slides measured; the others are counted above with their
  // reason (armadillo: 9 of 24 deeper than the local feature size of its thin limbs)
  EXPECT_GE(slides, 12) << shape;
  // the slides are 15% of the diagonal long: a 6-face cube or a dodecahedron has few boundaries
  // to cross within that; every mesh of >= 40 faces must give 10 per depth
  EXPECT_GE(crossings, std::min(10, cache->numFaces() / 4)) << shape << ": the slides must cross patch boundaries";
  EXPECT_EQ(outOfContact, 0) << shape;
  EXPECT_EQ(capHits, 0) << shape;
  EXPECT_EQ(notStationary, 0) << shape;
  EXPECT_EQ(badForce, 0) << shape;
  EXPECT_EQ(notFoot, 0) << shape;
  // A continuous force halves its largest consecutive change with the step (ratio 0.5); a jump
  // keeps it (ratio ~1). The Gregory patch's curvature grows without bound towards its corners,
  // so on a slide passing close to a corner the largest change falls a little slower than the
  // step (measured up to 0.68 on the dense triangle meshes, whose slides pass near many
  // corners); 0.7 keeps a clear margin from a jump.
  EXPECT_LE(worstRatio, 0.7) << shape;
}

INSTANTIATE_TEST_SUITE_P(Shapes, QueryProperties, ::testing::ValuesIn(test::closedShapes()),
                         [](const ::testing::TestParamInfo<std::string>& i) { return test::shapeTestName(i.param); });

}  // namespace
}  // namespace sf
