// SPDX-License-Identifier: Apache-2.0
// checkMesh, flipFaces and applyOrientation: the shared mesh catalogue (every file loads
// and matches /work/shared/meshes/README.md), plus small hand-made topologies.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>
#include <random>
#include <set>

#include <smoothforce/mesh/mesh_check.h>
#include <smoothforce/mesh/mesh_io.h>
#include <smoothforce/mesh/seams.h>
#include "polygon_mesh_support.h"
#include "shared_mesh_files.h"

namespace {

/// One row of the catalogue in shared/meshes/README.md.
struct Entry {
  const char* file;
  int V, F;
  std::map<int, int> sizes;  ///< face-size histogram
  int loops;                 ///< boundary loops; 0 = closed, -1 = open, count not catalogued
  int genus;                 ///< for closed connected manifolds, else -1
  int nonManifoldEdges = 0, duplicates = 0, unreferenced = 0;
  bool negativeVolume = false;
};

const Entry kCatalogue[] = {
    {"keenan_crane/spot_control_mesh.obj", 188, 180, {{3, 4}, {4, 160}, {5, 16}}, 0, 0},
    {"keenan_crane/spot_quadrangulated.obj", 2930, 2928, {{4, 2928}}, 0, 0},
    {"keenan_crane/spot_triangulated.obj", 2930, 5856, {{3, 5856}}, 0, 0},
    {"keenan_crane/bob_tri.obj", 5344, 10688, {{3, 10688}}, 0, 1},
    {"keenan_crane/semi2.obj", 4232, 2025, {{4, 1012}, {8, 1013}}, 1, -1},
    {"keenan_crane/semi6.obj", 4512, 2071, {{3, 1350}, {12, 721}}, 1, -1},
    {"odedstein/spot_low_resolution.obj", 829, 1654, {{3, 1654}}, 0, 0},
    {"odedstein/spot.obj", 11533, 23062, {{3, 23062}}, 0, 0},
    {"odedstein/bunny.obj", 3301, 6598, {{3, 6598}}, 0, 0},
    {"odedstein/bunny_hr.obj", 29834, 59664, {{3, 59664}}, 0, 0},
    {"odedstein/armadillo.obj", 14587, 29170, {{3, 29170}}, 0, 0},
    {"odedstein/torus.obj", 2304, 4608, {{3, 4608}}, 0, 1},
    {"odedstein/sphere.obj", 642, 1280, {{3, 1280}}, 0, 0},
    {"polygon_laplacian/hexaSphere.off", 1760, 882, {{5, 128}, {6, 638}, {7, 116}}, 0, 0},
    {"polygon_laplacian/tetris.obj", 52, 16, {{4, 1}, {5, 1}, {6, 3}, {7, 2}, {8, 5}, {9, 3}, {10, 1}}, 1, -1},
    {"polygon_laplacian/L-plane.obj", 45, 16, {{6, 8}, {7, 8}}, 1, -1},
    {"polygon_laplacian/quad-sphere.off", 482, 512, {{3, 64}, {4, 448}}, 0, 0},
    {"polygon_laplacian/sphere2.off", 3842, 3840, {{4, 3840}}, 0, 0, 0, 0, 0, true},
    {"pmp/chamfer-cube.off", 24, 26, {{3, 8}, {4, 18}}, 0, 0},
    {"pmp/hole_capsule.off", 89, 76, {{4, 76}}, 3, -1},
    {"pmp/L.off", 6, 1, {{6, 1}}, 1, -1},
    {"lagrange/catmark_fvar_bound1.obj", 25, 16, {{4, 16}}, 1, -1},
    {"lagrange/cube.obj", 8, 6, {{4, 6}}, 0, 0},
    {"stanford/bun_zipper_res4.ply", 453, 948, {{3, 948}}, -1, -1, 70, 40, 0},
    {"stanford/bun_zipper_res3.ply", 1889, 3851, {{3, 3851}}, -1, -1, 141, 83, 2},
    {"stanford/bun_zipper_res2.ply", 8171, 16301, {{3, 16301}}, -1, -1, 150, 87, 25},
    {"stanford/bun_zipper.ply", 35947, 69451, {{3, 69451}}, 5, -1, 0, 0, 1113},
    {"geomview/dodecahedron.off", 20, 12, {{5, 12}}, 0, 0},
    {"geomview/snub_dodecahedron.off", 60, 92, {{3, 80}, {5, 12}}, 0, 0},
};

using sf::test::cubeMesh;
using sf::test::polygonMesh;
using sf::test::sharedMesh;

}  // namespace

