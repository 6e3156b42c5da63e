// SPDX-License-Identifier: Apache-2.0
// The command line's contract, the loop and the signals: `loop` and scene
// objects take the patch options and render the surface `trace` renders with the same
// options; a latched safety fault exits 3; SIGINT and SIGTERM stop loop, trace and sweep
// alike with 130 and 143.
#include <gtest/gtest.h>

#include <cmath>
#include <csignal>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "cli_contract_support.h"

namespace {

namespace fs = std::filesystem;
using sf::test::CliStreams;
using sf::test::fileBytes;
using json = nlohmann::json;

class LoopContract : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir = fs::temp_directory_path() / ("sf_loop_contract_" + std::to_string(::getpid()));
    fs::create_directories(dir);
  }
  static void TearDownTestSuite() { fs::remove_all(dir); }
  CliStreams run(const std::string& args, int signal = 0, double after = 0) const {
    return sf::test::runStreams(dir, args, "", signal, after);
  }
  static std::string file(const std::string& name, const std::string& content = "") {
    const std::string p = (dir / name).string();
    if (!content.empty()) std::ofstream(p, std::ios::binary) << content;
    return p;
  }
  static inline fs::path dir;
  static inline const std::string spot = std::string(SF_DATA_DIR) + "/spot_control_mesh.obj";
  static inline const std::string sphere = std::string(SF_SHARED_MESHES) + "/polygon_laplacian/quad-sphere.off";
};

std::vector<std::vector<double>> rows(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);  // header
  std::vector<std::vector<double>> v;
  while (std::getline(in, line)) {
    std::vector<double> r;
    std::istringstream cells(line);
    for (std::string c; std::getline(cells, c, ',');) r.push_back(std::stod(c));
    v.push_back(r);
  }
  return v;
}

// A HIP held 1% of the cage's size inside the patch of face 17: loop (replay device, one
// sample held) and trace (the HIP repeated) step the same renderer on the same HIPs, so the
// forces before safety (rfx, rfy, rfz of the record) equal trace's, for each --normals.
TEST_F(LoopContract, LoopRendersTheSurfaceTraceRendersWithTheSamePatchOptions) {
  std::vector<std::vector<double>> forces[2];
  const char* modes[2] = {"angle", "area"};
  for (int k = 0; k < 2; ++k) {
    const std::string mode = modes[k];
    const CliStreams e = run("eval " + spot + " --normals " + mode + " --points " +
                             file("p.csv", "face,xi,eta\n17,0.1,0.2\n") + " -o -");
    ASSERT_EQ(e.status, 0) << e.err;
    const std::vector<double> p = rows(e.out).at(0);  // face,xi,eta,x,y,z,nx,ny,nz
    char hip[160];
    std::snprintf(hip, sizeof hip, "%.17g,%.17g,%.17g", p[3] - 0.01 * p[6], p[4] - 0.01 * p[7], p[5] - 0.01 * p[8]);
    std::string hips = "x,y,z\n";
    for (int i = 0; i < 100; ++i) hips += std::string(hip) + "\n";
    const std::string trace = file("trace_" + mode + ".csv"), rec = file("rec_" + mode + ".csv");
    CliStreams r =
        run("trace --mesh " + spot + " --normals " + mode + " --hips " + file("h.csv", hips) + " -o " + trace);
    ASSERT_EQ(r.status, 0) << r.err;
    r = run("loop --mesh " + spot + " --normals " + mode + " --device replay:" +
            file("one.csv", "t,x,y,z\n0," + std::string(hip) + "\n") + " --duration 0.1 --record " + rec);
    ASSERT_EQ(r.status, 0) << r.err;
    const auto t = rows(fileBytes(trace)), l = rows(fileBytes(rec));
    ASSERT_EQ(t.size(), 100u);
    ASSERT_GE(l.size(), 10u);  // 100 ticks; some are skipped on a loaded machine
    ASSERT_LE(l.size(), 100u);
    int compared = 0;
    for (size_t i = 0; i < l.size(); ++i) {
      ASSERT_EQ(t[i][3], 1) << "in contact";
      for (int a = 0; a < 3; ++a) EXPECT_NEAR(l[i][8 + a], t[i][10 + a], 1e-5 * std::abs(t[i][10 + a]) + 1e-12);
      ++compared;
    }
    EXPECT_EQ(compared, static_cast<int>(l.size()));
    forces[k] = t;
  }
  // the option matters: the two surfaces give different forces at this HIP
  double diff = 0;
  for (int a = 0; a < 3; ++a) diff = std::max(diff, std::abs(forces[0][0][10 + a] - forces[1][0][10 + a]));
  EXPECT_GT(diff, 1e-4) << "--normals angle and area render the same force here: pick another face";
}

