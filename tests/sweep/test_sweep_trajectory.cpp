// SPDX-License-Identifier: Apache-2.0
// The sweep's default trajectory (defaultTrajectory): a section of the patch surface on every
// bundled mesh, flat ones included, and a sweep that runs without one where no section exists.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
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
/// The section as defined: the whole level-L tessellation, its patches' boundary copies welded
/// on a grid of 1e-7 of its box's diagonal (a key's first copy gives the vertex), cut by the
/// first plane (shortest non-flat axis first) that meets it.
std::vector<Eigen::Vector3d> wholeTessellationSection(const PatchCache& c, int level) {
  const TriangleMesh tm =
      tessellatePatches(c, level, [&](const int32_t* f, const double* x, const double* y, size_t n, PatchPoint* out) {
        evaluatePatches(c, f, x, y, n, out, Backend::Tbb);
      });
  if (tm.triangles.empty()) return {};
  Eigen::Vector3d lo = tm.positions[0], hi = lo;
  for (const auto& p : tm.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double tol = 1e-7 * std::max((hi - lo).norm(), 1e-300);
  std::map<std::array<long long, 3>, int> weld;
  std::vector<int> id(tm.positions.size());
  std::vector<Eigen::Vector3d> P;
  for (size_t i = 0; i < tm.positions.size(); ++i) {
    std::array<long long, 3> key;
    for (int a = 0; a < 3; ++a) key[a] = std::llround(tm.positions[i][a] / tol);
    auto [it, fresh] = weld.emplace(key, static_cast<int>(P.size()));
    if (fresh) P.push_back(tm.positions[i]);
    id[i] = it->second;
  }
  std::vector<std::array<int, 3>> tri;
  for (const auto& t : tm.triangles) {
    const std::array<int, 3> v = {id[t[0]], id[t[1]], id[t[2]]};
    if (v[0] != v[1] && v[1] != v[2] && v[0] != v[2]) tri.push_back(v);
  }
  const Eigen::Vector3d extent = hi - lo;
  std::array<int, 3> axes = {0, 1, 2};
  std::stable_sort(axes.begin(), axes.end(), [&](int a, int b) { return extent[a] < extent[b]; });
  for (const int axis : axes) {
    if (!(extent[axis] > 1e-9 * extent.norm())) continue;
    std::vector<Eigen::Vector3d> s = longestSection(P, tri, axis, 0.5 * (lo[axis] + hi[axis]));
    if (!s.empty()) return s;
  }
  return {};
}

// defaultTrajectory evaluates every face for the box but welds and cuts only the faces near the
// plane (and every face that shares a weld cell with theirs): the section of the whole welded
// tessellation, point for point and bit for bit, on every bundled mesh up to 600 kB and the
// spot cage in float.
TEST(DefaultTrajectory, IsTheSectionOfTheWholeWeldedTessellation) {
  int meshes = 0;
  size_t points = 0;
  std::vector<std::pair<std::string, Precision>> inputs;
  for (const std::string& path : test::sharedMeshFiles(600'000)) inputs.emplace_back(path, Precision::Double);
  inputs.emplace_back(std::string(SF_DATA_DIR) + "/spot_control_mesh.obj", Precision::Float);
  for (const auto& [path, precision] : inputs) {
    SCOPED_TRACE(path);
    const PatchCache c = test::cacheFromFile(path, CrossTangentMode::Corrected, precision);
    const std::vector<Eigen::Vector3d> loop = defaultTrajectory(c, 8), whole = wholeTessellationSection(c, 8);
    ASSERT_EQ(loop.size(), whole.size());
    size_t differ = 0;
    for (size_t i = 0; i < loop.size(); ++i) differ += std::memcmp(loop[i].data(), whole[i].data(), 24) != 0;
    EXPECT_EQ(differ, 0u);
    points += loop.size();
    ++meshes;
  }
  std::printf("%d meshes: %zu section points, each the whole tessellation's\n", meshes, points);
  EXPECT_GE(meshes, 21);
}

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
