// SPDX-License-Identifier: Apache-2.0
// The runtime structures report the bytes they hold (SharedGeometry::memory, `cache info
// --memory`), checked against an independent count: the heap bytes glibc holds in use
// (mallinfo2: small blocks and mmapped ones) grow by what the parts report when a renderer builds
// them (less what a second renderer sharing them adds: its own state), and shrink by it when
// they go, for every part of every mesh here, prebuilt (both surface indexes) and lazy, patch
// method and god-object.
#include <gtest/gtest.h>
#include <malloc.h>

#include <cmath>
#include <string>

#include <smoothforce/force/shared_geometry.h>
#include <smoothforce/patch/mesh_pipeline.h>

#include <nlohmann/json.hpp>

#include "cli_test_support.h"
#include "test_hostile_support.h"

namespace sf {
namespace {

/// Bytes glibc's allocator holds in use: small and large (mmapped) blocks.
size_t heapInUse() {
  malloc_trim(0);
  const struct mallinfo2 m = mallinfo2();
  return m.uordblks + m.hblkhd;
}

std::shared_ptr<const PatchCache> build(const std::string& path, bool prebuilt) {
  const PatchOptions o;
  const LoadedMesh loaded = loadMesh(path, o);
  return std::make_shared<const PatchCache>(prebuilt ? buildPatchCache(loaded, o, Backend::Tbb)
                                                     : preparePatchSkeleton(loaded, o));
}

TEST(MemoryReport, EveryPartHoldsWhatTheHeapGrowsBy) {
  const std::string meshes[] = {std::string(SF_DATA_DIR) + "/spot_control_mesh.obj",
                                std::string(SF_DATA_DIR) + "/chamfer-cube.off",
                                std::string(SF_SHARED_MESHES) + "/odedstein/spot_low_resolution.obj"};
  int parts = 0;
  for (const std::string& mesh : meshes) {
    // prebuilt with the tessellation index (auto), prebuilt with the bounds index, lazy
    for (int config : {0, 1, 2}) {
      const bool prebuilt = config < 2;
      SCOPED_TRACE(mesh + (config == 0 ? " prebuilt" : config == 1 ? " prebuilt, bounds" : " lazy"));
      const auto cache = build(mesh, prebuilt);
      ForceOptions options;
      if (config == 1) options.surfaceIndex = SurfaceIndex::Bounds;
      for (ForceMethod method : {ForceMethod::Patch, ForceMethod::Direct}) {
        const size_t before = heapInUse();
        size_t reported = 0, grown = 0;
        {
          SharedGeometry g(cache);
          const std::unique_ptr<ForceRenderer> r = g.makeRenderer(method, options);
          const size_t withOne = heapInUse();
          // a second renderer shares the parts: what it adds is a renderer's own state
          const std::unique_ptr<ForceRenderer> r2 = g.makeRenderer(method, options);
          const size_t own = heapInUse() - withOne;
          grown = withOne - before - std::min(own, withOne - before);
          for (const SharedGeometry::Part& p : g.memory()) {
            if (p.name == "cache") {
              EXPECT_EQ(p.bytes, cache->bytes());
              continue;
            }
            EXPECT_GT(p.bytes, size_t(0)) << p.name;
            reported += p.bytes;
            ++parts;
          }
        }
        const size_t after = heapInUse();
        // what the parts report is what the heap grew by for the first renderer less what a second
        // one adds (its own state), up to allocator bookkeeping (64 kB or 5%), and it is given back
        // when they go
        const double slack = std::max(65536.0, 0.05 * double(grown));
        EXPECT_LE(double(reported), double(grown) + slack) << "reported " << reported << ", heap grew " << grown;
        EXPECT_GE(double(reported), double(grown) - slack) << "reported " << reported << ", heap grew " << grown;
        EXPECT_LE(double(after), double(before) + slack) << "the parts kept " << (after - before) << " bytes";
      }
    }
  }
  // prebuilt: polygon scene + patch surface, or + lazy surface (bounds index), lazy: polygon scene +
  // lazy surface + lazy patches, direct: the god-object's scene; three meshes
  EXPECT_EQ(parts, 3 * (2 + 2 + 3 + 1 + 1 + 1));
}

TEST(MemoryReport, CacheInfoReportsEveryPart) {
  hostile::TempDir dir("sf_memory_report");
  const std::string cache = (dir.path / "spot.sfcache").string();
  ASSERT_EQ(test::smoothforce("cache build " + std::string(SF_DATA_DIR) + "/spot_control_mesh.obj -o " + cache).status,
            0);
  const test::CliResult r = test::smoothforce("cache info " + cache + " --memory --json");
  ASSERT_EQ(r.status, 0) << r.out;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  std::vector<std::string> names;
  size_t total = 0;
  for (const auto& p : j["memory"]["parts"]) {
    names.push_back(p["name"]);
    total += size_t(p["bytes"]);
    EXPECT_DOUBLE_EQ(double(p["bytes_per_face"]), double(p["bytes"]) / 180.0);
  }
  EXPECT_EQ(names, (std::vector<std::string>{"cache", "polygon_scene", "patch_surface", "lazy_surface",
                                              "god_object_scene"}));
  EXPECT_EQ(size_t(j["memory"]["total_bytes"]), total);
  EXPECT_TRUE(nlohmann::json::parse(test::smoothforce("cache info " + cache + " --json").out)["memory"].is_null());
}

}  // namespace
}  // namespace sf