TEST_F(LoopContract, SceneObjectsTakeThePatchKeys) {
  fs::copy_file(spot, dir / "spot.obj", fs::copy_options::overwrite_existing);
  file("scene.json", R"({"objects": [
      {"name": "a", "mesh": "spot.obj", "normals": "area", "precision": "float", "cross_tangent": "blend",
       "orient": "keep"},
      {"name": "b", "mesh": "spot.obj", "pose": {"translation": [3, 0, 0]}}]})");
  CliStreams r = run("loop --scene " + file("scene.json") + " --normals angle --device null --duration 0.02 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json j = json::parse(r.out);
  ASSERT_EQ(j["objects"].size(), 2u);
  const json& a = j["objects"][0];
  EXPECT_EQ(a["normals"], "area");
  EXPECT_EQ(a["precision"], "float");
  EXPECT_EQ(a["cross_tangent"], "blend");
  const json& b = j["objects"][1];  // the command line's options are the defaults
  EXPECT_EQ(b["normals"], "angle");
  EXPECT_EQ(b["precision"], "double");
  EXPECT_EQ(b["cross_tangent"], "corrected");
  // errors name the key; a cache keeps its own options
  ASSERT_EQ(run("cache build " + spot + " -o " + file("spot.sfcache")).status, 0);
  struct Bad {
    std::string scene, message;
  };
  for (const Bad& bad : {Bad{R"({"objects": [{"mesh": "spot.obj", "normals": "weird"}]})", "/objects/0/normals"},
                         Bad{R"({"objects": [{"mesh": "spot.obj", "orient": "in"}]})", "/objects/0/orient"},
                         Bad{R"({"objects": [{"cache": "spot.sfcache", "normals": "area"}]})",
                             "/objects/0/normals: applies to mesh objects only"},
                         Bad{R"({"objects": [{"mesh": "spot.obj", "cross-tangent": "paper"}]})",
                             "/objects/0/cross-tangent: unknown key"}}) {
    r = run("loop --scene " + file("bad.json", bad.scene) + " --duration 0.02");
    EXPECT_EQ(r.status, 1) << bad.scene;
    EXPECT_NE(r.err.find(bad.message), std::string::npos) << r.err;
  }
}

TEST_F(LoopContract, SceneObjectsTakeTheCageKey) {
  fs::copy_file(spot, dir / "spot.obj", fs::copy_options::overwrite_existing);
  file("cage.json", R"({"objects": [{"name": "a", "mesh": "spot.obj", "cage": "catmull-clark"},
      {"name": "b", "mesh": "spot.obj", "pose": {"translation": [3, 0, 0]}}]})");
  CliStreams r = run("loop --scene " + file("cage.json") + " --device null --duration 0.02 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json j = json::parse(r.out);
  ASSERT_EQ(j["objects"].size(), 2u);
  EXPECT_EQ(j["objects"][0]["cage"], "catmull-clark");
  EXPECT_EQ(j["objects"][1]["cage"], "none");
  r = run("loop --scene " + file("cage.json") + " --cage catmull-clark --device null --duration 0.02 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(json::parse(r.out)["objects"][1]["cage"], "catmull-clark");  // the command line gives the default
  r = run("loop --scene " + file("bad.json", R"({"objects": [{"mesh": "spot.obj", "cage": "loop"}]})") +
          " --duration 0.02");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("/objects/0/cage: cage: expected none|catmull-clark, got 'loop'"), std::string::npos) << r.err;
}

