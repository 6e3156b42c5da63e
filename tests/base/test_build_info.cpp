// SPDX-License-Identifier: Apache-2.0
// Build information: the generated version header against CMake's project version,
// the CLI's --version, the OpenCL switch (a CPU-only build's OpenCL entry points fail with
// "built without OpenCL"), and the base module's CHECK macros and status bits.
#include <gtest/gtest.h>

#include <smoothforce/base/error.h>
#include <smoothforce/base/status.h>
#include <smoothforce/config.h>
#include <smoothforce/opencl/opencl_backend.h>
#include <smoothforce/opencl/opencl_refine.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/version.h>
#include <algorithm>
#include <string>
#include <utility>

#include "cli_test_support.h"
#include "gp_config.h"

namespace sf {
namespace {

TEST(BuildInfo, VersionHeaderIsTheProjectVersion) {
  EXPECT_STREQ(SF_VERSION_STRING, SF_PROJECT_VERSION);  // CMake's project(VERSION), passed separately
  EXPECT_EQ(std::to_string(SF_VERSION_MAJOR) + "." + std::to_string(SF_VERSION_MINOR) + "." +
                std::to_string(SF_VERSION_PATCH),
            SF_PROJECT_VERSION);
  EXPECT_EQ(SF_VERSION_NUMBER, SF_VERSION_MAJOR * 10000 + SF_VERSION_MINOR * 100 + SF_VERSION_PATCH);
}

TEST(BuildInfo, CliPrintsTheProjectVersion) {
  const test::CliResult r = test::smoothforce("--version");
  ASSERT_EQ(r.status, 0) << r.out;
  const std::string cpuOnly = SF_HAS_OPENCL ? "" : " (CPU-only: built without OpenCL)";
  EXPECT_EQ(r.out, "smoothforce " SF_PROJECT_VERSION + cpuOnly + "\n");
}

TEST(BuildInfo, OpenCLEntryPointsAgreeWithTheBuild) {
  std::string why;
  const bool available = openclAvailable(&why);
  if (SF_HAS_OPENCL) {
    if (!available) GTEST_SKIP() << "built with OpenCL, but no device: " << why;
    SUCCEED() << "built with OpenCL and a device exists";
    return;
  }
  // CPU-only: never available, and every entry point says why instead of crashing.
  EXPECT_FALSE(available);
  EXPECT_NE(why.find("built without OpenCL"), std::string::npos) << why;
  const PatchOptions po;
  PatchCache cache = buildPatchCache(loadMesh(SF_DATA_DIR "/spot_control_mesh.obj", po), po, Backend::Serial);
  auto expectUnavailable = [](auto&& call, const char* what) {
    try {
      call();
      ADD_FAILURE() << what << " did not throw";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("built without OpenCL"), std::string::npos) << e.what();
    }
  };
  expectUnavailable([&] { constructPatchesOpenCL(cache); }, "constructPatchesOpenCL");
  expectUnavailable([&] { OpenCLEvaluator ev(cache); }, "OpenCLEvaluator");
  expectUnavailable([&] { OpenCLRefiner rf(cache); }, "OpenCLRefiner");
  const int32_t face = 0;
  const double xi = 0, eta = 0;
  PatchPoint out;
  expectUnavailable([&] { evaluatePatchesOpenCL(cache, &face, &xi, &eta, 1, &out); }, "evaluatePatchesOpenCL");