TEST(MeshCatalogue, EveryFileLoadsAndMatchesTheTable) {
  std::set<std::string> listed;
  for (const Entry& e : kCatalogue) {
    SCOPED_TRACE(e.file);
    listed.insert(e.file);
    const sf::PolygonMesh m = sf::readMesh(sharedMesh(e.file));
    const sf::MeshReport r = sf::checkMesh(m);
    EXPECT_EQ(r.numVertices, e.V);
    EXPECT_EQ(r.numFaces, e.F);
    std::map<int, int> sizes;
    for (size_t n = 0; n < r.faceSizeHistogram.size(); ++n)
      if (r.faceSizeHistogram[n]) sizes[static_cast<int>(n)] = r.faceSizeHistogram[n];
    EXPECT_EQ(sizes, e.sizes);
    if (e.loops >= 0) {
      EXPECT_EQ(r.boundaryLoops.size(), static_cast<size_t>(e.loops));
    }
    EXPECT_EQ(r.closed(), e.loops == 0);
    EXPECT_EQ(r.nonManifoldEdges.size(), static_cast<size_t>(e.nonManifoldEdges));
    EXPECT_EQ(r.duplicateFaces.size(), static_cast<size_t>(e.duplicates));
    EXPECT_EQ(r.unreferencedVertices.size(), static_cast<size_t>(e.unreferenced));
    EXPECT_TRUE(r.degenerateFaces.empty());
    EXPECT_TRUE(r.inconsistentEdges.empty());
    const bool manifold = e.nonManifoldEdges == 0;
    if (manifold) {
      EXPECT_TRUE(r.nonManifoldVertices.empty());
      EXPECT_EQ(r.numComponents, 1);
      EXPECT_TRUE(r.clean() || e.unreferenced > 0);
    } else {
      EXPECT_FALSE(r.nonManifoldVertices.empty());
      EXPECT_FALSE(r.clean());
    }
    if (e.genus >= 0) {
      const int chi = r.numVertices - static_cast<int>(r.unreferencedVertices.size()) - r.numEdges + r.numFaces;
      EXPECT_EQ(chi, 2 - 2 * e.genus);
      EXPECT_EQ(r.signedVolume < 0, e.negativeVolume);
    }
  }
  for (const auto& dir : std::filesystem::directory_iterator(SF_SHARED_MESHES)) {
    if (!dir.is_directory()) continue;
    for (const auto& f : std::filesystem::directory_iterator(dir.path())) {
      const std::string rel = dir.path().filename().string() + "/" + f.path().filename().string();
      EXPECT_TRUE(listed.count(rel)) << rel << " is not in the test's catalogue";
    }
  }
  EXPECT_EQ(listed.size(), 29u);
}

TEST(MeshCatalogue, DescribeNamesTheProblems) {
  const sf::MeshReport r = sf::checkMesh(sf::readMesh(sharedMesh("stanford/bun_zipper_res4.ply")));
  std::string all;
  for (const std::string& line : r.describe(3)) all += line + "\n";
  EXPECT_NE(all.find("non-manifold edges: 70 (first: "), std::string::npos) << all;
  EXPECT_NE(all.find("duplicate faces: 40 (first: "), std::string::npos) << all;
  EXPECT_NE(all.find("face sizes: 948 tri"), std::string::npos) << all;
  const sf::MeshReport c = sf::checkMesh(cubeMesh());
  all.clear();
  for (const std::string& line : c.describe()) all += line + "\n";
  EXPECT_NE(all.find("genus 0"), std::string::npos) << all;
  EXPECT_EQ(all.find("non-manifold"), std::string::npos) << all;
}

