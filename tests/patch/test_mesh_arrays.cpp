// SPDX-License-Identifier: Apache-2.0
// In-memory input: a mesh given as arrays builds the same cache, byte for
// byte, as the file it came from, and every bad-input class gets its error naming the field.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <functional>
#include <iterator>
#include <limits>

#include <smoothforce/base/hash.h>
#include <smoothforce/mesh/mesh_io.h>
#include <smoothforce/patch/cache_file.h>
#include <smoothforce/patch/mesh_arrays.h>
#include "patch_test_support.h"
#include "file_bytes.h"

namespace sf::test {
namespace {

namespace fs = std::filesystem;

/// Flat arrays of a mesh as read from a file (what a caller would hand over).
struct Flat {
  std::vector<double> positions, normals;
  std::vector<int32_t> offsets, vertices;
  NormalLayout layout = NormalLayout::Auto;
  MeshArrays view(const std::string& name) const {
    MeshArrays a;
    a.positions = positions.data();
    a.numVertices = positions.size() / 3;
    a.faceOffsets = offsets.data();
    a.numFaces = offsets.size() - 1;
    a.faceVertices = vertices.data();
    a.normals = normals.empty() ? nullptr : normals.data();
    a.numNormals = normals.size() / 3;
    a.normalLayout = layout;
    a.name = name;
    return a;
  }
};

Flat flatten(const PolygonMesh& m) {
  Flat f;
  for (const auto& p : m.positions) f.positions.insert(f.positions.end(), {p.x(), p.y(), p.z()});
  f.offsets = m.faceOffsets;
  f.vertices = m.faceVertices;
  const auto& n = m.fileCornerNormals.empty() ? m.fileNormals : m.fileCornerNormals;
  for (const auto& v : n) f.normals.insert(f.normals.end(), {v.x(), v.y(), v.z()});
  f.layout = m.fileCornerNormals.empty() ? NormalLayout::PerVertex : NormalLayout::PerCorner;
  return f;
}


std::string cacheBytes(const LoadedMesh& lm, const PatchOptions& o, const std::string& path) {
  writePatchCache(buildPatchCache(lm, o, Backend::Tbb), path);
  return sf::test::fileBytes(path);
}

/// Every mesh file that reads: tests/data (most are malformed on purpose; those that read
/// count), data/, and ../shared/meshes up to 1 MB.
std::vector<std::string> meshFiles() {
  std::vector<std::string> out;
  for (const std::string& root : {std::string(SF_TEST_DATA), std::string(SF_DATA_DIR), std::string(SF_SHARED_MESHES)})
    for (const auto& e : fs::recursive_directory_iterator(root)) {
      const std::string ext = e.path().extension().string();
      if (!e.is_regular_file() || (ext != ".obj" && ext != ".off" && ext != ".ply")) continue;
      if (root == SF_SHARED_MESHES && e.file_size() > (1u << 20)) continue;
      out.push_back(e.path().string());
    }
  std::sort(out.begin(), out.end());
  return out;
}

TEST(MeshArrays, SameCacheBytesAsTheFileForEveryMesh) {
  const fs::path dir = fs::temp_directory_path() / ("sf_mesh_arrays_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  int compared = 0, withNormals = 0, perCorner = 0, unreadable = 0, shared = 0;
  for (const std::string& path : meshFiles()) {
    PolygonMesh m;
    try {
      m = readMesh(path);
    } catch (const InputError&) {
      ++unreadable;  // a malformed file: no arrays to compare
      continue;
    }
    const Flat flat = flatten(m);
    const bool hasNormals = !flat.normals.empty();
    std::vector<NormalMode> modes{NormalMode::Auto};
    if (hasNormals) modes.push_back(NormalMode::File);
    for (NormalMode mode : modes) {
      PatchOptions o;
      o.normals = mode;
      LoadedMesh fromFile;
      try {
        fromFile = loadMesh(path, o);
      } catch (const InputError&) {  // the checks after reading (normals): the arrays must fail alike
        MeshArrays a = flat.view(path);
        EXPECT_THROW(loadMeshArrays(a, o), InputError) << path;
        continue;
      }
      MeshArrays a = flat.view(path);
      a.meshHash = hashFile(path);
      const LoadedMesh fromArrays = loadMeshArrays(a, o);
      EXPECT_EQ(fromFile.flipped, fromArrays.flipped) << path;
      EXPECT_EQ(fromFile.report.describe(), fromArrays.report.describe()) << path;
      EXPECT_EQ(fromFile.normalReport.describe(), fromArrays.normalReport.describe()) << path;
      const std::string fileBytes = cacheBytes(fromFile, o, (dir / "file.sfcache").string());
      const std::string arrayBytes = cacheBytes(fromArrays, o, (dir / "arrays.sfcache").string());
      ASSERT_GT(fileBytes.size(), 128u) << path;
      EXPECT_TRUE(fileBytes == arrayBytes) << path << " (" << toString(mode) << ")";
      ++compared;
      withNormals += hasNormals;
      perCorner += flat.layout == NormalLayout::PerCorner && hasNormals;
      shared += path.rfind(SF_SHARED_MESHES, 0) == 0;
    }
  }
  fs::remove_all(dir);
  // 26 shared meshes up to 1 MB, the bundled spot cage and the hostile files that read.
  EXPECT_GE(compared, 30);
  EXPECT_GE(shared, 24);
  EXPECT_GE(withNormals, 4);
  EXPECT_GE(perCorner, 2);
  EXPECT_GE(unreadable, 50);
  std::printf(
      "compared %d caches (%d from ../shared/meshes, %d with file normals, %d per corner); %d unreadable files\n",
      compared, shared, withNormals, perCorner, unreadable);
}

TEST(MeshArrays, DefaultHashIsTheArraysContent) {
  const Flat flat = flatten(readMesh(std::string(SF_DATA_DIR) + "/spot_control_mesh.obj"));
  const MeshArrays a = flat.view("spot");
  const LoadedMesh lm = loadMeshArrays(a, {});
  EXPECT_EQ(lm.fileHash, meshArraysHash(a));
  Flat moved = flat;
  moved.positions[7] += 1e-9;
  EXPECT_NE(meshArraysHash(moved.view("spot")), lm.fileHash);
  EXPECT_EQ(lm.mesh.sourcePath, "spot");
}

/// A unit cube of 6 quads, outward.
Flat cube() {
  Flat f;
  f.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
  f.vertices = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};
  f.offsets = {0, 4, 8, 12, 16, 20, 24};
  return f;
}

std::string errorOf(const Flat& f, NormalMode mode = NormalMode::Auto) {
  PatchOptions o;
  o.normals = mode;
  try {
    loadMeshArrays(f.view("cube"), o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(MeshArrays, EveryBadInputClassNamesTheFieldAndElement) {
  EXPECT_EQ(errorOf(cube()), "");
  struct Case {
    const char* what;
    std::function<void(Flat&)> spoil;
    const char* message;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Case> cases{
      {"NaN position", [&](Flat& f) { f.positions[3 * 5 + 1] = nan; },
       "cube: positions[5][1] (vertex 5): non-finite value nan"},
      {"infinite position", [](Flat& f) { f.positions[0] = std::numeric_limits<double>::infinity(); },
       "cube: positions[0][0] (vertex 0): non-finite value inf"},
      {"index too large", [](Flat& f) { f.vertices[9] = 8; },
       "cube: faceVertices[9] (face 2, corner 1): vertex index 8 out of range [0, 8)"},
      {"negative index", [](Flat& f) { f.vertices[23] = -1; },
       "cube: faceVertices[23] (face 5, corner 3): vertex index -1 out of range [0, 8)"},
      {"two-corner face", [](Flat& f) { f.offsets[3] = 10; },
       "cube: faceOffsets[3] (face 2): 2 corners (8 to 10); a face needs at least 3"},
      {"decreasing offsets", [](Flat& f) { f.offsets[2] = 2; },
       "cube: faceOffsets[2] (face 1): -2 corners (4 to 2); a face needs at least 3"},
      {"offsets not from 0", [](Flat& f) { f.offsets[0] = 1; }, "cube: faceOffsets[0]: 1 (must be 0)"},
      {"no faces", [](Flat& f) { f.offsets = {0}; }, "cube: no faces"},
      {"normal rows", [](Flat& f) { f.normals.assign(3 * 5, 1.0); },
       "cube: normals: 5 rows, expected 8 (one per vertex) or 24 (one per corner)"},
      {"normal layout", [](Flat& f) { f.normals.assign(3 * 8, 1.0), f.layout = NormalLayout::PerCorner; },
       "cube: normals: 8 rows, expected 24 (one per corner)"},
      {"NaN normal", [&](Flat& f) { f.normals.assign(3 * 24, 1.0), f.normals[3 * 13 + 2] = nan; },
       "cube: normals[13][2] (corner 13): non-finite value nan"},
  };
  int named = 0;
  for (const Case& c : cases) {
    Flat f = cube();
    c.spoil(f);
    EXPECT_EQ(errorOf(f), c.message) << c.what;
    named += errorOf(f) == c.message;
  }
  EXPECT_EQ(named, static_cast<int>(cases.size()));
  // A zero normal under --normals file: the normals check names the vertex (as for a file).
  Flat z = cube();
  z.normals.assign(3 * 8, 1.0);
  z.normals[3 * 6] = z.normals[3 * 6 + 1] = z.normals[3 * 6 + 2] = 0;
  EXPECT_NE(errorOf(z, NormalMode::File).find("vertex 6"), std::string::npos) << errorOf(z, NormalMode::File);
  // --normals file without normals: the file's message, naming the arrays.
  EXPECT_EQ(errorOf(cube(), NormalMode::File).rfind("cube", 0), 0u) << errorOf(cube(), NormalMode::File);
}

TEST(MeshArrays, TopologyProblemsAreReportedAsForAFile) {
  Flat f = cube();
  // Duplicate the first face and flip every face inward: the report lists the duplicate, and
  // the closed inward mesh is flipped back unless the orientation is kept.
  f.vertices.insert(f.vertices.end(), f.vertices.begin(), f.vertices.begin() + 4);
  f.offsets.push_back(28);
  const LoadedMesh lm = loadMeshArrays(f.view("cube"), {});
  EXPECT_EQ(lm.report.duplicateFaces.size(), 1u);
  Flat inward = cube();
  for (size_t i = 0; i + 4 <= inward.vertices.size(); i += 4)
    std::reverse(inward.vertices.begin() + i, inward.vertices.begin() + i + 4);
  EXPECT_TRUE(loadMeshArrays(inward.view("inward"), {}).flipped);
  PatchOptions keep;
  keep.keepOrientation = true;
  EXPECT_FALSE(loadMeshArrays(inward.view("inward"), keep).flipped);
}

}  // namespace
}  // namespace sf::test
