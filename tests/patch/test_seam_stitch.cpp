// SPDX-License-Identifier: Apache-2.0
// The load-time repairs of loadMesh. Seams written twice (stitchSeams, seams.h): every shared
// mesh written as a soup (each corner its own vertex, as a triangle soup or an exporter that
// splits every vertex writes it) joins back into the mesh as read, and builds its patches bit
// for bit; split per-vertex normals go to the corners; ambiguous and unsafe seams stay open.
// Faces against their neighbours (orientCoherently, mesh_check.h): turned back, the patches
// are those of the mesh as read; `--orient keep` keeps them.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <smoothforce/mesh/mesh_check.h>
#include <smoothforce/mesh/mesh_io.h>
#include <smoothforce/mesh/seams.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/patch/patch_build.h>
#include "polygon_mesh_support.h"
#include "shared_mesh_files.h"

namespace sf {
namespace {

/// `m` with every corner its own vertex (in corner order), per-vertex file normals carried to
/// the corners' vertices, corner normals kept; tags dropped (a soup has no shared vertex ids).
PolygonMesh soupOf(const PolygonMesh& m) {
  PolygonMesh s;
  s.faceOffsets = m.faceOffsets;
  s.fileCornerNormals = m.fileCornerNormals;
  s.faceSmoothingGroups = m.faceSmoothingGroups;
  const bool vertexNormals = m.fileNormals.size() == m.positions.size();
  for (int c = 0; c < m.numCorners(); ++c) {
    s.positions.push_back(m.positions[m.faceVertices[c]]);
    if (vertexNormals) s.fileNormals.push_back(m.fileNormals[m.faceVertices[c]]);
    s.faceVertices.push_back(c);
  }
  return s;
}

const MeshCheckOptions kTopology{false};

TEST(SeamStitch, SoupsOfEverySharedMeshJoinBackIntoTheMeshAsRead) {
  int meshes = 0, bijective = 0, withSeamsAsRead = 0;
  long joined = 0, interior = 0;
  for (const std::string& path : test::sharedMeshFiles()) {
    SCOPED_TRACE(path);
    PolygonMesh read = readMesh(path);
    read.creaseTags.clear();
    read.cornerTags.clear();
    const MeshReport before = checkMesh(read, kTopology);
    // the mesh as read may have seams of its own (written twice there): the soup joins those too
    const SeamReport own = stitchSeams(read);
    withSeamsAsRead += own.seamEdges > 0;
    const MeshReport asRead = checkMesh(read, kTopology);
    if (own.seamEdges > 0) std::printf("  %s: %d seam edges as read\n", path.c_str(), own.seamEdges);
    EXPECT_LE(asRead.boundaryLoops.size(), before.boundaryLoops.size());

    PolygonMesh soup = soupOf(read);
    const SeamReport seams = stitchSeams(soup);
    // as read, a few stanford bunnies repeat faces; their soups' joins there stay open
    EXPECT_EQ(seams.leftOpen.empty(), asRead.duplicateFaces.empty()) << seams.leftOpen;
    EXPECT_FALSE(seams.cornerNormals);  // one normal per vertex as read: the same across every seam
    const MeshReport after = checkMesh(soup, kTopology);
    if (seams.openEdges > 0)
      std::printf("  %s: %d of %d pairs left open (%s); %d edges, %zu boundary loops (as read %d, %zu)\n", path.c_str(),
                  seams.openEdges, seams.pairsFound, seams.leftOpen.c_str(), after.numEdges, after.boundaryLoops.size(),
                  asRead.numEdges, asRead.boundaryLoops.size());
    // never joins what the mesh does not: each vertex of the soup stands for one vertex read
    std::map<int, int> soupToRead, readToSoup;
    bool function = true, injective = true;
    for (int c = 0; c < read.numCorners(); ++c) {
      const auto [it, fresh] = soupToRead.emplace(soup.faceVertices[c], read.faceVertices[c]);
      function &= fresh || it->second == read.faceVertices[c];
      const auto [jt, fresh2] = readToSoup.emplace(read.faceVertices[c], soup.faceVertices[c]);
      injective &= fresh2 || jt->second == soup.faceVertices[c];
    }
    EXPECT_TRUE(function) << "a soup vertex joins corners of different vertices as read";
    // and joins all of it on every manifold, consistently oriented mesh: the same edges,
    // components, boundary loops; elsewhere a non-manifold edge (three or more boundary edges at
    // one place) or an inconsistent one (same direction) stays open in the soup
    const bool manifold = asRead.nonManifoldEdges.empty() && asRead.nonManifoldVertices.empty() &&
                          asRead.inconsistentEdges.empty() && asRead.duplicateFaces.empty();
    if (manifold) {
      EXPECT_TRUE(injective) << "the soup keeps apart corners of one vertex as read";
      EXPECT_EQ(after.numEdges, asRead.numEdges);
      EXPECT_EQ(after.numComponents, asRead.numComponents);
      EXPECT_EQ(after.boundaryLoops.size(), asRead.boundaryLoops.size());
      EXPECT_EQ(after.closed(), asRead.closed());
      EXPECT_EQ(static_cast<int>(soupToRead.size()),
                asRead.numVertices - static_cast<int>(asRead.unreferencedVertices.size()));
      bijective += function && injective;
    }
    long boundaryEdges = 0;
    for (const auto& loop : asRead.boundaryLoops) boundaryEdges += static_cast<long>(loop.size());
    if (manifold) {
      EXPECT_EQ(seams.seamEdges, asRead.numEdges - boundaryEdges);
      interior += asRead.numEdges - boundaryEdges;
    }
    joined += seams.seamEdges;
    ++meshes;
  }
  std::printf(
      "%d meshes (%d with seams as read): %d manifold ones joined back vertex for vertex; %ld seam edges "
      "joined in all, %ld interior edges of the manifold ones\n",
      meshes, withSeamsAsRead, bijective, joined, interior);
  EXPECT_EQ(meshes, 28);
  EXPECT_GE(bijective, 24);
  EXPECT_GE(joined, interior);
}

/// The shared mesh at `path` as read, tags dropped and its own seams joined, into *read and its
/// topology into *r, when it has minFaces..20,000 faces and is manifold, consistently oriented,
/// without repeated faces or unreferenced vertices (the meshes whose soups rebuild it exactly).
bool manifoldAsRead(const std::string& path, int minFaces, PolygonMesh* read, MeshReport* r) {
  *read = readMesh(path);
  if (read->numFaces() > 20000 || read->numFaces() < minFaces) return false;
  read->creaseTags.clear();
  read->cornerTags.clear();
  stitchSeams(*read);
  *r = checkMesh(*read, kTopology);
  return r->nonManifoldEdges.empty() && r->nonManifoldVertices.empty() && r->inconsistentEdges.empty() &&
         r->duplicateFaces.empty() && r->unreferencedVertices.empty();
}

// The soup of every manifold shared mesh of up to 20,000 faces builds the patches of the mesh as
// read, bit for bit (records and status of every face), by default and with creases at 30
// degrees: the normals, creases and fold repair see one mesh.
TEST(SeamStitch, ASoupBuildsThePatchesOfTheMeshAsRead) {
  int builds = 0;
  long faces = 0;
  for (const std::string& path : test::sharedMeshFiles()) {
    PolygonMesh read;
    MeshReport r;
    if (!manifoldAsRead(path, 1, &read, &r)) continue;
    SCOPED_TRACE(path);
    for (const double creaseAngle : {0.0, 30.0}) {
      PatchOptions options;
      options.creases.angleDeg = creaseAngle;
      const LoadedMesh a = loadMesh(read, 1, options), b = loadMesh(soupOf(read), 1, options);
      ASSERT_EQ(b.mesh.numFaces(), a.mesh.numFaces());
      int boundaryEdges = 0;
      for (const auto& loop : r.boundaryLoops) boundaryEdges += static_cast<int>(loop.size());
      EXPECT_EQ(b.seams.seamEdges, r.numEdges - boundaryEdges);
      EXPECT_EQ(b.report.numEdges, a.report.numEdges);
      EXPECT_EQ(b.report.closed(), a.report.closed());
      EXPECT_EQ(b.flipped, a.flipped);
      const PatchCache ca = buildPatchCache(a, options, Backend::Tbb), cb = buildPatchCache(b, options, Backend::Tbb);
      EXPECT_EQ(cb.faceStatus, ca.faceStatus);
      EXPECT_TRUE(cb.edgeDataD == ca.edgeDataD) << "patch records differ";
      EXPECT_EQ(cb.faceVertices.size(), ca.faceVertices.size());
      ++builds;
      faces += ca.numFaces();
    }
  }
  std::printf("%d builds, %ld faces: the soup's patches are those of the mesh as read\n", builds, faces);
  EXPECT_GE(builds, 2 * 18);
}

/// `soup` with a seeded tenth of its faces turned (corners reversed after the first, their corner
/// normals with them), the middle face where the draw turned none; the turned faces' ids in order.
std::vector<int> turnSomeFaces(PolygonMesh& soup, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<int> turned;
  std::vector<char> turn(soup.numFaces(), 0);
  for (int f = 0; f < soup.numFaces(); ++f) turn[f] = rng() % 10 == 0;
  if (std::find(turn.begin(), turn.end(), 1) == turn.end() && !turn.empty()) turn[turn.size() / 2] = 1;
  for (int f = 0; f < soup.numFaces(); ++f) {
    if (!turn[f]) continue;
    turned.push_back(f);
    const int b = soup.faceOffsets[f] + 1, e = soup.faceOffsets[f + 1];
    std::reverse(soup.faceVertices.begin() + b, soup.faceVertices.begin() + e);
    if (!soup.fileCornerNormals.empty())
      std::reverse(soup.fileCornerNormals.begin() + b, soup.fileCornerNormals.begin() + e);
  }
  return turned;
}

// A soup with faces turned against their neighbours (a tenth of every manifold shared mesh's
// faces, up to 20,000 faces, seeded), as a triangle soup with flipped triangles comes: under
// `--orient outward` every seam joins, the turned faces are turned back (exactly those, on the
// meshes of one component) and the patches are those of the mesh as read, bit for bit; under
// `keep` the edges between a turned face and its neighbours stay open, the rest join.
TEST(SeamStitch, ASoupWithFacesTurnedJoinsBackAndBuildsThePatchesOfTheMeshAsRead) {
  int builds = 0, oneComponent = 0;
  long turnedSeams = 0, openUnderKeep = 0;
  for (const std::string& path : test::sharedMeshFiles()) {
    PolygonMesh read;
    MeshReport r;
    if (!manifoldAsRead(path, 4, &read, &r)) continue;  // a face turned among at least 3 as written
    SCOPED_TRACE(path);
    PolygonMesh soup = soupOf(read);
    const std::vector<int> turned = turnSomeFaces(soup, 5);
    ASSERT_FALSE(turned.empty());
    int boundaryEdges = 0;
    for (const auto& loop : r.boundaryLoops) boundaryEdges += static_cast<int>(loop.size());
    const PatchOptions options;
    const LoadedMesh a = loadMesh(read, 1, options), b = loadMesh(soup, 1, options);
    EXPECT_EQ(b.seams.seamEdges, r.numEdges - boundaryEdges);
    EXPECT_GT(b.seams.turnedSeams, 0);
    EXPECT_TRUE(b.seams.leftOpen.empty()) << b.seams.leftOpen;
    EXPECT_TRUE(b.orientation.unorientableFaces.empty());
    EXPECT_TRUE(b.report.inconsistentEdges.empty());
    if (r.numComponents == 1) {
      EXPECT_EQ(b.orientation.turnedFaces, turned);
      ++oneComponent;
    }
    EXPECT_EQ(b.report.numEdges, a.report.numEdges);
    EXPECT_EQ(b.report.closed(), a.report.closed());
    const PatchCache ca = buildPatchCache(a, options, Backend::Tbb), cb = buildPatchCache(b, options, Backend::Tbb);
    EXPECT_EQ(cb.faceStatus, ca.faceStatus);
    EXPECT_TRUE(cb.edgeDataD == ca.edgeDataD) << "patch records differ";
    turnedSeams += b.seams.turnedSeams;
    ++builds;
    // keep: a seam between a turned face and a face as written is not one (the faces disagree)
    PatchOptions keep;
    keep.keepOrientation = true;
    const LoadedMesh k = loadMesh(soup, 1, keep);
    EXPECT_EQ(k.seams.turnedSeams, 0);
    EXPECT_EQ(k.seams.seamEdges, b.seams.seamEdges - b.seams.turnedSeams);
    EXPECT_TRUE(k.report.inconsistentEdges.empty());
    openUnderKeep += b.seams.turnedSeams;
  }
  std::printf(
      "%d meshes: %ld seams between turned faces and their neighbours joined, every face in line again "
      "(%d of one component: exactly the turned ones); %ld left open under keep\n",
      builds, turnedSeams, oneComponent, openUnderKeep);
  EXPECT_GE(builds, 18);
  EXPECT_GE(oneComponent, 12);
}

/// A stadium prism (two half-discs of 5 vertices joined by straight sides) written as an
/// exporter with per-vertex normals writes a creased part: the caps' vertices apart from the
/// side's, each with its own normal (the caps' +-z, the side's radial in the plane).
PolygonMesh splitNormalStadium() {
  std::vector<std::array<double, 3>> ring;  // x, y, angle of the side's normal
  for (int k = 0; k < 5; ++k) {
    const double a = -std::numbers::pi / 2 + std::numbers::pi * k / 4;
    ring.push_back({1 + 0.5 * std::cos(a), 0.5 * std::sin(a), a});
  }
  for (int k = 0; k < 5; ++k) {
    const double a = std::numbers::pi / 2 + std::numbers::pi * k / 4;
    ring.push_back({-1 + 0.5 * std::cos(a), 0.5 * std::sin(a), a});
  }
  const int n = static_cast<int>(ring.size());
  PolygonMesh m;
  for (const double z : {0.0, 0.6})  // side: vertices 0..2n-1
    for (const auto& [x, y, a] : ring) {
      m.positions.emplace_back(x, y, z);
      m.fileNormals.emplace_back(std::cos(a), std::sin(a), 0);
    }
  for (const double z : {0.0, 0.6})  // caps: 2n..4n-1
    for (const auto& [x, y, a] : ring) {
      m.positions.emplace_back(x, y, z);
      m.fileNormals.emplace_back(0, 0, z > 0 ? 1 : -1);
    }
  std::vector<int32_t> bottom, top;
  for (int i = n - 1; i >= 0; --i) bottom.push_back(2 * n + i);
  for (int i = 0; i < n; ++i) top.push_back(3 * n + i);
  m.addFace(bottom);
  m.addFace(top);
  for (int i = 0; i < n; ++i) m.addFace({i, (i + 1) % n, n + (i + 1) % n, n + i});
  return m;
}

TEST(SeamStitch, SplitVertexNormalsGoToTheCornersAndMakeCreasesWhereAsked) {
  PolygonMesh m = splitNormalStadium();
  const MeshReport open = checkMesh(m, kTopology);
  EXPECT_EQ(open.numComponents, 3);
  EXPECT_EQ(open.boundaryLoops.size(), 4u);
  PolygonMesh joined = m;
  const SeamReport seams = stitchSeams(joined);
  EXPECT_EQ(seams.seamEdges, 20);
  EXPECT_EQ(seams.mergedVertices.size(), 20u);
  for (const auto& [v, into] : seams.mergedVertices) {
    EXPECT_GE(v, 20);  // the caps' vertices into the side's
    EXPECT_EQ(into, v - 20);
    EXPECT_EQ(joined.positions[v], joined.positions[into]);
  }
  EXPECT_TRUE(seams.cornerNormals);
  EXPECT_TRUE(joined.fileNormals.empty());
  ASSERT_EQ(joined.fileCornerNormals.size(), static_cast<size_t>(joined.numCorners()));
  for (int c = 0; c < joined.numCorners(); ++c)
    EXPECT_EQ(joined.fileCornerNormals[c], m.fileNormals[m.faceVertices[c]]);
  const MeshReport closed = checkMesh(joined, kTopology);
  EXPECT_TRUE(closed.closed());
  EXPECT_EQ(closed.numComponents, 1);
  EXPECT_EQ(closed.numEdges, 30);
  EXPECT_FALSE(seams.describe().empty());

  // auto averages split normals (as for OBJ), `--normals file` keeps them: each seam a crease
  // whose two sides share one curve, so the surface is closed either way
  for (const NormalMode mode : {NormalMode::Auto, NormalMode::File}) {
    PatchOptions options;
    options.normals = mode;
    const LoadedMesh lm = loadMesh(m, 1, options);
    EXPECT_EQ(lm.seams.seamEdges, 20);
    EXPECT_TRUE(lm.report.closed());
    EXPECT_EQ(lm.normalReport.creaseCorners, mode == NormalMode::File ? 40 : 0);
    const PatchCache c = buildPatchCache(lm, options, Backend::Tbb);
    EXPECT_EQ(std::count(c.slotTwin.begin(), c.slotTwin.end(), -1), 0);
  }
}

TEST(SeamStitch, AmbiguousAndUnsafeSeamsStayOpen) {
  // two cubes written apart that meet along an edge: four boundary-free halves, nothing to join
  PolygonMesh pair = test::cubeMesh();
  {
    const PolygonMesh b = test::cubeMesh();
    const int off = pair.numVertices();
    for (const Eigen::Vector3d& p : b.positions) pair.positions.push_back(p + Eigen::Vector3d(2, 2, 0));
    for (int f = 0; f < b.numFaces(); ++f) {
      std::vector<int32_t> vs;
      for (int k = 0; k < b.faceSize(f); ++k) vs.push_back(b.faceVertex(f, k) + off);
      pair.addFace(vs);
    }
  }
  PolygonMesh kept = pair;
  EXPECT_EQ(stitchSeams(kept).pairsFound, 0);
  EXPECT_EQ(kept.faceVertices, pair.faceVertices);

  // the same two cubes as a soup: the edge they share is four boundary edges at one place, which
  // no pair joins; every other edge does (11 per cube), and the shared edge's ends with them, so
  // each cube closes on its own: the two cubes as written, not one non-manifold solid
  PolygonMesh soup = soupOf(pair);
  const SeamReport s = stitchSeams(soup);
  EXPECT_TRUE(s.leftOpen.empty());
  EXPECT_EQ(s.seamEdges, 22);
  const MeshReport r = checkMesh(soup, kTopology);
  EXPECT_EQ(r.numComponents, 2);
  EXPECT_EQ(r.numEdges, 24);
  EXPECT_TRUE(r.closed());
  EXPECT_TRUE(r.nonManifoldEdges.empty() && r.nonManifoldVertices.empty());

  // two triangles back to back: joining both would make each the other's duplicate
  PolygonMesh pillow =
      test::polygonMesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 0}, {0, 1, 0}}, {{0, 1, 2}, {3, 4, 5}});
  const PolygonMesh asRead = pillow;
  const SeamReport p = stitchSeams(pillow);
  EXPECT_EQ(p.pairsFound, 3);
  EXPECT_EQ(p.seamEdges, 0);
  EXPECT_EQ(p.openEdges, 3);
  EXPECT_NE(p.leftOpen.find("faces on the vertices of others"), std::string::npos) << p.leftOpen;
  EXPECT_EQ(pillow.faceVertices, asRead.faceVertices);
  EXPECT_NE(p.describe().front().find("left open"), std::string::npos);
}