TEST(MeshOrientation, Sphere2IsFlippedOutward) {
  sf::PolygonMesh m = sf::readMesh(sharedMesh("polygon_laplacian/sphere2.off"));
  const sf::MeshReport r = sf::checkMesh(m);
  ASSERT_LT(r.signedVolume, 0);
  sf::PolygonMesh kept = m;
  EXPECT_FALSE(sf::applyOrientation(kept, r, sf::OrientPolicy::Keep));
  EXPECT_EQ(kept.faceVertices, m.faceVertices);
  EXPECT_TRUE(sf::applyOrientation(m, r, sf::OrientPolicy::Outward));
  const sf::MeshReport after = sf::checkMesh(m);
  EXPECT_NEAR(after.signedVolume, -r.signedVolume, 1e-12);
  EXPECT_TRUE(after.inconsistentEdges.empty());
  EXPECT_FALSE(sf::applyOrientation(m, after, sf::OrientPolicy::Outward));
}

TEST(MeshOrientation, FlipKeepsFirstCornerAndReordersCornerNormals) {
  sf::PolygonMesh m = polygonMesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}}, {{0, 1, 2, 3}, {1, 4, 2}});
  for (int c = 0; c < m.numCorners(); ++c) m.fileCornerNormals.emplace_back(c, 0, 0);
  const sf::PolygonMesh original = m;
  sf::flipFaces(m);
  EXPECT_EQ(m.faceVertices, (std::vector<int32_t>{0, 3, 2, 1, 1, 2, 4}));
  const std::vector<double> xs = {0, 3, 2, 1, 4, 6, 5};
  for (int c = 0; c < m.numCorners(); ++c) EXPECT_EQ(m.fileCornerNormals[c].x(), xs[c]);
  sf::flipFaces(m);
  EXPECT_EQ(m.faceVertices, original.faceVertices);
  EXPECT_EQ(m.fileCornerNormals, original.fileCornerNormals);
}

TEST(MeshOrientation, OnlyClosedConsistentInwardMeshesFlip) {
  sf::PolygonMesh c = cubeMesh();
  sf::MeshReport r = sf::checkMesh(c);
  EXPECT_TRUE(r.clean());
  EXPECT_TRUE(r.closed());
  EXPECT_NEAR(r.signedVolume, 8, 1e-12);
  EXPECT_FALSE(sf::applyOrientation(c, r, sf::OrientPolicy::Outward));  // already outward
  sf::flipFaces(c);
  r = sf::checkMesh(c);
  EXPECT_NEAR(r.signedVolume, -8, 1e-12);
  EXPECT_TRUE(sf::applyOrientation(c, r, sf::OrientPolicy::Outward));
  EXPECT_NEAR(sf::checkMesh(c).signedVolume, 8, 1e-12);

  // One face of six turned the wrong way: closed, 4 of 12 edges inconsistent (over 10%), not flipped.
  sf::PolygonMesh bad = cubeMesh();
  std::reverse(bad.faceVertices.begin() + 1, bad.faceVertices.begin() + 4);
  sf::flipFaces(bad);
  r = sf::checkMesh(bad);
  EXPECT_EQ(r.inconsistentEdges.size(), 4u);
  EXPECT_FALSE(sf::applyOrientation(bad, r, sf::OrientPolicy::Outward));

  // Open and inward-facing: not flipped either.
  sf::PolygonMesh open = polygonMesh({{0, 0, 0}, {0, 1, 0}, {1, 0, 0}}, {{0, 1, 2}});
  open.positions[0].z() = 1;
  r = sf::checkMesh(open);
  ASSERT_LT(r.signedVolume, 0);
  EXPECT_FALSE(sf::applyOrientation(open, r, sf::OrientPolicy::Outward));
}

