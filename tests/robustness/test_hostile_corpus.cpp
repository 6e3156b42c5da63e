// SPDX-License-Identifier: Apache-2.0
// Hostile input: every file of tests/data/hostile/ (made by
// tools/make_hostile_corpus.py) is rejected by readMesh / readPatchCache with an
// sf::InputError whose message starts with the file's path: never a crash, never another
// exception type. The cache variants that need valid XXH64 checksums are made here at run
// time from a freshly written cache (tests/robustness/test_hostile_cache.cpp).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <smoothforce/mesh/mesh_io.h>
#include <smoothforce/patch/cache_file.h>
#include "test_hostile_support.h"

namespace sf::hostile {
namespace {

namespace fs = std::filesystem;

const fs::path kCorpus = fs::path(SF_TEST_DATA) / "hostile";

/// INDEX.tsv: file -> why it must be rejected.
std::map<std::string, std::string> readIndex() {
  std::map<std::string, std::string> idx;
  std::ifstream in(kCorpus / "INDEX.tsv");
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    const size_t tab = line.find('\t');
    idx[line.substr(0, tab)] = tab == std::string::npos ? "" : line.substr(tab + 1);
  }
  return idx;
}

std::vector<fs::path> corpusFiles() {
  std::vector<fs::path> v;
  for (const auto& e : fs::directory_iterator(kCorpus))
    if (e.is_regular_file() && e.path().filename() != "INDEX.tsv") v.push_back(e.path());
  std::sort(v.begin(), v.end());
  return v;
}

TEST(HostileCorpus, EveryFileIsRejectedWithItsName) {
  const auto idx = readIndex();
  int meshes = 0, caches = 0;
  for (const fs::path& p : corpusFiles()) {
    const std::string path = p.string(), name = p.filename().string();
    SCOPED_TRACE(name + ": " + (idx.count(name) ? idx.at(name) : "(not in INDEX.tsv)"));
    if (p.extension() == ".sfcache") {
      ++caches;
      expectRejected(path, [&] { readPatchCache(path); });
    } else {
      ++meshes;
      expectRejected(path, [&] { readMesh(path); });
    }
  }
  EXPECT_GE(meshes + caches, 100);
  EXPECT_GE(caches, 5);
}

TEST(HostileCorpus, IndexMatchesTheFolderAndTheCorpusStaysSmall) {
  const auto idx = readIndex();
  std::set<std::string> files;
  uintmax_t bytes = 0;
  for (const fs::path& p : corpusFiles()) {
    files.insert(p.filename().string());
    bytes += fs::file_size(p);
    EXPECT_TRUE(idx.count(p.filename().string())) << p << " is not in INDEX.tsv (rerun tools/make_hostile_corpus.py)";
  }
  for (const auto& [name, why] : idx) EXPECT_TRUE(files.count(name)) << name << " is in INDEX.tsv but missing";
  EXPECT_LT(bytes, 2u << 20);
}

// Paths that are not regular files.
TEST(HostileCorpus, DirectoriesAndDevices) {
  const TempDir dir("sf_hostile_dirs");
  fs::create_directories(dir.path / "mesh.obj");
  fs::create_directories(dir.path / "cache.sfcache");
  expectRejected((dir.path / "mesh.obj").string(), [&] { readMesh((dir.path / "mesh.obj").string()); });
  expectRejected((dir.path / "cache.sfcache").string(), [&] { readPatchCache((dir.path / "cache.sfcache").string()); });
  expectRejected("/dev/null", [&] { readPatchCache("/dev/null"); });
  expectRejected((dir.path / "missing.ply").string(), [&] { readMesh((dir.path / "missing.ply").string()); });
}

// Inputs too large to commit: generated here, written, read back.
TEST(HostileCorpus, LargeGeneratedInputs) {
  const TempDir dir("sf_hostile_large");
  const auto write = [&](const std::string& name, const std::string& bytes) {
    const std::string p = (dir.path / name).string();
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  };
  // a 4 MB line, a face with 1M corners ending out of range, 200k tiny bad lines
  std::string s = "v " + std::string(4 << 20, '7') + " 0 0\n";
  std::string p = write("long_line.obj", s);
  expectRejected(p, [&] { readMesh(p); });
  s = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf";
  for (int i = 0; i < 1000000; ++i) s += " 1";
  s += " 4\n";
  p = write("million_corners.obj", s);
  expectRejected(p, [&] { readMesh(p); });
  s = "OFF\n3 200000 0\n0 0 0\n1 0 0\n0 1 0\n";
  for (int i = 0; i < 199999; ++i) s += "3 0 1 2\n";
  s += "3 0 1 3\n";
  p = write("many_faces_last_bad.off", s);
  expectRejected(p, [&] { readMesh(p); });
  // a binary PLY header claiming INT32_MAX-vertex lists in a 1 MB body of 0xff
  s = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list int int vertex_indices\nend_header\n" +
      std::string(36, '\0') + std::string(1 << 20, '\xff');
  p = write("ffff.ply", s);
  expectRejected(p, [&] { readMesh(p); });
}

}  // namespace
}  // namespace sf::hostile
