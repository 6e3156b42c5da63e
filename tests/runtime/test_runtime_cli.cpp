// SPDX-License-Identifier: Apache-2.0
// End-to-end tests of `smoothforce loop` (real clock, real force renderer): report lines,
// record file, one-line option errors. Skipped while the command is not registered.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>

#include "cli_test_support.h"

namespace {

namespace fs = std::filesystem;

using sf::test::CliResult;
using sf::test::smoothforce;

class RuntimeCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const CliResult help = smoothforce("loop --help");
    ASSERT_TRUE(help.status == 0 && help.out.find("--duration") != std::string::npos)
        << "`smoothforce loop` is not registered: " << help.out;
    dir = fs::temp_directory_path() / ("sf_rt_cli_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::ofstream(dir / "cube.obj") << "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv -0.5 0.5 -0.5\nv 0.5 0.5 -0.5\n"
                                       "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv -0.5 0.5 0.5\nv 0.5 0.5 0.5\n"
                                       "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
  }
  void TearDown() override {
    if (!dir.empty()) fs::remove_all(dir);
  }
  std::string path(const std::string& name) const { return (dir / name).string(); }
  /// One-line error, exit status 1 or 2.
  void expectError(const std::string& args, const std::string& want) {
    const CliResult r = smoothforce("loop --mesh " + path("cube.obj") + " --duration 0.05 " + args);
    EXPECT_NE(r.status, 0) << args;
    EXPECT_NE(r.out.find(want), std::string::npos) << args << "\n" << r.out;
    EXPECT_EQ(r.out.find('\n'), r.out.size() - 1) << "not one line: " << r.out;
  }
  fs::path dir;
};

TEST_F(RuntimeCli, ReportsTimingContactsAndRecords) {
  for (const char* method : {"patch", "direct", "shading"}) {
    const std::string rec = path(std::string("rec_") + method + ".csv");
    const CliResult r = smoothforce("loop --mesh " + path("cube.obj") + " --method " + method +
                                    " --device scripted --speed 0.5 --duration 0.3 --record " + rec);
    ASSERT_EQ(r.status, 0) << r.out;
    const std::regex timing(
        R"((^|\n)step compute: p50 [0-9.]+ us, p99 [0-9.]+ us, p99\.9 [0-9.]+ us, max [0-9.]+ us\n)");
    EXPECT_TRUE(std::regex_search(r.out, timing)) << r.out;
    EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(\nwake-up lateness: p50 [0-9.]+ us, p99 )"))) << r.out;
    EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(\nmissed deadlines: [0-9]+ )"))) << r.out;
    std::smatch m;
    // given a mesh, the patch method builds patches lazily where the slide touches (the top face
    // and the faces its refinement reaches); the polygon methods build none
    ASSERT_TRUE(std::regex_search(
        r.out, m,
        std::regex(
            R"(\npatch constructions: ([0-9]+) for 6 faces \(a face evicted and needed again is built again\)\n)")))
        << r.out;
    if (std::string(method) == "patch") {
      EXPECT_GE(std::stoi(m[1]), 1) << r.out;
      EXPECT_LE(std::stoi(m[1]), 6) << r.out;  // capacity 256: nothing is evicted, nothing rebuilt
    } else {
      EXPECT_EQ(std::stoi(m[1]), 0) << r.out;
    }
    // a loaded machine skips ticks (counted): every property below is relative to the steps run
    ASSERT_TRUE(std::regex_search(r.out, m, std::regex(R"(\nsteps: ([0-9]+) of ([0-9]+) ticks)"))) << r.out;
    const int steps = std::stoi(m[1]), ticks = std::stoi(m[2]);
    EXPECT_EQ(ticks, 300) << r.out;
    EXPECT_GT(steps, 0) << r.out;
    ASSERT_TRUE(std::regex_search(r.out, m, std::regex(R"(\nrecords: ([0-9]+) written, ([0-9]+) dropped)"))) << r.out;
    const int written = std::stoi(m[1]);
    EXPECT_EQ(written + std::stoi(m[2]), steps) << r.out;
    ASSERT_TRUE(std::regex_search(r.out, m, std::regex(R"(contacts: ([0-9]+) steps in contact, ([0-9]+) onsets)")));
    EXPECT_GT(std::stoi(m[1]), steps / 2) << method << ": the slide runs 1.7 cm below the top face\n" << r.out;
    EXPECT_GE(std::stoi(m[2]), 1);
    std::ifstream in(rec);
    std::string header;
    ASSERT_TRUE(std::getline(in, header)) << rec;
    EXPECT_EQ(header.rfind("tick,t,x,y,z,fx,fy,fz", 0), 0u);
    int rows = 0;
    for (std::string line; std::getline(in, line);) ++rows;
    EXPECT_EQ(rows, written);
  }
}

