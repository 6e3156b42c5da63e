// The sweep's default trajectory (defaultTrajectory): a section of the patch surface on every
// bundled mesh, flat ones included, and a sweep that runs without one where no section exists.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/patch/tessellate.h>
#include <smoothforce/sweep/sweep_run.h>
#include <smoothforce/sweep/sweep_sampling.h>
#include "patch_test_support.h"
#include "query_test_support.h"
#include "test_sweep_support.h"

namespace sf {
namespace {

/// The box of the level-L tessellation of the patches (the box the section planes cut).
void tessellationBox(const PatchCache& c, int level, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
  const TriangleMesh tm =
      tessellatePatches(c, level, [&](const int32_t* f, const double* x, const double* y, size_t n, PatchPoint* out) {
        evaluatePatches(c, f, x, y, n, out, Backend::Serial);
      });
  lo = Eigen::Vector3d::Constant(INFINITY);
  hi = -lo;
  for (const auto& p : tm.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
}

// Every bundled mesh has a default trajectory: points in one plane through the box's centre
// normal to an axis (the shortest, or, on a flat mesh, another), every one on the patch surface
// by the dense oracle (within the level-8 tessellation's chord error, where no patch folds).
TEST(DefaultTrajectory, EveryBundledMeshHasASectionOnItsSurface) {
  constexpr int kLevel = 8;
  int meshes = 0, flat = 0;
  size_t points = 0, bounded = 0, nearFold = 0;
  for (const std::string& path : test::sharedMeshFiles()) {
    SCOPED_TRACE(path);
    const PatchCache c = test::cacheFromFile(path);
    const std::vector<Eigen::Vector3d> loop = defaultTrajectory(c, kLevel);
    ASSERT_GE(loop.size(), 2u);
    ASSERT_GT(polylineLength(loop), 0.0);
    Eigen::Vector3d lo, hi;
    tessellationBox(c, kLevel, lo, hi);
    const double diag = (hi - lo).norm();
    const Eigen::Vector3d mid = 0.5 * (lo + hi), extent = hi - lo;
    int shortest = 0;
    extent.minCoeff(&shortest);
    const bool isFlat = extent[shortest] <= 1e-9 * diag;
    int axis = -1;  // the axis whose centre plane holds every point
    for (int a = 0; a < 3 && axis < 0; ++a) {
      bool all = true;
      for (const auto& p : loop) all = all && std::abs(p[a] - mid[a]) <= 1e-12 * diag;
      if (all && !(isFlat && a == shortest)) axis = a;  // a flat mesh lies in its shortest axis's plane
    }
    ASSERT_GE(axis, 0) << "the points lie in no centre plane normal to an axis";
    if (isFlat) {
      EXPECT_NE(axis, shortest);
      ++flat;
    } else {
      EXPECT_EQ(axis, shortest);
    }
    // where a patch folds, the tessellation's triangles flip and their chords leave the patch
    // (the sweep projects every trajectory point onto the patches before probing): the points
    // nearest a folded patch are counted, not bounded
    const test::DenseOracle oracle(c, 100000);
    PatchRefiner refiner(c);
    double worst = 0;
    for (const auto& p : loop) {
      const test::DenseOracle::Nearest q = oracle.nearest(p, refiner);
      ASSERT_GE(q.face, 0);
      if (c.faceStatus[q.face] & GP_ST_FOLD) {
        ++nearFold;
        continue;
      }
      worst = std::max(worst, q.distance);
      ++bounded;
    }
    EXPECT_LE(worst, 5e-3 * diag);  // measured: at most 3.3e-3 (tetris.obj, a chord past a reflex corner)
    std::printf("  %s: %zu points on axis %d, %.3g m long, at most %.2g of the diagonal off the patches\n",
                path.substr(path.rfind('/') + 1).c_str(), loop.size(), axis, polylineLength(loop), worst / diag);
    ++meshes;
    points += loop.size();
  }
  EXPECT_EQ(meshes, static_cast<int>(test::sharedMeshFiles().size()));
  EXPECT_GE(meshes, 20);
  EXPECT_EQ(flat, 5);  // pmp/L.off, keenan_crane/semi2.obj, semi6.obj in z = 0, L-plane.obj, tetris.obj
  EXPECT_EQ(bounded + nearFold, points);
  EXPECT_GE(bounded, points * 9 / 10);
  std::printf("  %d meshes (%d flat), %zu trajectory points, %zu of them nearest a folded patch\n", meshes, flat,
              points, nearFold);
}

/// Two unit quads (normals +z) at opposite corners of their box: no centre plane normal to an
/// axis meets either.
std::shared_ptr<const PatchCache> twoApartQuads() {
  ref::RefMesh m;
  for (const double o : {0.0, 10.0})
    for (const auto& v :
         {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(1, 1, 0), Eigen::Vector3d(0, 1, 0)})
      m.positions.push_back(v + Eigen::Vector3d::Constant(o));
  m.faces = {{0, 1, 2, 3}, {4, 5, 6, 7}};
  m.normals.assign(8, Eigen::Vector3d::UnitZ());
  return std::make_shared<const PatchCache>(test::cacheFromShape(m));
}

// A sweep asked for no trajectory runs without the default one where no section exists, and
// says so, rather than refusing the whole sweep over a series the user did not ask for.
TEST(DefaultTrajectory, ASweepWithoutASectionRunsWithoutTrajectoryAndNotesIt) {
  const auto cache = twoApartQuads();
  EXPECT_TRUE(defaultTrajectory(*cache, 8).empty());
  SweepInputs in;
  in.cache = cache;
  in.config.source = "two quads";
  in.config.methods = {"fake"};
  in.config.samples = 200;
  in.depths = parseDepthList("1%");
  in.makeRenderer = [](const std::string&) { return std::make_unique<sweeptest::FakeSphere>(1.0, 500); };
  std::vector<std::string> notes;
  SweepControl control;
  control.note = [&](const std::string& n) { notes.push_back(n); };
  const SweepData d = runSweep(in, control);
  EXPECT_TRUE(d.trajectories.empty());
  ASSERT_EQ(d.results.size(), 1u);
  EXPECT_EQ(d.results[0].size(), 200u);
  for (const HipResult& r : d.results[0]) EXPECT_TRUE(r.done);
  const auto said = std::count_if(notes.begin(), notes.end(), [](const std::string& n) {
    return n.find("sweep: note: no default trajectory:") == 0;
  });
  EXPECT_EQ(said, 1);
}

}  // namespace
}  // namespace sf