// The spot cage and the chamfered cube with one face turned against its neighbours, every face
// in turn: loadMesh turns it back (that face alone) and the patches are the mesh's as read, bit
// for bit; under --orient keep the face stays turned and the check names its edges.
TEST(CoherentOrientation, AFaceTurnedAgainstItsNeighboursBuildsThePatchesOfTheMeshAsRead) {
  int builds = 0;
  for (const char* rel : {"keenan_crane/spot_control_mesh.obj", "pmp/chamfer-cube.off"}) {
    SCOPED_TRACE(rel);
    const PolygonMesh read = readMesh(test::sharedMesh(rel));
    for (const double creaseAngle : {0.0, 30.0}) {
      PatchOptions options;
      options.creases.angleDeg = creaseAngle;
      const PatchCache home = buildPatchCache(loadMesh(read, 1, options), options, Backend::Tbb);
      for (int f = 0; f < read.numFaces(); ++f) {
        PolygonMesh m = read;
        std::reverse(m.faceVertices.begin() + m.faceOffsets[f] + 1, m.faceVertices.begin() + m.faceOffsets[f + 1]);
        const LoadedMesh lm = loadMesh(m, 1, options);
        ASSERT_EQ(lm.orientation.turnedFaces, std::vector<int>{f});
        ASSERT_TRUE(lm.report.inconsistentEdges.empty());
        ASSERT_FALSE(lm.flipped);
        const PatchCache c = buildPatchCache(lm, options, Backend::Tbb);
        ASSERT_TRUE(c.edgeDataD == home.edgeDataD) << "face " << f;
        ASSERT_EQ(c.faceStatus, home.faceStatus) << "face " << f;
        ++builds;
      }
    }
    PolygonMesh m = read;
    std::reverse(m.faceVertices.begin() + 1, m.faceVertices.begin() + m.faceOffsets[1]);
    PatchOptions keep;
    keep.keepOrientation = true;
    const LoadedMesh kept = loadMesh(m, 1, keep);
    EXPECT_TRUE(kept.orientation.turnedFaces.empty());
    EXPECT_EQ(kept.report.inconsistentEdges.size(), static_cast<size_t>(read.faceSize(0)));
    EXPECT_EQ(kept.mesh.faceVertices, m.faceVertices);
  }
  EXPECT_EQ(builds, 2 * (180 + 26));
}

}  // namespace
}  // namespace sf