TEST_F(LoopContract, ACacheKeepsItsPatchOptions) {
  const std::string cache = file("auto.sfcache");
  ASSERT_EQ(run("cache build " + spot + " -o " + cache).status, 0);
  const std::string hips = file("h1.csv", "x,y,z\n0,0,5\n");
  for (const std::string& cmd : {"loop --cache " + cache + " --device null --duration 0.02",
                                 "trace --cache " + cache + " --hips " + hips + " -o " + file("o.csv")}) {
    CliStreams r = run(cmd + " --normals angle");
    EXPECT_EQ(r.status, 1) << cmd;
    EXPECT_NE(r.err.find("auto.sfcache: built with --normals auto, but --normals angle was given"), std::string::npos)
        << r.err;
    r = run(cmd + " --normals auto --precision double");
    EXPECT_EQ(r.status, 0) << cmd << "\n" << r.err;
  }
}

// A latched safety fault exits 3: RuntimeUdpCli covers it (the sender stopping: a stale
// device), text and --json. A device scale of 1e300 overflowed the HIP to infinity here
// ("non-finite HIP position"); such a scene is now refused, naming the key (exit 1).
TEST_F(LoopContract, ADeviceScaleThatWouldOverflowTheHipIsRefused) {
  const std::string replay = "replay:" + file("far.csv", "t,x,y,z\n0,-1e10,0,0\n1,1e10,0,0\n");
  const std::string scene = file("scaled.json",
                                 "{\"device\": {\"transform\": {\"scale\": 1e300}}, \"objects\": "
                                 "[{\"mesh\": \"" +
                                     sphere + "\"}]}");
  CliStreams r = run("loop --scene " + scene + " --device " + replay + " --duration 0.05");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("scaled.json: /device/transform/scale: expected a scale in [1e-09, 1e+09], got 1e+300"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.out, "");
  // the same loop on a finite replay: 0; --json has "udp" with a udp device only
  r = run("loop --mesh " + sphere + " --device replay:" + file("ok.csv", "t,x,y,z\n0,0,0,2\n1,0,0,1.5\n") +
          " --duration 0.05 --json");
  EXPECT_EQ(r.status, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["exit_status"], 0);
  EXPECT_FALSE(j.contains("udp"));
}

// --speed beyond 10 m/s is a usage error (exit 2) for both scripted paths: 1e308 m/s read
// past the end of the path's arrays (valgrind), 1e200 m/s made the HIP jump anywhere.
TEST_F(LoopContract, AbsurdScriptedSpeedsAreUsageErrors) {
  int refused = 0;
  for (const char* device : {"scripted:slide", "scripted:circle"}) {
    for (const char* speed : {"1e308", "1e200", "11", "0"}) {
      const CliStreams r =
          run("loop --mesh " + sphere + " --device " + device + " --speed " + speed + " --duration 0.05");
      EXPECT_EQ(r.status, 2) << device << " " << speed << "\n" << r.err;
      EXPECT_NE(r.err.find("--speed: expected a speed in (0, 10] m/s, got "), std::string::npos) << r.err;
      EXPECT_EQ(r.out, "");
      refused += r.status == 2;
    }
  }
  EXPECT_EQ(refused, 8);
  const CliStreams r = run("loop --mesh " + sphere + " --device scripted:circle --speed 10 --duration 0.05");
  EXPECT_EQ(r.status, 0) << r.err;
}

// A replay of absolute times (1.7e9 s since 1970) held its first sample for the whole run
// with no sign: refused, naming the file, its first time and the run's duration. A replay
// read from stdin is named <stdin> in its errors (it was "-").
TEST_F(LoopContract, ReplaysThatTheRunNeverReachesAreRefused) {
  const std::string epoch = file("epoch.csv", "t,x,y,z\n1700000000.000000,0,0,2\n1700000000.001000,0,0,1.5\n");
  CliStreams r = run("loop --mesh " + sphere + " --device replay:" + epoch + " --duration 2");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("epoch.csv: the first sample is at t = 1700000000 s, not before the run's end (2 s)"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.out, "");
  r = sf::test::runStreams(dir, "loop --mesh " + sphere + " --device replay:- --duration 0.05",
                           "t,x,y,z\n0,0,0,2\n1,0,0,1.5\n1,0,0,1\n");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("<stdin>:4: time 1 s is not greater than the previous row's"), std::string::npos) << r.err;
  r = sf::test::runStreams(dir, "loop --mesh " + sphere + " --device replay:- --duration 0.05",
                           "t,x,y,z\n0,0,0,2\n1,0,0,1.5\n");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("device: replay <stdin> ("), std::string::npos) << r.out;
}