// With --patch-capacity 1, a HIP that presses into the top face and the side face in turn
// (out of contact between) has the face it leaves evicted and built again: more constructions
// than the cube has faces, which the report line read as "patches built: 12 of 6 faces". The
// properties are relative to the onsets the run counted (a loaded machine may skip ticks).
TEST_F(RuntimeCli, ReportCountsPatchConstructions) {
  std::ofstream hips(path("hips.csv"));
  hips << "t,x,y,z\n";
  int rows = 0;
  for (int cycle = 0; cycle < 6; ++cycle)
    for (const char* p : {"0,0,1.5", "0,0,0.49", "0,0,1.5", "1.5,0,0", "0.49,0,0", "1.5,0,0"})
      for (int i = 0; i < 25; ++i, ++rows) hips << 1e-3 * rows << "," << p << "\n";
  hips.close();
  EXPECT_EQ(rows, 900);
  int checked = 0;
  for (const char* capacity : {"1", "256"}) {
    const CliResult r =
        smoothforce("loop --mesh " + path("cube.obj") + " --device replay:" + path("hips.csv") +
                    " --duration 0.9 --max-force-step 100 --max-missed 1000000 --patch-capacity " + capacity);
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_EQ(r.out.find("patches built"), std::string::npos) << r.out;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.out, m, std::regex(R"(contacts: [0-9]+ steps in contact, ([0-9]+) onsets)")))
        << r.out;
    const int onsets = std::stoi(m[1]);
    EXPECT_GE(onsets, 7) << "12 presses of 25 ms each\n" << r.out;
    ASSERT_TRUE(std::regex_search(
        r.out, m,
        std::regex(
            R"(\npatch constructions: ([0-9]+) for 6 faces \(a face evicted and needed again is built again\)\n)")))
        << r.out;
    const int built = std::stoi(m[1]);
    if (std::string(capacity) == "1") {
      EXPECT_GE(built, onsets) << "each press builds the face the one before evicted\n" << r.out;
      EXPECT_GT(built, 6) << r.out;
    } else {
      EXPECT_GE(built, 2) << r.out;  // the top and the side, built once each
      EXPECT_LE(built, 6) << r.out;
    }
    ++checked;
  }
  EXPECT_EQ(checked, 2);
}

TEST_F(RuntimeCli, OptionErrorsAreOneLine) {
  expectError("--rate 0", "--rate: expected a rate in [1, 10000] Hz, got '0'");
  expectError("--rate 20000", "--rate:");
  expectError("--duration -1", "--duration:");
  expectError("--stiffness 0", "--stiffness:");
  expectError("--speed -2", "--speed:");
  expectError("--depth 0", "--depth:");
  expectError("--max-force 0", "--max-force:");
  expectError("--device warp", "--device: expected null, scripted");
  expectError("--device replay:" + path("none.csv"), "none.csv: cannot open");
  expectError("--method magic", "--method");
  expectError("--cache x.sfcache", "excludes");
  std::ofstream(path("bad.json")) << R"({"objects": [{"mesh": "cube.obj", "pose": {"scale": 0}}]})";
  const CliResult r = smoothforce("loop --scene " + path("bad.json") + " --duration 0.05");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.out.find("bad.json: /objects/0/pose/scale: expected a scale in [1e-09, 1e+09], got 0"), std::string::npos)
      << r.out;
  const CliResult none = smoothforce("loop --duration 0.05");
  EXPECT_NE(none.out.find("give exactly one of --scene, --cache, --mesh"), std::string::npos) << none.out;
}

TEST_F(RuntimeCli, SceneWithTwoObjects) {
  std::ofstream(path("scene.json")) << R"({"objects": [
      {"mesh": "cube.obj"},
      {"mesh": "cube.obj", "method": "direct", "pose": {"translation": [1.5, 0, 0], "scale": 0.5}}]})";
  const CliResult r = smoothforce("loop --scene " + path("scene.json") + " --device scripted --duration 0.2");
  ASSERT_EQ(r.status, 0) << r.out;
  std::smatch m;  // the patch object builds what it touches, the direct one nothing; one cube file: 6 faces
  ASSERT_TRUE(std::regex_search(
      r.out, m,
      std::regex(
          R"(\npatch constructions: ([0-9]+) for 6 faces \(a face evicted and needed again is built again\)\n)")))
      << r.out;
  EXPECT_GE(std::stoi(m[1]), 1) << r.out;
  EXPECT_LE(std::stoi(m[1]), 6) << r.out;
}

}  // namespace
