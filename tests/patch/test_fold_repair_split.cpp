// SPDX-License-Identifier: Apache-2.0
// The fold repair's split (polygon_split.h): over every shared mesh, the pieces of every cut
// polygon tile it (areas), keep its own corners and normals, and have no reflex or straight
// corner; faces left whole are untouched; on the planar non-convex meshes the repaired surface
// has no sampled fold and its patches certify; the cache keeps the pieces' sources (format 3)
// and a cache built without the repair is the one built before the option existed.
#include <gtest/gtest.h>

#include <unistd.h>
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>

#include <smoothforce/base/hash.h>
#include <smoothforce/mesh/polygon_split.h>
#include <smoothforce/patch/cache_file.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/patch/patch_certificate.h>
#include <smoothforce/patch/tangent_fans.h>
#include <smoothforce/query/patch_surface.h>
#include <smoothforce/query/surface_faults.h>
#include <nlohmann/json.hpp>

#include "cli_test_support.h"
#include "file_bytes.h"
#include "patch_test_support.h"
#include "shared_mesh_files.h"

namespace sf {
namespace {

/// The default construction (the fold repair on), named for the reader.
PatchOptions splitOptions() {
  PatchOptions o;
  o.foldRepair = FoldRepairMode::On;
  return o;
}

/// The design page's construction on the polygons as read.
PatchOptions offOptions() {
  PatchOptions o;
  o.foldRepair = FoldRepairMode::Off;
  return o;
}

/// Polygon area from the cross products of a fan about its first corner, projected on the unit
/// normal n (independent of the Newell vector the split uses).
double fanArea(const PolygonMesh& m, int f, const Eigen::Vector3d& n) {
  double a = 0;
  const Eigen::Vector3d p0 = m.positions[m.faceVertex(f, 0)];
  for (int k = 1; k + 1 < m.faceSize(f); ++k)
    a += 0.5 * (m.positions[m.faceVertex(f, k)] - p0).cross(m.positions[m.faceVertex(f, k + 1)] - p0).dot(n);
  return a;
}

TEST(FoldRepairSplit, PiecesTileTheirPolygonKeepItsCornersAndHaveNoBadCorner) {
  int meshes = 0, cut = 0, pieces = 0, whole = 0, wholeCompared = 0, wholeTurned = 0;
  std::map<std::string, int> cutPerMesh;
  for (const std::string& path : test::sharedMeshFiles()) {
    SCOPED_TRACE(path);
    const LoadedMesh before = loadMesh(path, offOptions());
    const LoadedMesh after = loadMesh(path, splitOptions());
    ++meshes;
    const PolygonMesh &a = before.mesh, &b = after.mesh;
    ASSERT_EQ(static_cast<int>(b.faceSource.size()), b.numFaces());
    ASSERT_EQ(b.positions, a.positions);  // no vertex added or moved
    ASSERT_EQ(static_cast<int>(after.cornerNormals.size()), b.numCorners());
    int g = 0;  // the first piece of face f
    for (int f = 0; f < a.numFaces(); ++f) {
      int h = g;
      while (h < b.numFaces() && b.faceSource[h] == f) ++h;
      ASSERT_GT(h, g) << "face " << f << " has no piece";
      const int first = a.faceOffsets[f];
      if (h == g + 1) {  // left whole: the same corners and normals
        ++whole;
        for (int k = 0; k < a.faceSize(f); ++k) {
          EXPECT_EQ(b.faceVertex(g, k), a.faceVertex(f, k));
          EXPECT_EQ(after.cornerNormals[b.faceOffsets[g] + k], before.cornerNormals[first + k]);
        }
        g = h;
        continue;
      }
      ++cut, ++cutPerMesh[std::filesystem::path(path).filename().string()];
      const Eigen::Vector3d n = newellNormal(a, f).normalized();
      double area = 0;
      std::vector<int> seen(a.faceSize(f), 0);
      for (int p = g; p < h; ++p) {
        ++pieces;
        area += fanArea(b, p, n);
        EXPECT_GT(fanArea(b, p, n), 0) << "piece " << p << " of face " << f << " turns the other way";
        for (double ang : planarCornerAngles(b, p))
          EXPECT_LT(ang, std::numbers::pi * (1 - kStraightCornerDeg / 180)) << "piece " << p << " of face " << f;
        for (int k = 0; k < b.faceSize(p); ++k) {
          int local = -1;  // the corner of face f it is
          for (int j = 0; j < a.faceSize(f); ++j)
            if (a.faceVertex(f, j) == b.faceVertex(p, k)) local = j;
          ASSERT_GE(local, 0) << "piece " << p << " has a corner face " << f << " lacks";
          ++seen[local];
          EXPECT_EQ(after.cornerNormals[b.faceOffsets[p] + k], before.cornerNormals[first + local]);
        }
      }
      for (int j = 0; j < a.faceSize(f); ++j) EXPECT_GT(seen[j], 0) << "corner " << j << " of face " << f << " lost";
      EXPECT_NEAR(area, fanArea(a, f, n), 1e-9 * std::fabs(fanArea(a, f, n))) << "face " << f;
      g = h;
    }
    EXPECT_EQ(g, b.numFaces());
    EXPECT_EQ(static_cast<int>(after.split.splitFaces.size()),
              cutPerMesh[std::filesystem::path(path).filename().string()]);
    // every face left whole keeps its patch records bit for bit (a mesh without a cut: all), but
    // for those at a tangled vertex fan, whose end tangents the repair turns (test_tangent_fans.cpp)
    const PatchCache off = buildPatchCache(before, offOptions(), Backend::Tbb);
    const PatchCache on = buildPatchCache(after, splitOptions(), Backend::Tbb);
    const size_t cOff = off.faceVertices.size(), cOn = on.faceVertices.size();
    for (int f = 0, p = 0; f < a.numFaces(); ++f) {
      int h = p;
      while (h < b.numFaces() && b.faceSource[h] == f) ++h;
      if (h == p + 1 && faceHasEdgeTangents(on, p)) {
        ++wholeTurned;
      } else if (h == p + 1) {
        ++wholeCompared;
        EXPECT_TRUE(test::sameStatusAsDesign(on.faceStatus[p], off.faceStatus[f]))
            << "face " << f << ": " << on.faceStatus[p] << " against " << off.faceStatus[f];
        for (int k = 0; k < a.faceSize(f); ++k)
          for (size_t i = 0; i < GP_E_NFIELDS; ++i)
            ASSERT_EQ(on.edgeDataD[i * cOn + on.faceOffsets[p] + k], off.edgeDataD[i * cOff + off.faceOffsets[f] + k])
                << "face " << f << " corner " << k << " field " << i;
      }
      p = h;
    }
  }
  EXPECT_EQ(wholeCompared + wholeTurned, whole);
  EXPECT_EQ(wholeTurned, 62);  // the spot cage's (test_tangent_fans.cpp)
  std::printf("fold repair split over %d meshes: %d faces cut into %d pieces, %d left whole\n", meshes, cut, pieces,
              whole);
  // the planar non-convex meshes: tetris 15 of 16 faces, L-plane all 16, pmp L its one hexagon;
  // no curved mesh is cut
  EXPECT_EQ(cutPerMesh["tetris.obj"], 15);
  EXPECT_EQ(cutPerMesh["L-plane.obj"], 16);
  EXPECT_EQ(cutPerMesh["L.off"], 1);
  EXPECT_EQ(cut, 32);
  EXPECT_GT(meshes, 20);
}

/// A flat star polygon in z = 0 with `points` tips (2 * points corners, reflex between tips).
PolygonMesh star(int points) {
  PolygonMesh m;
  for (int k = 0; k < 2 * points; ++k) {
    const double a = std::numbers::pi * k / points, r = k % 2 ? 0.4 : 1.0;
    m.positions.push_back({r * std::cos(a), r * std::sin(a), 0});
    m.faceVertices.push_back(k);
  }
  m.faceOffsets = {0, 2 * points};
  return m;
}

TEST(FoldRepairSplit, HostilePolygonsAreCutOrLeftWholeNeverBroken) {
  // stars up to kMaxSplitCorners corners are cut into pieces without a bad corner; larger ones,
  // a flat bow-tie and a polygon with a non-finite vertex are left whole and reported
  for (int points : {3, 8, 32, 33, 200}) {
    SCOPED_TRACE(points);
    PolygonMesh m = star(points);
    std::vector<Eigen::Vector3d> normals(m.numCorners(), Eigen::Vector3d::UnitZ());
    const PolygonSplitReport r = splitBadCorners(m, &normals);
    ASSERT_EQ(static_cast<int>(normals.size()), m.numCorners());
    if (2 * points <= kMaxSplitCorners) {
      EXPECT_EQ(r.splitFaces, std::vector<int>{0});
      EXPECT_TRUE(r.unsplitFaces.empty());
      EXPECT_EQ(r.pieces, m.numFaces());
      for (int f = 0; f < m.numFaces(); ++f)
        for (double ang : planarCornerAngles(m, f)) EXPECT_LT(ang, std::numbers::pi * (1 - kStraightCornerDeg / 180));
    } else {
      EXPECT_TRUE(r.splitFaces.empty());
      EXPECT_EQ(r.unsplitFaces, std::vector<int>{0});
      EXPECT_EQ(m.numFaces(), 1);
    }
  }
  PolygonMesh bow;  // its outline crosses itself: (0,0) (1,1) (1,0) (0,1)
  bow.positions = {{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}, {0.5, 2, 0}};
  bow.faceVertices = {0, 1, 4, 2, 3};
  bow.faceOffsets = {0, 5};
  PolygonSplitReport r = splitBadCorners(bow);
  EXPECT_TRUE(r.splitFaces.empty());
  EXPECT_EQ(bow.numFaces(), 1);
  PolygonMesh bad = star(4);
  bad.positions[3].x() = std::numeric_limits<double>::quiet_NaN();
  r = splitBadCorners(bad);
  EXPECT_TRUE(r.splitFaces.empty());
  EXPECT_EQ(bad.numFaces(), 1);
  EXPECT_EQ(bad.faceSource, std::vector<int32_t>{0});
}

TEST(FoldRepairSplit, PlanarNonConvexMeshesNeitherFoldNorTearAndCertify) {
  struct Case {
    const char* rel;
    int foldsBefore, certified, faces;  // with the repair: certified of faces
    bool certify;
  };
  const Case cases[] = {{"polygon_laplacian/tetris.obj", 11, 53, 53, true},
                        {"polygon_laplacian/L-plane.obj", 16, 40, 40, true},
                        {"pmp/L.off", 1, 2, 2, true}};
  for (const Case& cs : cases) {
    SCOPED_TRACE(cs.rel);
    const std::string path = test::sharedMesh(cs.rel);
    const PatchCache off = buildPatchCache(loadMesh(path, offOptions()), offOptions(), Backend::Tbb);
    PatchCache on = buildPatchCache(loadMesh(path, splitOptions()), splitOptions(), Backend::Tbb);
    int foldsOff = 0, foldsOn = 0;
    for (uint32_t st : off.faceStatus) foldsOff += (st & GP_ST_FOLD) != 0;
    for (uint32_t st : on.faceStatus) foldsOn += (st & GP_ST_FOLD) != 0;
    EXPECT_EQ(foldsOff, cs.foldsBefore);
    EXPECT_EQ(foldsOn, 0);
    // the cuts are shared edges like any other: no gap, and (flat) no angle between the patches
    const test::G1Stats g1 = test::measureG1(on, 1e-7);
    EXPECT_GT(g1.edges, 0);
    EXPECT_LT(g1.maxGap, 1e-6);
    EXPECT_LT(g1.maxAngle, 1e-6);
    if (!cs.certify) continue;
    certifyPatches(on);
    const CertificateSummary s = summarizeCertificates(on);
    std::printf("%s: %d sampled folds without the repair, %d with; certified %d of %d\n", cs.rel, foldsOff, foldsOn,
                s.certified, on.numFaces());
    EXPECT_EQ(on.numFaces(), cs.faces);
    EXPECT_EQ(s.certified, cs.certified);
    EXPECT_EQ(s.folded, 0);
  }
}

TEST(FoldRepairSplit, TheCacheKeepsThePiecesSourcesAndOffIsUnchanged) {
  const std::string path = test::sharedMesh("pmp/L.off");
  const auto dir = std::filesystem::temp_directory_path() / ("sf_fold_repair_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  PatchCache on = buildPatchCache(loadMesh(path, splitOptions()), splitOptions(), Backend::Tbb);
  writePatchCache(on, (dir / "on.sfcache").string());
  const PatchCache back = readPatchCache((dir / "on.sfcache").string());
  EXPECT_EQ(back.options.foldRepair, FoldRepairMode::On);
  EXPECT_EQ(back.faceSource, on.faceSource);
  EXPECT_EQ(back.faceVertices, on.faceVertices);
  EXPECT_EQ(back.edgeDataD, on.edgeDataD);
  EXPECT_EQ(test::fileBytes(dir / "on.sfcache").substr(8, 4), std::string("\x03\0\0\0", 4));  // format 3
  // with certificates too
  certifyPatches(on);
  writePatchCache(on, (dir / "on2.sfcache").string());
  const PatchCache back2 = readPatchCache((dir / "on2.sfcache").string());
  EXPECT_EQ(back2.faceCertificate, on.faceCertificate);
  EXPECT_EQ(back2.faceSource, on.faceSource);
  // off: the options hash is the one of caches written before the option existed, and so the
  // file is too (format 1, no sources)
  EXPECT_EQ(PatchOptions{}.foldRepair, FoldRepairMode::On);  // the default
  const PatchCache off = buildPatchCache(loadMesh(path, offOptions()), offOptions(), Backend::Tbb);
  EXPECT_TRUE(off.faceSource.empty());
  EXPECT_NE(hashPatchOptions(splitOptions()), hashPatchOptions(offOptions()));
  EXPECT_EQ(hashPatchOptions(offOptions()), 0x6e7e34f945976932ull);  // as written by earlier builds
  writePatchCache(off, (dir / "off.sfcache").string());
  EXPECT_EQ(test::fileBytes(dir / "off.sfcache").substr(8, 4), std::string("\x01\0\0\0", 4));
  // a cache of version 0.5, whose options hash named the repair "split", reads as on: the same
  // file with that hash in its header (offset 24) and the header checksum (offset 120) redone
  {
    std::string bytes = test::fileBytes(dir / "on.sfcache");
    const std::string legacy = "precision=double;cross-tangent=corrected;normals=auto;orient=outward;fields=" +
                               std::to_string(GP_E_NFIELDS) + ";fold-repair=split";
    const uint64_t h = hashBytes(legacy.data(), legacy.size());
    std::memcpy(bytes.data() + 24, &h, 8);
    const uint64_t sum = hashBytes(bytes.data(), 120);
    std::memcpy(bytes.data() + 120, &sum, 8);
    std::ofstream((dir / "legacy.sfcache").string(), std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
    const PatchCache old = readPatchCache((dir / "legacy.sfcache").string());
    EXPECT_EQ(old.options.foldRepair, FoldRepairMode::On);
    EXPECT_EQ(old.faceSource, on.faceSource);
    bytes[24] ^= 1;  // any other hash is still refused
    const uint64_t sum2 = hashBytes(bytes.data(), 120);
    std::memcpy(bytes.data() + 120, &sum2, 8);
    std::ofstream((dir / "bad.sfcache").string(), std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
    EXPECT_THROW(readPatchCache((dir / "bad.sfcache").string()), InputError);
  }
  // a reader that expects the repair refuses a cache built without it
  CacheExpectation e;
  e.options = splitOptions();
  EXPECT_THROW(readPatchCache((dir / "off.sfcache").string(), e), InputError);
  std::filesystem::remove_all(dir);
}

TEST(FoldRepairSplit, TheCommandLineBuildsReportsAndKeepsIt) {
  const auto dir = std::filesystem::temp_directory_path() / ("sf_fold_repair_cli_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string mesh = test::sharedMesh("pmp/L.off"), cache = (dir / "L.sfcache").string();
  test::CliResult r = test::smoothforce("cache build " + mesh + " --fold-repair split -o " + cache);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("fold repair: on: 1 flat polygon with a reflex or straight corner cut into 2 convex pieces"),
            std::string::npos)
      << r.out;
  r = test::smoothforce("cache info " + cache + " --json");
  ASSERT_EQ(r.status, 0) << r.out;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["format"], 3);
  EXPECT_EQ(j["options"]["fold_repair"], "on");
  EXPECT_EQ(j["fold_repair"]["cut"], nlohmann::json::parse(R"([{"face_as_read": 0, "faces": [0, 1]}])"));
  EXPECT_EQ(j["patches"]["folds"], 0);
  // the cache keeps its options; a bad value is a usage error with the shared message
  const std::string points = (dir / "points.csv").string();
  {
    std::FILE* f = std::fopen(points.c_str(), "w");
    std::fputs("face,xi,eta\n0,0,0\n", f);
    std::fclose(f);
  }
  r = test::smoothforce("eval " + cache + " --fold-repair off --points " + points + " -o -");
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_NE(r.out.find("built with --fold-repair on, but --fold-repair off was given"), std::string::npos) << r.out;
  // the synonym and the default name the cache's repair
  for (const char* same : {" --fold-repair split", " --fold-repair on", ""}) {
    r = test::smoothforce("eval " + cache + same + " --points " + points + " -o -");
    EXPECT_EQ(r.status, 0) << same << ": " << r.out;
  }
  r = test::smoothforce("cache build " + mesh + " --fold-repair sometimes -o " + cache);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("--fold-repair: expected off|on|search, got 'sometimes'"), std::string::npos) << r.out;
  // the default cuts the same pieces
  r = test::smoothforce("cache build " + mesh + " -o " + cache);
  ASSERT_EQ(r.status, 0) << r.out;
  r = test::smoothforce("cache info " + cache + " --json");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(nlohmann::json::parse(r.out)["fold_repair"]["cut"],
            nlohmann::json::parse(R"([{"face_as_read": 0, "faces": [0, 1]}])"));
  std::filesystem::remove_all(dir);
}

/// A closed prism over the counter-clockwise outline (x, y) in z = 0, height h: the outline as
/// its two caps (bottom reversed), a quad per side.
PolygonMesh extrude(const std::vector<std::array<double, 2>>& outline, double h) {
  PolygonMesh m;
  const int n = static_cast<int>(outline.size());
  for (double z : {0.0, h})
    for (const auto& p : outline) m.positions.push_back({p[0], p[1], z});
  m.faceOffsets = {0};
  auto face = [&](std::vector<int> v) {
    m.faceVertices.insert(m.faceVertices.end(), v.begin(), v.end());
    m.faceOffsets.push_back(static_cast<int32_t>(m.faceVertices.size()));
  };
  std::vector<int> bottom, top;
  for (int i = 0; i < n; ++i) bottom.push_back(n - 1 - i), top.push_back(n + i);
  face(bottom);
  face(top);
  for (int i = 0; i < n; ++i) face({i, (i + 1) % n, n + (i + 1) % n, n + i});
  return m;
}

TEST(FoldRepairSplit, ExtrudedNonConvexPartsAreFaultFreeByDefault) {
  // CAD-like parts: a non-convex outline extruded, read with averaged normals (the caps' corner
  // normals lean 45 degrees or more off their plane) and with its edges made creases (the caps
  // flat). The design page's construction folds both caps of every one; the default splits them
  // and the closed surface has no fault (winding numbers either side of every triangle), and,
  // creased, its area is the prism's.
  using Outline = std::vector<std::array<double, 2>>;
  auto polar = [](int corners, auto radius) {
    Outline o;
    for (int k = 0; k < corners; ++k) {
      const double a = 2 * std::numbers::pi * k / corners, r = radius(k);
      o.push_back({r * std::cos(a), r * std::sin(a)});
    }
    return o;
  };
  struct Part {
    const char* name;
    Outline outline;
    double height;
  };
  const Part parts[] = {
      {"L", {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 3}, {0, 3}}, 1.0},
      {"plus", {{1, 0}, {2, 0}, {2, 1}, {3, 1}, {3, 2}, {2, 2}, {2, 3}, {1, 3}, {1, 2}, {0, 2}, {0, 1}, {1, 1}}, 1.0},
      {"U", {{0, 0}, {3, 0}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}}, 1.0},
      {"T", {{0, 2}, {1, 2}, {1, 0}, {2, 0}, {2, 2}, {3, 2}, {3, 3}, {0, 3}}, 0.5},
      {"star", polar(10, [](int k) { return k % 2 ? 0.45 : 1.0; }), 0.4},
      {"notched disc", polar(32, [](int k) { return (k / 2) % 2 ? 0.8 : 1.0; }), 0.3},
  };
  int cases = 0, foldedCapsOff = 0, faultyOff = 0, capsCut = 0;
  for (const Part& part : parts) {
    for (double creaseDeg : {0.0, 30.0}) {
      SCOPED_TRACE(std::string(part.name) + " crease angle " + std::to_string(creaseDeg));
      ++cases;
      const PolygonMesh mesh = extrude(part.outline, part.height);
      PatchOptions off = offOptions(), on = PatchOptions{};
      off.creases.angleDeg = on.creases.angleDeg = creaseDeg;
      const PatchCache before = buildPatchCache(loadMesh(mesh, 1, off), off, Backend::Tbb);
      const LoadedMesh cut = loadMesh(mesh, 1, on);
      const PatchCache after = buildPatchCache(cut, on, Backend::Tbb);
      capsCut += static_cast<int>(cut.split.splitFaces.size());
      EXPECT_EQ(cut.split.splitFaces, (std::vector<int>{0, 1}));
      for (int f = 0; f < 2; ++f) foldedCapsOff += (before.faceStatus[f] & GP_ST_FOLD) != 0;
      for (uint32_t st : after.faceStatus) EXPECT_EQ(st & GP_ST_FOLD, 0u);
      const SurfaceFaults fOff = measureSurfaceFaults(PatchSurface(before));
      const SurfaceFaults fOn = measureSurfaceFaults(PatchSurface(after));
      ASSERT_TRUE(fOff.closed && fOn.closed);
      faultyOff += fOff.faultArea() > 0;
      EXPECT_EQ(fOn.faultArea(), 0.0) << "fault faces " << ::testing::PrintToString(fOn.faultFaces());
      std::printf("%s, crease angle %g: fault area %.4f%% -> %.4f%%\n", part.name, creaseDeg,
                  100 * fOff.faultArea() / fOff.totalArea, 100 * fOn.faultArea() / fOn.totalArea);
      if (creaseDeg > 0) {  // every patch flat: the surface is the prism
        double area2 = 0, perimeter = 0;
        const Outline& o = part.outline;
        for (size_t i = 0; i < o.size(); ++i) {
          const auto &p = o[i], &q = o[(i + 1) % o.size()];
          area2 += p[0] * q[1] - q[0] * p[1];
          perimeter += std::hypot(q[0] - p[0], q[1] - p[1]);
        }
        const double exact = std::fabs(area2) + perimeter * part.height;
        EXPECT_NEAR(fOn.totalArea, exact, 1e-9 * exact);
      }
    }
  }
  EXPECT_EQ(cases, 12);
  EXPECT_EQ(capsCut, 24);
  EXPECT_EQ(foldedCapsOff, 24);  // sampled folds of the design page's construction
  EXPECT_EQ(faultyOff, 11);      // the notched disc with averaged normals folds without overlapping
}

}  // namespace
}  // namespace sf