// A scene's cache objects keep their options as --cache does: --precision float or --normals
// file on the command line were ignored for them (they are the defaults of mesh objects).
TEST_F(LoopContract, SceneCacheObjectsKeepTheirPatchOptionsAsCacheDoes) {
  fs::copy_file(spot, dir / "spot.obj", fs::copy_options::overwrite_existing);
  ASSERT_EQ(run("cache build " + spot + " -o " + file("kept.sfcache")).status, 0);
  const std::string scene =
      file("mixed.json",
           R"({"objects": [{"mesh": "spot.obj"}, {"cache": "kept.sfcache", "pose": {"translation": [3, 0, 0]}}]})");
  const std::string only = file("only.json", R"({"objects": [{"cache": "kept.sfcache"}]})");
  struct Case {
    std::string scene, option, where;
  };
  int refused = 0;
  for (const Case& c : {Case{scene, "--precision float", "mixed.json: /objects/1 ("},
                        Case{only, "--precision float", "only.json: /objects/0 ("},
                        Case{only, "--normals file", "only.json: /objects/0 ("},
                        Case{only, "--normals angle", "only.json: /objects/0 ("},
                        Case{only, "--cross-tangent paper", "only.json: /objects/0 ("}}) {
    const std::string& opt = c.option;
    const CliStreams r = run("loop --scene " + c.scene + " " + opt + " --device null --duration 0.02");
    EXPECT_EQ(r.status, 1) << opt << "\n" << r.err;
    EXPECT_NE(r.err.find(c.where), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("kept.sfcache): built with " + opt.substr(0, opt.find(' '))), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("but " + opt + " was given"), std::string::npos) << r.err;
    refused += r.status == 1;
  }
  EXPECT_EQ(refused, 5);
  const CliStreams r =
      run("loop --scene " + scene + " --precision double --normals auto --device null --duration 0.02");
  EXPECT_EQ(r.status, 0) << r.err;
}

TEST_F(LoopContract, SigintAndSigtermStopEveryCommandAlike) {
  int checked = 0;
  for (int sig : {SIGINT, SIGTERM}) {
    const std::string name = sig == SIGINT ? "SIGINT" : "SIGTERM";
    // loop: the report of the steps run, then 130 / 143 (missed deadlines never latch a fault
    // here: a loaded machine's stall must not stop the loop before the signal does)
    CliStreams r = run("loop --mesh " + sphere + " --device scripted --duration 60 --max-missed 1000000", sig, 0.5);
    EXPECT_EQ(r.status, 128 + sig) << r.err;
    EXPECT_NE(r.out.find(", stopped early"), std::string::npos) << r.out;
    EXPECT_NE(r.err.find("loop: interrupted by " + name), std::string::npos) << r.err;
    // trace: nothing written
    std::string hips = "x,y,z\n";
    for (int i = 0; i < 300000; ++i) hips += "0.01,0.02," + std::to_string(0.9 + 0.2 * (i % 100) / 100.0) + "\n";
    const std::string out = file("t_" + name + ".csv");
    r = run("trace --mesh " + sphere + " --hips " + file("long.csv", hips) + " -o " + out, sig, 0.3);
    EXPECT_EQ(r.status, 128 + sig) << r.err;
    EXPECT_NE(r.err.find("trace: interrupted by " + name), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
    // sweep: a checkpoint of what is done, which --resume completes
    const std::string sw = file("sw_" + name);
    const std::string args = "sweep --mesh " + sphere +
                             " --depth 1% --samples 50000 --methods patch --threads 1 --no-plots " +
                             "--checkpoint-every 0.05 -o " + sw;
    r = run(args, sig, 0.3);
    EXPECT_EQ(r.status, 128 + sig) << r.err;
    EXPECT_NE(r.err.find("sweep: interrupted by " + name), std::string::npos) << r.err;
    EXPECT_NE(fileBytes(fs::path(sw) / "sweep.json").find("\"complete\": false"), std::string::npos);
    r = run(args + " --resume");
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("sweep: resuming shard 0/1"), std::string::npos) << r.err;
    EXPECT_NE(fileBytes(fs::path(sw) / "sweep.json").find("\"complete\": true"), std::string::npos);
    ++checked;
  }
  EXPECT_EQ(checked, 2);
}

}  // namespace
