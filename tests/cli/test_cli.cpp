// SPDX-License-Identifier: Apache-2.0
// End-to-end tests of the `smoothforce` command line: exit status, one-line errors, files.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli_test_support.h"

namespace {

namespace fs = std::filesystem;

using CliRun = sf::test::CliResult;
CliRun run(const std::string& args) { return sf::test::smoothforce(args); }

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() / ("sf_cli_" + std::to_string(::getpid()));
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }
  std::string file(const std::string& name, const std::string& content = "") {
    const std::string p = (dir / name).string();
    if (!content.empty()) std::ofstream(p) << content;
    return p;
  }
  std::string mesh = std::string(SF_DATA_DIR) + "/spot_control_mesh.obj";
  fs::path dir;
};

TEST_F(Cli, HelpOnEverySubcommand) {
  for (const char* sub : {"", "cache", "cache build", "cache info", "eval", "export"}) {
    const CliRun r = run(std::string(sub) + " --help");
    EXPECT_EQ(r.status, 0) << sub << "\n" << r.out;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << sub;
  }
}

TEST_F(Cli, CacheBuildInfoEvalExport) {
  const std::string cache = file("spot.sfcache");
  CliRun r = run("cache build " + mesh + " -o " + cache);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("180 faces: 4 tri, 160 quad, 16 5-gon"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("patches/s"), std::string::npos);
  r = run("cache info " + cache);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("188 vertices, 180 faces"), std::string::npos) << r.out;

  const std::string pts = file("pts.csv", "face,xi,eta\n0,1,0\n3,0,0\n179,0.2,-0.3\n");
  const std::string out = file("out.csv");
  r = run("eval " + cache + " --points " + pts + " -o " + out);
  ASSERT_EQ(r.status, 0) << r.out;
  std::ifstream in(out);
  std::string header, row;
  std::getline(in, header);
  EXPECT_EQ(header, "face,xi,eta,x,y,z,nx,ny,nz");
  int rows = 0;
  while (std::getline(in, row)) ++rows;
  EXPECT_EQ(rows, 3);
  // the same from the mesh directly, and with the serial backend: identical text
  const std::string out2 = file("out2.csv");
  r = run("eval " + mesh + " --backend serial --points " + pts + " -o " + out2);
  ASSERT_EQ(r.status, 0) << r.out;
  std::stringstream a, b;
  a << std::ifstream(out).rdbuf();
  b << std::ifstream(out2).rdbuf();
  EXPECT_EQ(a.str(), b.str());

  for (const char* ext : {".obj", ".ply"}) {
    const std::string tess = file(std::string("tess") + ext);
    r = run("export " + cache + " --level 3 -o " + tess + " --no-weld");
    ASSERT_EQ(r.status, 0) << r.out;
    // 4 tri * (1+3*6) + 160 quad * (1+4*6) + 16 pentagons * (1+5*6) vertices
    EXPECT_NE(r.out.find("(4572 vertices"), std::string::npos) << r.out;
    EXPECT_GT(fs::file_size(tess), 1000u);
    // Welded along the 366 shared edges: 188 V + 366 E * 2 + interiors 4 * 10 + 160 * 13 + 16 * 16
    // (tests/test_viewer_outputs.py checks the welded surface in VTK).
    r = run("export " + cache + " --level 3 -o " + tess);
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_NE(r.out.find("(3296 vertices"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("0 edges left open"), std::string::npos) << r.out;
  }
}

TEST_F(Cli, ErrorsAreOneLineWithNonZeroExit) {
  struct Case {
    std::string args, expect;
  };
  const std::string cache = file("c.sfcache");
  ASSERT_EQ(run("cache build " + mesh + " -o " + cache).status, 0);
  const std::string outside = file("outside.csv", "face,xi,eta\n0,0,0\n0,0.99,0.5\n");
  const std::string badface = file("badface.csv", "face,xi,eta\n180,0,0\n");
  const std::string badnum = file("badnum.csv", "face,xi,eta\n0,0,abc\n");
  const std::string badhdr = file("badhdr.csv", "f,x,y\n0,0,0\n");
  const std::string garbage = file("garbage.sfcache", std::string(300, 'z'));
  const std::string out = file("o.csv");
  for (const Case& c : std::vector<Case>{
           {"eval " + cache + " --points " + outside + " -o " + out,
            "outside.csv:3: (xi, eta) = (0.99, 0.5) is outside"},
           {"eval " + cache + " --points " + badface + " -o " + out, "badface.csv:2: face 180 out of range"},
           {"eval " + cache + " --points " + badnum + " -o " + out, "badnum.csv:2: eta is not a finite number"},
           {"eval " + cache + " --points " + badhdr + " -o " + out, "badhdr.csv:1: expected header"},
           {"cache info " + garbage, "not a SmoothForce patch cache"},
           {"cache info " + file("missing.sfcache"), "cannot open"},
           {"cache build " + file("nothere.obj") + " -o " + cache, "nothere.obj"},
           {"cache build " + mesh + " --precision half", "precision"},
           {"export " + cache + " --level 0 -o " + file("x.obj"), "level"},
           {"export " + cache + " --level 2 -o " + file("x.stl"), ".obj or .ply"},
       }) {
    const CliRun r = run(c.args);
    EXPECT_GT(r.status, 0) << c.args << "\n" << r.out;
    EXPECT_NE(r.out.find(c.expect), std::string::npos) << c.args << "\n" << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << "one line: " << r.out;
  }
}

}  // namespace
