// SPDX-License-Identifier: Apache-2.0
// Lazy patch construction: the records equal a prebuilt cache's, the LRU bound holds, and a
// force renderer over a skeleton renders exactly what it renders over the prebuilt cache.
#include <gtest/gtest.h>

#include <smoothforce/force/force_tracking.h>
#include <smoothforce/patch/lazy_patches.h>
#include <smoothforce/query/embree_scene.h>
#include "force_test_support.h"
#include "patch_test_support.h"

namespace sf {
namespace {

const char* kSpot = "keenan_crane/spot_control_mesh.obj";

template <class Real>
void expectSameRecords(Precision precision) {
  const PatchCache full = test::cacheFromFile(test::sharedMesh(kSpot), CrossTangentMode::Corrected, precision);
  LazyPatches lazy(std::make_shared<const PatchCache>(test::skeletonFromFile(test::sharedMesh(kSpot), precision)), 7);
  std::vector<Real> want(GP_MAX_N * GP_E_NFIELDS);
  // every face, in an order that evicts (capacity 7), twice
  for (int pass = 0; pass < 2; ++pass)
    for (int i = 0; i < full.numFaces(); ++i) {
      const int f = (i * 37 + pass) % full.numFaces();
      gatherRecords(full, f, want.data());
      uint32_t st = 0;
      const Real* got;
      if constexpr (std::is_same_v<Real, double>)
        got = lazy.recordsD(f, st);
      else
        got = lazy.recordsF(f, st);
      ASSERT_NE(got, nullptr) << f;
      EXPECT_EQ(st, full.faceStatus[f]) << f;
      for (int j = 0; j < full.faceSize(f) * GP_E_NFIELDS; ++j)
        ASSERT_EQ(got[j], want[j]) << "face " << f << " value " << j;  // bit for bit
    }
  EXPECT_EQ(lazy.distinctFaces(), full.numFaces());
  EXPECT_EQ(lazy.capacity(), 7);
}

TEST(LazyPatches, RecordsEqualThePrebuiltCacheBitForBit) {
  expectSameRecords<double>(Precision::Double);
  expectSameRecords<float>(Precision::Float);
}

TEST(LazyPatches, LeastRecentlyUsedBound) {
  LazyPatches lazy(std::make_shared<const PatchCache>(test::skeletonFromFile(test::sharedMesh(kSpot))), 3);
  uint32_t st;
  for (int f : {0, 1, 2, 0, 1, 2}) ASSERT_NE(lazy.recordsD(f, st), nullptr);
  EXPECT_EQ(lazy.constructions(), 3);  // all held
  lazy.recordsD(3, st);                // evicts 0, the least recently used
  EXPECT_EQ(lazy.constructions(), 4);
  lazy.recordsD(2, st);  // held
  lazy.recordsD(1, st);  // held
  EXPECT_EQ(lazy.constructions(), 4);
  lazy.recordsD(0, st);  // was evicted: rebuilt, evicting 3
  EXPECT_EQ(lazy.constructions(), 5);
  lazy.recordsD(3, st);
  EXPECT_EQ(lazy.constructions(), 6);
  EXPECT_EQ(lazy.distinctFaces(), 4);
  EXPECT_EQ(lazy.recordsD(-1, st), nullptr);
  EXPECT_EQ(st, GP_ST_TOO_MANY_SIDES);
  EXPECT_EQ(lazy.recordsD(100000, st), nullptr);
  EXPECT_EQ(lazy.recordsF(0, st), nullptr) << "a double skeleton has no float records";
}

TEST(LazyPatches, RendererOverSkeletonMatchesPrebuiltAndBuildsOnlyNearContact) {
  auto full = std::make_shared<const PatchCache>(test::cacheFromFile(test::sharedMesh(kSpot)));
  auto skeleton = std::make_shared<const PatchCache>(test::skeletonFromFile(test::sharedMesh(kSpot)));
  // the ForceSlide path: from outside into contact on face 11, then across 6 faces, 3 cm deep
  const std::vector<Eigen::Vector3d> hips = test::slidePath(*full, 11, 0, 6, 40, 0.03).hips;
  for (int capacity : {0, 4}) {
    ForceOptions o;
    o.patchCapacity = capacity;
    o.initialGuess = InitialGuess::Polygon;  // the global query a skeleton runs: the same arithmetic on both
    auto a = makeForceRenderer(full, ForceMethod::Patch, o);
    auto b = makeForceRenderer(skeleton, ForceMethod::Patch, o);
    int contacts = 0;
    for (const auto& h : hips) {
      const ForceSample x = a->step(h), y = b->step(h);
      ASSERT_EQ(x.contact, y.contact);
      ASSERT_EQ(x.face, y.face);
      EXPECT_EQ(x.force, y.force);  // the same records give the same arithmetic
      EXPECT_EQ(x.status, y.status);
      contacts += x.contact;
    }
    EXPECT_GT(contacts, int(hips.size()) * 3 / 4);
    EXPECT_EQ(a->patchesBuilt(), full->numFaces());
    EXPECT_GE(b->patchesBuilt(), 2);
    if (capacity == 0) {
      EXPECT_LT(b->patchesBuilt(), full->numFaces() / 4) << "only faces near the path";
    }
    std::printf("  capacity %d: %d patch constructions for %d faces, %d steps in contact\n", capacity,
                b->patchesBuilt(), full->numFaces(), contacts);
  }
  // the polygon methods need no patch
  EXPECT_EQ(makeForceRenderer(skeleton, ForceMethod::Direct, ForceOptions{})->patchesBuilt(), 0);
}

}  // namespace
}  // namespace sf