// The spot cage turned inward with one face left as it was, for every face in turn (180 meshes):
// 2-5 of 360 edges inconsistent, the volume the majority's: flipped, so that every face but the
// one out of line points outward again (before, such a mesh stayed inside out).
TEST(MeshOrientation, AnInwardMeshWithOneFaceOutOfLineIsFlipped) {
  const sf::PolygonMesh home = sf::readMesh(sharedMesh("keenan_crane/spot_control_mesh.obj"));
  sf::PolygonMesh inward = home;
  sf::flipFaces(inward);
  int flipped = 0;
  for (int f = 0; f < home.numFaces(); ++f) {
    sf::PolygonMesh m = inward;
    std::copy(home.faceVertices.begin() + home.faceOffsets[f], home.faceVertices.begin() + home.faceOffsets[f + 1],
              m.faceVertices.begin() + m.faceOffsets[f]);
    const sf::MeshReport r = sf::checkMesh(m);
    ASSERT_FALSE(r.inconsistentEdges.empty()) << f;
    ASSERT_LT(r.signedVolume, 0) << f;
    ASSERT_TRUE(sf::applyOrientation(m, r, sf::OrientPolicy::Outward)) << f;
    for (int g = 0; g < m.numFaces(); ++g) {
      const bool same = std::equal(m.faceVertices.begin() + m.faceOffsets[g], m.faceVertices.begin() + m.faceOffsets[g + 1],
                                   home.faceVertices.begin() + home.faceOffsets[g]);
      EXPECT_EQ(same, g != f) << f << " " << g;
    }
    EXPECT_GT(sf::checkMesh(m).signedVolume, 0) << f;
    ++flipped;
  }
  EXPECT_EQ(flipped, 180);
}

// Every shared mesh with a tenth of its faces turned against their neighbours (seeded): after
// orientCoherently no edge of two faces runs the same way twice, and on every mesh of one
// component the faces turned back are exactly those turned, so the mesh is the one read.
TEST(MeshOrientation, FacesTurnedAgainstTheirNeighboursAreTurnedBackOnEverySharedMesh) {
  std::mt19937 rng(11);
  int meshes = 0, restored = 0;
  long turned = 0;
  for (const std::string& path : sf::test::sharedMeshFiles()) {
    SCOPED_TRACE(path);
    const sf::PolygonMesh read = sf::readMesh(path);
    const sf::MeshReport r = sf::checkMesh(read, {false});
    ASSERT_TRUE(r.inconsistentEdges.empty());
    sf::PolygonMesh m = read;
    std::vector<int> flipped;
    for (int f = 0; f < m.numFaces(); ++f) {
      if (rng() % 10 != 0) continue;
      flipped.push_back(f);
      std::reverse(m.faceVertices.begin() + m.faceOffsets[f] + 1, m.faceVertices.begin() + m.faceOffsets[f + 1]);
    }
    const size_t inconsistent = sf::checkMesh(m, {false}).inconsistentEdges.size();
    const sf::OrientationRepair o = sf::orientCoherently(m);
    EXPECT_TRUE(o.unorientableFaces.empty());
    EXPECT_TRUE(sf::checkMesh(m, {false}).inconsistentEdges.empty());
    // each face is as read or reversed (its first corner kept)
    for (int f = 0; f < m.numFaces(); ++f) {
      const auto b = m.faceVertices.begin() + m.faceOffsets[f], e = m.faceVertices.begin() + m.faceOffsets[f + 1];
      const auto rb = read.faceVertices.begin() + read.faceOffsets[f];
      std::vector<int32_t> rev(rb, rb + (e - b));
      if (rev.size() > 1) std::reverse(rev.begin() + 1, rev.end());
      EXPECT_TRUE(std::equal(b, e, rb) || std::equal(b, e, rev.begin())) << f;
    }
    if (r.numComponents == 1 && r.nonManifoldEdges.empty() && read.numFaces() >= 4) {
      EXPECT_EQ(o.turnedFaces, flipped);
      EXPECT_EQ(m.faceVertices, read.faceVertices);
      restored += m.faceVertices == read.faceVertices;
    }
    if (!flipped.empty()) EXPECT_GT(inconsistent, 0u);
    turned += static_cast<long>(o.turnedFaces.size());
    ++meshes;
  }
  std::printf("%d meshes, %ld faces turned back, %d of one component restored as read\n", meshes, turned, restored);
  EXPECT_EQ(meshes, 28);
  EXPECT_GE(restored, 20);
}