  // the command line: one line naming the reason, non-zero status
  const test::CliResult r = test::smoothforce("cache build " SF_DATA_DIR "/spot_control_mesh.obj --backend opencl -o " +
                                              std::string(::testing::TempDir()) + "sf_cpu_only.sfcache");
  EXPECT_NE(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("smoothforce: OpenCL construction: SmoothForce was built without OpenCL"), std::string::npos)
      << r.out;
}

TEST(BaseError, ChecksPassSilentlyAndFailWithBothOperands) {
  const int three = 3, four = 4;
  EXPECT_NO_THROW(SF_CHECK(three < four));
  EXPECT_NO_THROW(SF_CHECK_EQ(three, 3));
  EXPECT_NO_THROW(SF_CHECK_NE(three, four));
  EXPECT_NO_THROW(SF_CHECK_LT(three, four));
  EXPECT_NO_THROW(SF_CHECK_LE(four, four));
  EXPECT_NO_THROW(SF_CHECK_GT(four, three));
  EXPECT_NO_THROW(SF_CHECK_GE(three, three));
  auto message = [](auto&& call) {
    try {
      call();
    } catch (const InternalError& e) {
      return std::string(e.what());
    }
    return std::string("no throw");
  };
  const std::string eq = message([&] { SF_CHECK_EQ(three, four); });
  EXPECT_NE(eq.find("test_build_info.cpp:"), std::string::npos) << eq;
  EXPECT_NE(eq.find("CHECK failed: three == four (3 vs. 4)"), std::string::npos) << eq;
  const std::string plain = message([&] { SF_CHECK(four < three); });
  EXPECT_NE(plain.find("CHECK failed: four < three"), std::string::npos) << plain;
  EXPECT_NE(message([&] { SF_CHECK_NE(three, 3); }).find("(3 vs. 3)"), std::string::npos);
  EXPECT_NE(message([&] { SF_CHECK_LT(four, three); }).find("four < three (4 vs. 3)"), std::string::npos);
  EXPECT_NE(message([&] { SF_CHECK_LE(four, three); }).find("four <= three (4 vs. 3)"), std::string::npos);
  EXPECT_NE(message([&] { SF_CHECK_GT(three, four); }).find("three > four (3 vs. 4)"), std::string::npos);
  EXPECT_NE(message([&] { SF_CHECK_GE(three, four); }).find("three >= four (3 vs. 4)"), std::string::npos);
  // operands are evaluated once
  int calls = 0;
  SF_CHECK_EQ(++calls, 1);
  EXPECT_EQ(calls, 1);
}

TEST(BaseStatus, BitsAreDistinctAndTrackBitsLieAboveThePatchBits) {
  // kStatusBits (the names Python and the C API give): one bit each, distinct, by prefix the
  // SF_ST_* bits below SF_TRACK_MASK's, which they fill as the SF_PROBE_* bits fill SF_PROBE_MASK
  uint32_t all = 0, allSt = 0, allTrack = 0, allProbe = 0;
  int n = 0;
  const std::pair<const char*, uint32_t*> groups[] = {
      {"SF_ST_", &allSt}, {"SF_TRACK_", &allTrack}, {"SF_PROBE_", &allProbe}};
  for (const StatusBit& b : kStatusBits) {
    const std::string name = b.name;
    EXPECT_EQ(b.value & (b.value - 1), 0u) << name << ": one bit each";
    EXPECT_NE(b.value, 0u) << name;
    EXPECT_EQ(all & b.value, 0u) << name << ": distinct";
    all |= b.value;
    int in = 0;
    for (const auto& [prefix, bits] : groups) {
      if (name.rfind(prefix, 0) != 0) continue;
      *bits |= b.value;
      ++in;
    }
    EXPECT_EQ(in, 1) << name << ": one of the three prefixes";
    ++n;
  }
  EXPECT_EQ(n, 28);
  EXPECT_EQ(allSt, SF_ST_AFFINE * 2 - 1);  // 0x1 .. 0x800, no gap
  EXPECT_EQ(allTrack, SF_TRACK_MASK);
  EXPECT_EQ(allProbe, SF_PROBE_MASK);
  EXPECT_EQ(kStatusBits[10].value, SF_ST_MODEL_POINT);
  EXPECT_STREQ(kStatusBits[10].name, "SF_ST_MODEL_POINT");
  EXPECT_EQ(kStatusBits[11].value, SF_ST_AFFINE);
  EXPECT_EQ(SF_TRACK_MASK & (SF_ST_AFFINE * 2 - 1), 0u);
  // the kernels' spelling (compile-time asserted in base/status.cpp as well)
  EXPECT_EQ(SF_ST_DEGENERATE_MASK, uint32_t(GP_ST_DEGENERATE_MASK));
  EXPECT_EQ(SF_TRACK_DEGENERATE, uint32_t(GP_TRACK_DEGENERATE));
  EXPECT_EQ(SF_TRACK_FOLD_EDGE, uint32_t(GP_TRACK_FOLD_EDGE));
}

}  // namespace
}  // namespace sf
