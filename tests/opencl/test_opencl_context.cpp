// SPDX-License-Identifier: Apache-2.0
// Unit and expected-failure tests of the OpenCL layer (host/opencl_context.h): device
// selection, error messages with the build log, the on-disk program-binary cache.
// Skipped with the reason when no OpenCL device exists.
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <string>

#include <smoothforce/opencl/opencl_backend.h>
#include <smoothforce/opencl/opencl_context.h>

namespace {

using namespace sf;

class OpenCLContextTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string why;
    if (!openclAvailable(&why)) GTEST_SKIP() << "no OpenCL device: " << why;
    dir_ = std::filesystem::temp_directory_path() / ("sf_clcache_" + std::to_string(::getpid()) + "_" +
                                                     ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    if (!dir_.empty()) std::filesystem::remove_all(dir_, ec);
  }
  std::filesystem::path dir_;
};

// A unique kernel per test run, so that no earlier cache entry can answer for it.
std::string tinyKernel() {
  return "__kernel void sf_twice(__global float* a) { a[get_global_id(0)] *= 2.0f; } /* " + std::to_string(::getpid()) +
         " */\n";
}

TEST_F(OpenCLContextTest, SelectsDevicesByIndexAndName) {
  const auto all = listOpenCLDevices();
  ASSERT_FALSE(all.empty());
  EXPECT_EQ(selectOpenCLDevice("0").name, all[0].name);
  std::string part = all.back().name.substr(0, std::min<size_t>(8, all.back().name.size()));
  std::transform(part.begin(), part.end(), part.begin(), [](unsigned char c) { return std::toupper(c); });
  EXPECT_EQ(selectOpenCLDevice(part).index, std::find_if(all.begin(), all.end(), [&](const auto& d) {
                                              std::string n = d.name;
                                              std::transform(n.begin(), n.end(), n.begin(),
                                                             [](unsigned char c) { return std::toupper(c); });
                                              return n.find(part) != std::string::npos;
                                            })->index);
  EXPECT_NO_THROW(selectOpenCLDevice(""));
  try {
    selectOpenCLDevice("no-such-device-xyz");
    ADD_FAILURE() << "expected OpenCLError";
  } catch (const OpenCLError& e) {
    EXPECT_NE(std::string(e.what()).find("no-such-device-xyz"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(all[0].name), std::string::npos) << "lists devices: " << e.what();
  }
  EXPECT_THROW(selectOpenCLDevice(std::to_string(all.size())), OpenCLError);
}

TEST_F(OpenCLContextTest, BuildFailureNamesCallCodeAndLog) {
  OpenCLContext ctx;
  try {
    ctx.buildProgram({"__kernel void broken(__global float* a) { a[0] = sf_undeclared_thing; }\n"}, "-cl-std=CL1.2",
                     {false, ""});
    ADD_FAILURE() << "expected OpenCLError";
  } catch (const OpenCLError& e) {
    const std::string m = e.what();
    EXPECT_EQ(e.code(), CL_BUILD_PROGRAM_FAILURE);
    EXPECT_NE(m.find("clBuildProgram"), std::string::npos) << m;
    EXPECT_NE(m.find("CL_BUILD_PROGRAM_FAILURE (-11)"), std::string::npos) << m;
    EXPECT_NE(m.find("sf_undeclared_thing"), std::string::npos) << "build log missing: " << m;
    EXPECT_NE(m.find("-cl-std=CL1.2"), std::string::npos) << m;
  }
}

TEST_F(OpenCLContextTest, BinaryCacheWritesThenLoads) {
  OpenCLContext ctx;
  const ProgramCacheOptions cache{true, dir_.string()};
  const BuiltProgram a = ctx.buildProgram({tinyKernel()}, "-cl-std=CL1.2", cache);
  EXPECT_FALSE(a.fromCache);
  EXPECT_TRUE(a.cacheNote.empty()) << a.cacheNote;
  ASSERT_TRUE(std::filesystem::exists(a.cacheFile)) << a.cacheFile;
  EXPECT_EQ(std::filesystem::path(a.cacheFile).parent_path(), dir_);
  const BuiltProgram b = ctx.buildProgram({tinyKernel()}, "-cl-std=CL1.2", cache);
  EXPECT_TRUE(b.fromCache) << b.cacheNote;
  EXPECT_EQ(a.cacheFile, b.cacheFile);
  // the key covers the options and the source text
  EXPECT_NE(ctx.programKey({tinyKernel()}, "-cl-std=CL1.2"), ctx.programKey({tinyKernel()}, "-cl-std=CL1.2 -DX"));
  EXPECT_NE(ctx.programKey({tinyKernel()}, ""), ctx.programKey({tinyKernel() + " "}, ""));
  // the loaded program runs
  cl::Buffer buf(ctx.context(), CL_MEM_READ_WRITE, 4 * sizeof(float));
  float v[4] = {1, 2, 3, 4};
  ctx.queue().enqueueWriteBuffer(buf, CL_TRUE, 0, sizeof v, v);
  cl::Kernel k(b.program, "sf_twice");
  k.setArg(0, buf);
  ctx.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(4));
  ctx.queue().enqueueReadBuffer(buf, CL_TRUE, 0, sizeof v, v);
  EXPECT_EQ(v[3], 8.0f);
}

TEST_F(OpenCLContextTest, BadCacheIsNotFatal) {
  OpenCLContext ctx;
  const ProgramCacheOptions cache{true, dir_.string()};
  std::filesystem::create_directories(dir_);
  const std::string file = (dir_ / (ctx.programKey({tinyKernel()}, "-cl-std=CL1.2") + ".bin")).string();
  std::ofstream(file) << "not a program binary";
  const BuiltProgram a = ctx.buildProgram({tinyKernel()}, "-cl-std=CL1.2", cache);
  EXPECT_FALSE(a.fromCache);
  EXPECT_NE(a.cacheNote.find("rejected"), std::string::npos) << a.cacheNote;
  EXPECT_TRUE(ctx.buildProgram({tinyKernel()}, "-cl-std=CL1.2", cache).fromCache) << "rewritten";
  // an unusable directory: built from source, with a note
  const BuiltProgram b = ctx.buildProgram({tinyKernel()}, "-cl-std=CL1.2", {true, "/dev/null/sf_cache"});
  EXPECT_FALSE(b.fromCache);
  EXPECT_FALSE(b.cacheNote.empty());
}

TEST_F(OpenCLContextTest, DefaultCacheDirFollowsXdg) {
  const char* old = std::getenv("XDG_CACHE_HOME");
  const std::string keep = old ? old : "";
  ::setenv("XDG_CACHE_HOME", "/tmp/sf_xdg_test", 1);
  EXPECT_EQ(defaultProgramCacheDir(), "/tmp/sf_xdg_test/smoothforce/cl");
  if (old)
    ::setenv("XDG_CACHE_HOME", keep.c_str(), 1);
  else
    ::unsetenv("XDG_CACHE_HOME");
}

}  // namespace