// A Moebius strip of 8 quads: no orientation agrees across its twisted edge, so it is left as
// read and named; a cube with one face turned is turned back (the face, and only it).
TEST(MeshOrientation, AMoebiusStripIsLeftAsReadAndACubesTurnedFaceIsTurnedBack) {
  std::vector<Eigen::Vector3d> p;
  const int n = 8;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * std::numbers::pi * i / n, h = t / 2;
    const Eigen::Vector3d c(std::cos(t), std::sin(t), 0),
        d(std::cos(h) * std::cos(t), std::cos(h) * std::sin(t), std::sin(h));
    p.push_back(c - 0.3 * d);
    p.push_back(c + 0.3 * d);
  }
  std::vector<std::vector<int32_t>> faces;
  for (int i = 0; i + 1 < n; ++i) faces.push_back({2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1});
  faces.push_back({2 * (n - 1), 1, 0, 2 * (n - 1) + 1});  // the twist: the ends meet swapped
  sf::PolygonMesh strip = polygonMesh(p, faces);
  const sf::PolygonMesh asRead = strip;
  const sf::OrientationRepair o = sf::orientCoherently(strip);
  EXPECT_EQ(o.unorientableFaces, (std::vector<int>{0}));
  EXPECT_TRUE(o.turnedFaces.empty());
  EXPECT_EQ(strip.faceVertices, asRead.faceVertices);
  ASSERT_EQ(o.describe().size(), 1u);
  EXPECT_NE(o.describe()[0].find("left as read"), std::string::npos);

  for (int f = 0; f < 6; ++f) {
    sf::PolygonMesh cube = cubeMesh();
    std::reverse(cube.faceVertices.begin() + cube.faceOffsets[f] + 1,
                 cube.faceVertices.begin() + cube.faceOffsets[f + 1]);
    for (int c = 0; c < cube.numCorners(); ++c) cube.fileCornerNormals.emplace_back(c, 0, 0);
    const sf::PolygonMesh turnedCube = cube;
    const sf::OrientationRepair back = sf::orientCoherently(cube);
    EXPECT_EQ(back.turnedFaces, (std::vector<int>{f}));
    EXPECT_EQ(cube.faceVertices, cubeMesh().faceVertices);
    // the corner normals turn with their corners
    for (int c = cube.faceOffsets[f]; c < cube.faceOffsets[f + 1]; ++c) {
      const int k = c - cube.faceOffsets[f], n4 = cube.faceSize(f);
      EXPECT_EQ(cube.fileCornerNormals[c], turnedCube.fileCornerNormals[cube.faceOffsets[f] + (n4 - k) % n4]);
    }
    EXPECT_TRUE(sf::checkMesh(cube).clean());
  }
}

TEST(MeshCheck, NonManifoldEdgesAndVertices) {
  const std::vector<Eigen::Vector3d> p = {{0, 0, 0}, {1, 0, 0},  {0, 1, 0}, {0, -1, 0},
                                          {0, 0, 1}, {-1, 0, 0}, {0, 0, -1}};
  const sf::MeshReport fin = sf::checkMesh(polygonMesh(p, {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}));
  EXPECT_EQ(fin.nonManifoldEdges, (std::vector<std::array<int, 2>>{{0, 1}}));
  EXPECT_EQ(fin.numEdges, 7);
  EXPECT_EQ(fin.numComponents, 1);
  EXPECT_FALSE(fin.closed());
  const sf::MeshReport bowtie = sf::checkMesh(polygonMesh(p, {{0, 1, 2}, {0, 5, 6}}));
  EXPECT_EQ(bowtie.nonManifoldVertices, (std::vector<int>{0}));
  EXPECT_TRUE(bowtie.nonManifoldEdges.empty());
  EXPECT_EQ(bowtie.numComponents, 2);
  EXPECT_EQ(bowtie.boundaryLoops.size(), 2u);
  EXPECT_EQ(bowtie.unreferencedVertices, (std::vector<int>{3, 4}));
}

