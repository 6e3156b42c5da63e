// SPDX-License-Identifier: Apache-2.0
// SharedGeometry (force/shared_geometry.h) and the scenes that use it: renderers of one cache that
// share their geometry give the forces of renderers made alone, bit for bit, and a scene's
// copies of one file share one cache.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <smoothforce/force/god_object.h>
#include <smoothforce/force/shared_geometry.h>
#include <smoothforce/patch/cache_file.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/runtime/scene.h>

namespace {

namespace fs = std::filesystem;
using Eigen::Vector3d;
using namespace sf;

const std::string kCage = std::string(SF_DATA_DIR) + "/spot_control_mesh.obj";

/// HIP path j of `count`: a circle about the mesh's box centre through its middle, in a plane
/// turned by j, so that each path goes in and out of the cow several times (contact starts,
/// tracking, ends).
Vector3d pathPoint(const Vector3d& centre, double radius, int j, int i, int steps) {
  const double a = 2 * M_PI * i / steps, tilt = 0.7 * j + 0.3;
  const Vector3d u(std::cos(tilt), std::sin(tilt), 0.2), v(-std::sin(tilt) * 0.3, std::cos(tilt) * 0.3, 1.0);
  return centre + radius * (std::cos(a) * u.normalized() + std::sin(a) * v.normalized());
}

bool sameSample(const ForceSample& a, const ForceSample& b) {
  return a.force == b.force && a.scp == b.scp && a.normal == b.normal && a.contact == b.contact &&
         a.face == b.face && a.xi == b.xi && a.eta == b.eta && a.iterations == b.iterations &&
         a.transitions == b.transitions && a.status == b.status;
}

/// K renderers from one SharedGeometry step their paths interleaved (one step of each in turn, so the
/// shared lazy store evicts the others' patches: capacity 4) and must give, at every step, what
/// a renderer made alone by makeForceRenderer gives on its own path.
void checkSharedAgainstAlone(const std::shared_ptr<const PatchCache>& cache, ForceMethod method, int& contacts,
                           int& steps) {
  constexpr int K = 3, kSteps = 240;
  ForceOptions o;
  o.patchCapacity = 4;
  o.stiffness = 800;  // not the default: the options are passed on
  Vector3d lo, hi;
  ASSERT_TRUE(referencedBox(*cache, lo, hi));
  const Vector3d centre = 0.5 * (lo + hi);
  const double radius = 0.2 * (hi - lo).norm();
  SharedGeometry geometry(cache);
  std::vector<std::unique_ptr<ForceRenderer>> shared, alone;
  for (int j = 0; j < K; ++j) {
    shared.push_back(geometry.makeRenderer(method, o));
    alone.push_back(makeForceRenderer(cache, method, o));
  }
  for (int i = 0; i <= kSteps; ++i)
    for (int j = 0; j < K; ++j) {
      const Vector3d hip = pathPoint(centre, radius, j, i, kSteps);
      const ForceSample a = shared[j]->step(hip), b = alone[j]->step(hip);
      ++steps;
      contacts += b.contact;
      EXPECT_TRUE(sameSample(a, b)) << toString(method) << " renderer " << j << " step " << i << ": force "
                                    << a.force.transpose() << " against " << b.force.transpose();
    }
}

TEST(SharedGeometry, SharedRenderersGiveTheForcesOfRenderersMadeAlone) {
  PatchOptions po;
  const LoadedMesh loaded = loadMesh(kCage, po);
  const auto skeleton = std::make_shared<const PatchCache>(preparePatchSkeleton(loaded, po));
  const auto prebuilt = std::make_shared<const PatchCache>(buildPatchCache(loaded, po, Backend::Serial));
  int contacts = 0, steps = 0, runs = 0;
  for (const auto& cache : {skeleton, prebuilt})
    for (ForceMethod m : {ForceMethod::Patch, ForceMethod::Direct, ForceMethod::Shading}) {
      checkSharedAgainstAlone(cache, m, contacts, steps);
      ++runs;
    }
  EXPECT_EQ(runs, 6);
  EXPECT_EQ(steps, 6 * 3 * 241);
  EXPECT_GT(contacts, steps / 5);  // the paths spend a good part of their length inside
  EXPECT_LT(contacts, steps);
}

// Far from the origin the god-object renders about the mesh (its local frame). Its renderers of
// one cache share one scene of the polygons moved there (godObjectScene): each used to build its
// own. The shared renderers give the forces of renderers made alone, and a renderer takes a
// scene only where it is of its polygons in its frame.
TEST(SharedGeometry, GodObjectRenderersFarFromTheOriginShareTheirLocalFrame) {
  PatchOptions po;
  const LoadedMesh loaded = loadMesh(kCage, po);
  int contacts = 0, steps = 0, offsets = 0;
  for (const double offset : {0.0, 1e4, 1e6, 1e9}) {
    PolygonMesh m = loaded.mesh;
    for (auto& p : m.positions) p += Vector3d(offset, -0.5 * offset, 0.25 * offset);
    const auto cache =
        std::make_shared<const PatchCache>(preparePatchSkeleton(loadMesh(std::move(m), 1, po), po));
    for (ForceMethod method : {ForceMethod::Direct, ForceMethod::Shading})
      checkSharedAgainstAlone(cache, method, contacts, steps);
    const std::shared_ptr<const PolygonScene> frame = godObjectScene(*cache);
    const bool far = offset > 0;
    EXPECT_EQ(&frame->cache() == cache.get(), !far) << offset;  // far: the moved polygons
    {
      GodObjectRenderer direct(cache, frame, ForceMethod::Direct, ForceOptions{});
      GodObjectRenderer shading(cache, frame, ForceMethod::Shading, ForceOptions{});
      EXPECT_EQ(frame.use_count(), 3) << offset;  // both renderers hold it: neither built its own
    }
    // the polygons in world coordinates, far from the origin: not the frame, so not taken
    const auto world = std::make_shared<const PolygonScene>(*cache, kWatertightPlanarTolerance);
    {
      GodObjectRenderer direct(cache, world, ForceMethod::Direct, ForceOptions{});
      EXPECT_EQ(world.use_count(), far ? 1 : 2) << offset;
    }
    // the frame of another cache (one vertex of the mesh moved by 1 mm) is not taken either
    if (far) {
      PolygonMesh other = loaded.mesh;
      other.positions[0] += Vector3d(1e-3, 0, 0);
      for (auto& p : other.positions) p += Vector3d(offset, -0.5 * offset, 0.25 * offset);
      const auto otherCache =
          std::make_shared<const PatchCache>(preparePatchSkeleton(loadMesh(std::move(other), 1, po), po));
      GodObjectRenderer direct(otherCache, frame, ForceMethod::Direct, ForceOptions{});
      EXPECT_EQ(frame.use_count(), 1) << offset;
    }
    ++offsets;
  }
  EXPECT_EQ(offsets, 4);
  EXPECT_EQ(steps, 4 * 2 * 3 * 241);
  EXPECT_GT(contacts, steps / 5);
  EXPECT_LT(contacts, steps);
}

TEST(SharedGeometry, RefusesANullCache) { EXPECT_THROW(SharedGeometry(nullptr), InputError); }

TEST(SharedGeometry, SceneCopiesOfOneFileShareOneCacheAndTheirGeometry) {
  const fs::path dir = fs::temp_directory_path() / ("sf_shared_geometry_" + std::to_string(::getpid()));
  fs::create_directories(dir / "sub");
  fs::copy_file(kCage, dir / "cage.obj");
  {
    PatchOptions po;
    const PatchCache c = buildPatchCache(loadMesh(kCage, po), po, Backend::Serial);
    writePatchCache(c, (dir / "cage.sfcache").string());
  }
  // objects 0, 1 and 3 name one mesh (3 by another spelling of its path), 2 with other patch
  // options, 4 and 5 one cache file
  const std::string scene = (dir / "scene.json").string();
  std::ofstream(scene) << R"({"objects": [
      {"mesh": "cage.obj"}, {"mesh": "cage.obj", "pose": {"translation": [2, 0, 0]}},
      {"mesh": "cage.obj", "precision": "float"}, {"mesh": "sub/../cage.obj", "method": "direct"},
      {"cache": "cage.sfcache"}, {"cache": "cage.sfcache", "method": "shading"}]})";
  const rt::Scene s = rt::loadScene(scene, rt::SceneDefaults{}, rt::sharedRendererFactory());
  const auto& o = s.objects();
  ASSERT_EQ(o.size(), 6u);
  EXPECT_EQ(o[0].cache, o[1].cache);
  EXPECT_EQ(o[0].cache, o[3].cache);
  EXPECT_NE(o[0].cache, o[2].cache);
  EXPECT_EQ(o[2].cache->options.precision, Precision::Float);
  EXPECT_EQ(o[4].cache, o[5].cache);
  EXPECT_NE(o[0].cache, o[4].cache);
  EXPECT_FALSE(hasPatchData(*o[0].cache));
  EXPECT_TRUE(hasPatchData(*o[4].cache));
  // each object's renderer renders as one made alone on its cache
  Vector3d lo, hi;
  ASSERT_TRUE(referencedBox(*o[0].cache, lo, hi));
  int same = 0, contacts = 0;
  for (size_t k = 0; k < o.size(); ++k) {
    auto alone = makeForceRenderer(o[k].cache, o[k].method, o[k].force);
    for (int i = 0; i <= 120; ++i) {
      const Vector3d hip = pathPoint(0.5 * (lo + hi), 0.2 * (hi - lo).norm(), int(k), i, 120);
      const ForceSample a = o[k].renderer->step(hip), b = alone->step(hip);
      same += sameSample(a, b);
      contacts += b.contact;
    }
  }
  EXPECT_EQ(same, 6 * 121);
  EXPECT_GT(contacts, 6 * 121 / 5);
  // the scene's counts take a shared patch store and a shared cache once
  ASSERT_NE(o[0].renderer->patchStore(), nullptr);
  EXPECT_EQ(o[0].renderer->patchStore(), o[1].renderer->patchStore());
  EXPECT_NE(o[0].renderer->patchStore(), o[2].renderer->patchStore());
  EXPECT_GT(o[0].renderer->patchesBuilt(), 0);
  EXPECT_EQ(s.patchesBuilt(), o[0].renderer->patchesBuilt() + o[2].renderer->patchesBuilt() + 180);
  EXPECT_EQ(s.totalFaces(), 3 * 180);
  fs::remove_all(dir);
}

}  // namespace
