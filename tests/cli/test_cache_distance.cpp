// SPDX-License-Identifier: Apache-2.0
// `smoothforce cache distance`: the distance between a cache's patch surface and another
// cache's (the same mesh under the default and --fold-repair off) or a mesh's polygons (the
// exact part an extruded L stands for), in text and JSON, and its usage errors.
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>
#include <nlohmann/json.hpp>

#include "cli_test_support.h"
#include "shared_mesh_files.h"

namespace sf {
namespace {

TEST(CacheDistance, MeasuresTheRepairAgainstThePartAndTheDesignPagesConstruction) {
  const auto dir = std::filesystem::temp_directory_path() / ("sf_cache_distance_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string part = (dir / "L.obj").string();
  {  // an L extruded by 1: caps with a reflex corner, creased at 30 degrees below
    std::ofstream o(part);
    o << "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 3 0\nv 0 3 0\n"
         "v 0 0 1\nv 2 0 1\nv 2 1 1\nv 1 1 1\nv 1 3 1\nv 0 3 1\n"
         "f 6 5 4 3 2 1\nf 7 8 9 10 11 12\n"
         "f 1 2 8 7\nf 2 3 9 8\nf 3 4 10 9\nf 4 5 11 10\nf 5 6 12 11\nf 6 1 7 12\n";
  }
  const std::string on = (dir / "on.sfcache").string(), off = (dir / "off.sfcache").string();
  ASSERT_EQ(test::smoothforce("cache build " + part + " --crease-angle 30 -o " + on).status, 0);
  ASSERT_EQ(test::smoothforce("cache build " + part + " --crease-angle 30 --fold-repair off -o " + off).status, 0);
  auto measure = [](const std::string& args) {
    const test::CliResult r = test::smoothforce("cache distance " + args + " --json");
    EXPECT_EQ(r.status, 0) << r.out;
    return nlohmann::json::parse(r.out);
  };
  // the repaired part is the prism itself (every patch flat); the design page's folds stick out
  const nlohmann::json repaired = measure(on + " --to " + part + " --level 6");
  EXPECT_EQ(repaired["to_surface"], "polygons");
  EXPECT_EQ(repaired["level"], 6);
  EXPECT_EQ(repaired["levels_used"], nlohmann::json::parse("[6, 6]"));
  EXPECT_NEAR(repaired["diagonal_m"].get<double>(), std::sqrt(4.0 + 9.0 + 1.0), 1e-12);
  EXPECT_LT(repaired["hausdorff"].get<double>(), 1e-12);
  const nlohmann::json folded = measure(off + " --to " + part);
  EXPECT_GT(folded["hausdorff"].get<double>(), 0.05);
  EXPECT_EQ(folded["hausdorff"], std::max(folded["cache_to_other"]["max"], folded["other_to_cache"]["max"]));
  // one surface against the other: the repair moved only the caps
  const nlohmann::json moved = measure(on + " --to " + off);
  EXPECT_EQ(moved["to_surface"], "patches");
  for (const char* side : {"cache_to_other", "other_to_cache"}) {
    const nlohmann::json& d = moved[side];
    std::vector<std::string> keys;
    for (const auto& [k, v] : d.items()) keys.push_back(k);
    EXPECT_EQ(keys, (std::vector<std::string>{"max", "mean", "points", "worst_face", "worst_point"}));
    EXPECT_GT(d["points"].get<int>(), 0);
  }
  EXPECT_GT(moved["other_to_cache"]["max"].get<double>(), 0.05);
  // the spot cage has nothing to cut, but 22 tangled vertex fans: the default and off differ on the
  // 62 patches around them only (the other patches are one, bit for bit: tangent_fans tests)
  const std::string spotOn = (dir / "spot.sfcache").string(), spotOff = (dir / "spot_off.sfcache").string();
  const std::string spot = test::sharedMesh("keenan_crane/spot_control_mesh.obj");
  ASSERT_EQ(test::smoothforce("cache build " + spot + " -o " + spotOn).status, 0);
  ASSERT_EQ(test::smoothforce("cache build " + spot + " --fold-repair off -o " + spotOff).status, 0);
  const nlohmann::json fans = measure(spotOn + " --to " + spotOff + " --level 3");
  EXPECT_GT(fans["hausdorff"].get<double>(), 0);
  EXPECT_LT(fans["hausdorff"].get<double>(), 0.01 * fans["diagonal_m"].get<double>());
  // the text form names both directions
  test::CliResult r = test::smoothforce("cache distance " + on + " --to " + part + " --level 2");
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("patches -> " + part + " polygons: max"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("two-sided (Hausdorff of the samples)"), std::string::npos) << r.out;
  // usage errors (2) and bad files (1)
  EXPECT_EQ(test::smoothforce("cache distance " + on + " --to " + part + " --level 0").status, 2);
  EXPECT_EQ(test::smoothforce("cache distance " + on).status, 2);
  r = test::smoothforce("cache distance " + on + " --to " + (dir / "none.obj").string());
  EXPECT_EQ(r.status, 1) << r.out;
  r = test::smoothforce("cache distance " + part + " --to " + on);
  EXPECT_EQ(r.status, 1) << r.out;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace sf
