// SPDX-License-Identifier: Apache-2.0
// Cache file: round trip, and rejection of truncated, corrupted, newer and mismatched files.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include <smoothforce/base/hash.h>
#include <smoothforce/patch/cache_file.h>
#include "patch_test_support.h"

namespace sf {
namespace {

std::string tmpPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("sf_test_" + std::to_string(::getpid()) + "_" + name)).string();
}

std::vector<char> slurp(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}
void spit(const std::string& p, const std::vector<char>& b) {
  std::ofstream(p, std::ios::binary).write(b.data(), static_cast<std::streamsize>(b.size()));
}

/// Expects readPatchCache to reject `path` with an InputError whose message starts with "<path>: "
/// and contains `fragment` (never empty: every case names what it expects).
void expectRejected(const std::string& path, const std::string& fragment, const CacheExpectation& ex = {}) {
  ASSERT_FALSE(fragment.empty());
  try {
    readPatchCache(path, ex);
    ADD_FAILURE() << "accepted " << path << " (expected '" << fragment << "')";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(path + ": ", 0), 0u) << msg;
    EXPECT_NE(msg.find(fragment), std::string::npos) << "expected '" << fragment << "' in: " << msg;
  }
}

class CacheFile : public ::testing::Test {
 protected:
  void SetUp() override {
    for (auto p : {Precision::Double, Precision::Float}) {
      PatchOptions o;
      o.precision = p;
      caches.push_back(
          buildPatchCache(loadMesh(std::string(SF_DATA_DIR) + "/spot_control_mesh.obj", o), o, Backend::Tbb));
    }
    path = tmpPath("cache.sfcache");
    writePatchCache(caches[0], path);
  }
  void TearDown() override { std::filesystem::remove(path); }
  std::vector<PatchCache> caches;
  std::string path;
};

TEST_F(CacheFile, RoundTripIsExact) {
  for (const PatchCache& c : caches) {
    writePatchCache(c, path);
    const PatchCache r = readPatchCache(path, {c.meshHash, c.options});
    EXPECT_EQ(r.positions, c.positions);
    EXPECT_EQ(r.faceOffsets, c.faceOffsets);
    EXPECT_EQ(r.faceVertices, c.faceVertices);
    EXPECT_EQ(r.slotTwin, c.slotTwin);
    EXPECT_EQ(r.faceStatus, c.faceStatus);
    EXPECT_EQ(r.edgeDataD, c.edgeDataD);
    EXPECT_EQ(r.edgeDataF, c.edgeDataF);
    EXPECT_EQ(r.meshHash, c.meshHash);
  }
  EXPECT_TRUE(isPatchCacheFile(path));
}

// Both precisions of the spot cage (test_hostile_cache.cpp damages the cube cache byte by byte;
// these are a real mesh's files): every cut names what is missing, with the byte counts.
TEST_F(CacheFile, RejectsTruncated) {
  int cases = 0;
  for (const PatchCache& cache : caches) {
    writePatchCache(cache, path);
    const auto b = slurp(path);
    ASSERT_GT(b.size(), 400u);
    const std::string payload = std::to_string(b.size() - 128) + " bytes";
    for (size_t keep : {size_t(0), size_t(5), size_t(100), size_t(128), b.size() / 2, b.size() - 1}) {
      spit(path, std::vector<char>(b.begin(), b.begin() + static_cast<long>(keep)));
      SCOPED_TRACE("kept " + std::to_string(keep) + " of " + std::to_string(b.size()) + " bytes");
      if (keep < 8)
        expectRejected(path, "not a SmoothForce patch cache (too short, no SFPATCH header)");
      else if (keep < 128)
        expectRejected(path, "truncated cache file: " + std::to_string(keep) + " bytes, shorter than its header");
      else
        expectRejected(path, "truncated cache file: payload has " + std::to_string(keep - 128) + " of " + payload);
      ++cases;
    }
  }
  EXPECT_EQ(cases, 12);
}

// A bit flipped in the magic, in every header field and across the payload: each is caught by
// the check that covers its byte (magic, header checksum, payload checksum).
TEST_F(CacheFile, RejectsCorruption) {
  int magic = 0, header = 0, payload = 0;
  for (const PatchCache& cache : caches) {
    writePatchCache(cache, path);
    const auto b = slurp(path);
    for (size_t at : {size_t(3), size_t(9), size_t(17), size_t(33), size_t(41), size_t(60), size_t(70), size_t(90),
                      size_t(121), size_t(200), b.size() / 2, b.size() - 3}) {
      auto c = b;
      c[at] ^= 0x10;
      spit(path, c);
      SCOPED_TRACE("byte " + std::to_string(at));
      if (at < 8) {
        expectRejected(path, "not a SmoothForce patch cache (bad magic)");
        ++magic;
      } else if (at < 128) {
        expectRejected(path, "corrupted cache header (checksum mismatch)");
        ++header;
      } else {
        expectRejected(path, "corrupted cache payload (checksum mismatch)");
        ++payload;
      }
    }
    auto c = b;
    c.push_back('x');
    spit(path, c);
    expectRejected(path, "trailing bytes after the cache payload");
  }
  EXPECT_EQ(magic, 2);
  EXPECT_EQ(header, 16);
  EXPECT_EQ(payload, 6);
}

TEST_F(CacheFile, RejectsNewerVersionAndMismatch) {
  auto b = slurp(path);
  // a newer version with a valid header checksum: recompute it as a newer writer would
  uint32_t v = kCacheFormatVersion + 1;
  std::memcpy(&b[8], &v, 4);
  const uint64_t hc = hashBytes(b.data(), 120);
  std::memcpy(&b[120], &hc, 8);
  spit(path, b);
  expectRejected(path, "written by a newer SmoothForce (cache format " + std::to_string(v) + ")");

  writePatchCache(caches[0], path);
  expectRejected(path, "cache was built from a different mesh", {caches[0].meshHash + 1, std::nullopt});
  PatchOptions other = caches[0].options;
  other.crossTangent = CrossTangentMode::Paper;
  expectRejected(path, "cache was built with different options", {std::nullopt, other});
}

TEST_F(CacheFile, MissingFileAndNonCache) {
  expectRejected(tmpPath("does_not_exist.sfcache"), "cannot open cache file");
  spit(path, std::vector<char>(4096, 'a'));
  expectRejected(path, "not a SmoothForce patch cache (bad magic)");
}

}  // namespace
}  // namespace sf
