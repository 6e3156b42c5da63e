// SPDX-License-Identifier: Apache-2.0
// `smoothforce trace` end to end.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "cli_test_support.h"

namespace {

namespace fs = std::filesystem;

using sf::test::CliResult;
using TraceRun = CliResult;
CliResult runCli(const std::string& args) { return sf::test::smoothforce(args); }

class ForceTraceCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() / ("sf_trace_" + std::to_string(::getpid()));
    fs::create_directories(dir);
  }
  void TearDown() override {
    if (!dir.empty()) fs::remove_all(dir);
  }
  std::string file(const std::string& name, const std::string& content = "") {
    const std::string p = (dir / name).string();
    if (!content.empty()) std::ofstream(p) << content;
    return p;
  }
  std::string mesh = std::string(SF_SHARED_MESHES) + "/polygon_laplacian/quad-sphere.off";
  fs::path dir;
};

std::vector<std::string> lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> v;
  for (std::string l; std::getline(in, l);) v.push_back(l);
  return v;
}

TEST_F(ForceTraceCli, EveryMethodWritesOneRowPerStep) {
  std::ostringstream hips;  // approach the sphere along +z, press in, slide, leave
  hips << "x,y,z\n";
  int rows = 0;
  for (int i = 0; i <= 20; ++i, ++rows) hips << "0.01,0.02," << 1.1 - 0.15 * i / 20 << "\n";
  for (int i = 1; i <= 40; ++i, ++rows) {
    const double a = 0.6 * i / 40;
    hips << 0.95 * std::sin(a) << ",0.02," << 0.95 * std::cos(a) << "\n";
  }
  for (int i = 1; i <= 10; ++i, ++rows) hips << 0.95 * std::sin(0.6) * (1 + 0.03 * i) << ",0.02,0.8\n";
  const std::string in = file("hips.csv", hips.str());
  for (const char* m : {"patch --refine newton", "patch --refine paper", "direct", "shading"}) {
    const std::string out = file("out.csv");
    const TraceRun r =
        runCli("trace --mesh " + mesh + " --method " + m + " --hips " + in + " -o " + out + " --stiffness 200");
    ASSERT_EQ(r.status, 0) << m << "\n" << r.out;
    EXPECT_NE(r.out.find("trace: " + std::to_string(rows) + " steps"), std::string::npos) << r.out;
    const auto l = lines(out);
    ASSERT_EQ(static_cast<int>(l.size()), rows + 1) << m;
    EXPECT_EQ(l[0], "x,y,z,contact,face,xi,eta,scp_x,scp_y,scp_z,fx,fy,fz,iterations,status");
    int contact = 0;
    for (size_t i = 1; i < l.size(); ++i) {
      std::vector<std::string> c;
      std::stringstream ss(l[i]);
      for (std::string f; std::getline(ss, f, ',');) c.push_back(f);
      ASSERT_EQ(c.size(), 15u) << l[i];
      if (c[3] == "1") {
        ++contact;
        EXPECT_NE(c[4], "-1");
      } else {
        EXPECT_EQ(c[4], "-1");
        EXPECT_EQ(std::stod(c[10]), 0.0);
      }
    }
    EXPECT_GT(contact, 40) << m;
    EXPECT_LT(contact, rows) << m;
  }
}

// With --patch-capacity 1 a face evicted and needed again is built again: the report counted
// those constructions as "patches built lazily: 288 of 180 faces". It now says constructions.
TEST_F(ForceTraceCli, LazyPatchReportCountsConstructions) {
  std::ostringstream hips;  // back and forth across the top of the sphere, pressed in
  hips << "x,y,z\n";
  for (int pass = 0; pass < 6; ++pass)
    for (int i = 0; i <= 40; ++i) {
      const double a = -0.5 + (pass % 2 ? 40 - i : i) / 40.0;
      hips << 0.95 * std::sin(a) << ",0.02," << 0.95 * std::cos(a) << "\n";
    }
  const std::string in = file("hips.csv", hips.str());
  int checked = 0;
  for (const char* capacity : {"1", "0"}) {
    const TraceRun r =
        runCli("trace --mesh " + mesh + " --patch-capacity " + capacity + " --hips " + in + " -o " + file("out.csv"));
    ASSERT_EQ(r.status, 0) << r.out;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(
        r.out, m,
        std::regex(R"(trace: ([0-9]+) lazy patch constructions for ([0-9]+) faces \(at most ([0-9a-z]+) held)")))
        << r.out;
    EXPECT_EQ(m[3].str(), std::string(capacity) == "1" ? "1" : "all");
    EXPECT_GT(std::stoi(m[1]), 0);
    EXPECT_EQ(r.out.find("patches built lazily"), std::string::npos) << r.out;
    ++checked;
  }
  EXPECT_EQ(checked, 2);
}

TEST_F(ForceTraceCli, RejectsBadInputWithFileAndLine) {
  const std::string out = file("o.csv");
  struct Bad {
    const char* content;
    const char* message;
  };
  for (const Bad& b : {Bad{"x,y\n1,2\n", ":1: expected header"}, Bad{"x,y,z\n1,2,3\n1,2\n", ":3: expected 3 columns"},
                       Bad{"x,y,z\n1,2,3\n1,abc,3\n", ":3: y is not a finite number"},
                       Bad{"x,y,z\n\n1,2,nan\n", ":3: z is not a finite number"}}) {
    const std::string in = file("bad.csv", b.content);
    const TraceRun r = runCli("trace --mesh " + mesh + " --hips " + in + " -o " + out);
    EXPECT_NE(r.status, 0) << b.content;
    EXPECT_NE(r.out.find(in + b.message), std::string::npos) << r.out;
  }
  const std::string in = file("ok.csv", "x,y,z\n0,0,2\n");
  EXPECT_NE(runCli("trace --hips " + in + " -o " + out).status, 0);  // neither --mesh nor --cache
  EXPECT_NE(runCli("trace --mesh " + mesh + " --cache " + mesh + " --hips " + in + " -o " + out).status, 0);
  EXPECT_NE(runCli("trace --mesh " + mesh + " --method god --hips " + in + " -o " + out).status, 0);
  EXPECT_NE(runCli("trace --mesh " + mesh + " --stiffness -5 --hips " + in + " -o " + out).status, 0);
  EXPECT_NE(runCli("trace --cache " + mesh + " --hips " + in + " -o " + out).status, 0);  // not a cache file
}

}  // namespace