TEST(MeshCheck, DuplicateAndDegenerateFaces) {
  const std::vector<Eigen::Vector3d> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {2, 0, 0}, {1, 1, 0}};
  const sf::MeshReport r = sf::checkMesh(polygonMesh(p, {{0, 1, 2},     // fine
                                                  {2, 0, 1},     // duplicate (rotated)
                                                  {0, 2, 1},     // duplicate (reversed)
                                                  {0, 1, 1},     // repeated vertex
                                                  {0, 1, 3, 5},  // zero-length edge 1-3
                                                  {0, 1, 4}}));  // collinear: zero area
  EXPECT_EQ(r.duplicateFaces, (std::vector<int>{1, 2}));
  EXPECT_EQ(r.degenerateFaces, (std::vector<int>{3, 4, 5}));
  EXPECT_FALSE(r.clean());
}

TEST(MeshCheck, BoundaryLoopFollowsFaceDirection) {
  std::vector<Eigen::Vector3d> p;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) p.emplace_back(i, j, 0);
  const sf::MeshReport r = sf::checkMesh(polygonMesh(p, {{0, 1, 4, 3}, {1, 2, 5, 4}, {3, 4, 7, 6}, {4, 5, 8, 7}}));
  ASSERT_EQ(r.boundaryLoops.size(), 1u);
  std::vector<int> loop = r.boundaryLoops[0];
  std::rotate(loop.begin(), std::find(loop.begin(), loop.end(), 0), loop.end());
  EXPECT_EQ(loop, (std::vector<int>{0, 1, 2, 5, 8, 7, 6, 3}));
  EXPECT_EQ(r.numEdges, 12);
  EXPECT_DOUBLE_EQ(r.signedVolume, 0);
}

TEST(MeshCheck, RandomSoupsTerminateAndCountEveryEdgeOnce) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const int nv = 3 + static_cast<int>(rng() % 12);
    std::vector<Eigen::Vector3d> p(nv);
    for (auto& q : p) q = Eigen::Vector3d(rng() % 3, rng() % 3, rng() % 3);
    sf::PolygonMesh m = polygonMesh(p, {});
    const int nf = 1 + static_cast<int>(rng() % 20);
    for (int f = 0; f < nf; ++f) {
      std::vector<int32_t> face(3 + rng() % 3);
      for (auto& v : face) v = static_cast<int32_t>(rng() % nv);
      m.addFace(face);
    }
    const sf::MeshReport r = sf::checkMesh(m);
    {  // the load-time repairs terminate on any soup and keep the faces' sizes
      sf::PolygonMesh repaired = m;
      sf::stitchSeams(repaired);
      sf::orientCoherently(repaired);
      ASSERT_EQ(repaired.faceOffsets, m.faceOffsets);
    }
    std::set<std::pair<int, int>> edges;
    for (int f = 0; f < m.numFaces(); ++f)
      for (int k = 0; k < m.faceSize(f); ++k) {
        const int a = m.faceVertex(f, k), b = m.faceVertex(f, k + 1);
        if (a != b) edges.insert({std::min(a, b), std::max(a, b)});
      }
    ASSERT_EQ(r.numEdges, static_cast<int>(edges.size()));
    size_t loopVertices = 0;
    for (const auto& l : r.boundaryLoops) loopVertices += l.size();
    EXPECT_LE(loopVertices, 2 * edges.size());
  }
}

TEST(MeshCheck, ShortFacesAreDegenerateAndBadIndicesThrow) {
  sf::PolygonMesh m = polygonMesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 1}, {2}, {}});
  const sf::MeshReport r = sf::checkMesh(m);
  EXPECT_EQ(r.degenerateFaces, (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(r.faceSizeHistogram, (std::vector<int>{1, 1, 1, 1}));
  m.faceVertices[1] = 7;
  m.sourcePath = "made.obj";
  try {
    sf::checkMesh(m);
    ADD_FAILURE() << "no InputError";
  } catch (const sf::InputError& e) {
    EXPECT_STREQ(e.what(), "made.obj: face 0: vertex index 7 out of range");
  }
}
