// SPDX-License-Identifier: Apache-2.0
// A HIP that jumps (a device glitch, a re-grab, a scene reset) never keeps a phantom contact:
// on every closed mesh of ../shared/meshes and the generated shapes, from contacts of three
// kinds (a contact start, a tracked press deeper, a tracked slide along the surface), with the
// patch method on a prebuilt cache and on a skeleton whose patches are built lazily, the HIP
// jumps by 0.05 to 3 diagonals (kJumpDiagonals is 0.03). Every jump's step decides contact as a
// contact start at its target does (the global query); wherever the dense oracle's ray parity
// (independent of the tracker's queries) puts the HIP outside, the step has no contact and ends
// it (SF_TRACK_LEAVE); inside, the tracked contact holds (no SF_TRACK_ENTER). Before the jump
// check, 9 of these 21 shapes kept phantom contacts (up to 388 of 3,450 jumps out of bunny_hr).
#include <gtest/gtest.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <atomic>
#include <cstdio>

#include <smoothforce/force/force_method.h>
#include <smoothforce/force/force_tracking.h>
#include <smoothforce/query/embree_scene.h>
#include <smoothforce/sweep/sweep_sampling.h>
#include "patch_test_support.h"
#include "query_test_support.h"

namespace sf {
namespace {

class ForceJump : public ::testing::TestWithParam<std::string> {};

void checkJumps(const std::string& shape, bool lazy) {
  const auto cache = test::closedShapeCache(shape);
  const auto skeleton = lazy ? std::make_shared<const PatchCache>(test::skeletonOf(*cache)) : nullptr;
  const double diag = boundingDiagonal(*cache);
  const test::DenseOracle oracle(*cache);
  const PatchSurfaceSampler sampler(*cache, cache->numFaces() > 4000 ? 2 : 6);
  constexpr int kSeeds = 120;
  const std::vector<SurfaceSample> samples = sampler.sample(kSeeds, 20261125);
  auto surface = lazy ? nullptr : std::make_shared<const PatchSurface>(*cache);
  tbb::enumerable_thread_specific<std::unique_ptr<ForceRenderer>> renderers([&] {
    if (lazy)
      return makeForceRenderer(skeleton, std::make_shared<const PolygonScene>(*skeleton), ForceMethod::Patch,
                               ForceOptions{});
    return makeForceRenderer(cache, std::make_shared<const PolygonScene>(*cache), ForceMethod::Patch, ForceOptions{},
                             surface);
  });
  // 14 directions: the 6 axes and the 8 diagonals
  std::vector<Eigen::Vector3d> dirs;
  for (int a = 0; a < 3; ++a)
    for (const double sgn : {1.0, -1.0}) dirs.push_back(sgn * Eigen::Vector3d::Unit(a));
  for (int i = 0; i < 8; ++i)
    dirs.push_back(Eigen::Vector3d(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1).normalized());
  const double sizes[4] = {0.05, 0.2, 1.0, 3.0};  // diagonals; kJumpDiagonals = 0.02
  constexpr int kKinds = 3, kDirsPerSize = 3;
  std::atomic<int> jumps{0}, outside{0}, phantom{0}, unlikeStart{0}, startDisagrees{0}, noLeave{0}, inside{0}, held{0}, entered{0}, raysDisagree{0},
      noContact{0};
  tbb::parallel_for(0, kSeeds * kKinds, [&](int g) {
    const SurfaceSample& p = samples[g / kKinds];
    const int kind = g % kKinds;
    ForceRenderer& R = *renderers.local();
    const double depth = 0.005 * diag;
    // the contact of this kind: a start; a tracked press deeper; a tracked slide along the tangent
    auto makeContact = [&](Eigen::Vector3d& hip) {
      R.reset();
      R.step(p.point + depth * p.normal);
      hip = p.point - depth * p.normal;
      ForceSample s = R.step(hip);
      for (int i = 1; kind == 1 && i <= 5 && s.contact; ++i) s = R.step(hip = p.point - depth * (1 + 0.2 * i) * p.normal);
      const Eigen::Vector3d t = p.normal.unitOrthogonal();
      for (int i = 1; kind == 2 && i <= 10 && s.contact; ++i) s = R.step(hip += 0.002 * diag * t);
      return s.contact;
    };
    for (int k = 0; k < 4; ++k)
      for (int d = 0; d < kDirsPerSize; ++d) {
        Eigen::Vector3d hip;
        if (!makeContact(hip)) {
          ++noContact;
          continue;
        }
        const Eigen::Vector3d target = hip + sizes[k] * diag * dirs[(g * 5 + k * kDirsPerSize + d) % dirs.size()];
        ++jumps;
        bool agree = false;
        const int w = oracle.winding(target, &agree);
        if (!agree) {
          ++raysDisagree;
          continue;
        }
        const ForceSample s = R.step(target);
        R.reset();
        const bool start = R.step(target).contact;  // a contact start at the target: the global query's verdict
        if (s.contact != start) ++unlikeStart;
        if (w == 0) {
          ++outside;
          if (s.contact && start) ++startDisagrees;
          if (s.contact && !start) {
            ++phantom;
            if (phantom <= 5)
              std::printf("%s %s: phantom contact after a jump of %.2f diagonals to (%g %g %g)\n", shape.c_str(),
                          lazy ? "lazy" : "prebuilt", sizes[k], target.x(), target.y(), target.z());
          }
          if (!(s.status & SF_TRACK_LEAVE)) ++noLeave;
        } else {
          ++inside;
          if (s.contact) {
            ++held;
            if (s.status & SF_TRACK_ENTER) ++entered;
          }
        }
      }
  });
  std::printf("%s %s: %d jumps, %d outside (%d phantom, %d where a contact start disagrees with the oracle too), "
              "%d inside (%d held), %d unlike a contact start, %d rays disagree, %d seeds without contact\n",
              shape.c_str(), lazy ? "lazy" : "prebuilt", jumps.load(), outside.load(), phantom.load(),
              startDisagrees.load(), inside.load(), held.load(), unlikeStart.load(), raysDisagree.load(),
              noContact.load());
  // after a jump the step decides as a contact start at the target does, at every jump
  EXPECT_EQ(unlikeStart.load(), 0);
  EXPECT_EQ(phantom.load(), 0);
  // a contact start itself disagrees with the oracle (QueryProperties' subject) at a surface fault
  // (the spot cage's overlapping sheets) or at a target within the oracle's tessellation error of
  // the surface: at most 2 of ~3,400 targets on any shape (measured)
  EXPECT_LE(startDisagrees.load(), outside.load() / 500);
  EXPECT_LE(noLeave.load(), startDisagrees.load());
  EXPECT_EQ(entered.load(), 0);
  // every seed is pressed 0.5% of the diagonal in at a surface sample: nearly all make contact
  EXPECT_GE(jumps.load(), kSeeds * kKinds * 4 * kDirsPerSize * 9 / 10);
  EXPECT_GE(outside.load(), jumps.load() / 2);  // most jumps of 0.2 diagonals and more leave the object
  EXPECT_LE(raysDisagree.load(), jumps.load() / 100);
  // inside, the global query decides as at a contact start: contact, except at surface faults
  // (the spot cage's overlapping sheets: QueryProperties' bound) and within the error of the
  // oracle's tessellation of the surface
  EXPECT_GE(held.load(), inside.load() * 95 / 100);
}

TEST_P(ForceJump, NoContactOutsideAfterAJumpPrebuilt) { checkJumps(GetParam(), false); }
TEST_P(ForceJump, NoContactOutsideAfterAJumpLazy) { checkJumps(GetParam(), true); }

INSTANTIATE_TEST_SUITE_P(Shapes, ForceJump, ::testing::ValuesIn(test::closedShapes()),
                         [](const ::testing::TestParamInfo<std::string>& i) { return test::shapeTestName(i.param); });

}  // namespace
}  // namespace sf
