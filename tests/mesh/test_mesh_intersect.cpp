// SPDX-License-Identifier: Apache-2.0
// Intersecting and self-crossing polygons (mesh_intersect.h, checkMesh): the exact triangle test
// against separating axes in integer arithmetic; the box hierarchy against every pair (small
// meshes) or a sweep over x (large ones) on every shared mesh, with the counts per mesh; the spot
// cage's two bow-ties; hand-built inputs (interpenetrating cubes, a bow-tie, an L, a tetris piece,
// a non-planar quad, a triangle in an L's notch); degenerate input; the exact predicates.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>
#include <random>
#include <set>

#include <smoothforce/mesh/exact_predicates.h>
#include <smoothforce/mesh/mesh_check.h>
#include <smoothforce/mesh/mesh_intersect.h>
#include <smoothforce/mesh/mesh_io.h>
#include "polygon_mesh_support.h"
#include "shared_mesh_files.h"

namespace {

using Eigen::Vector3d;
using sf::test::polygonMesh;
using I3 = std::array<int64_t, 3>;

I3 sub(const I3& a, const I3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
I3 cross(const I3& a, const I3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
int64_t dot(const I3& a, const I3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// Closed triangles with integer corners share a point unless an axis separates them: the two
/// normals, the nine edge-edge cross products and each normal crossed with its own edges (the
/// coplanar case). Exact in int64 for small coordinates. An independent reference.
bool separatingAxesIntersect(const std::array<I3, 3>& p, const std::array<I3, 3>& q) {
  std::vector<I3> axes;
  const I3 np = cross(sub(p[1], p[0]), sub(p[2], p[0])), nq = cross(sub(q[1], q[0]), sub(q[2], q[0]));
  axes.push_back(np);
  axes.push_back(nq);
  for (int i = 0; i < 3; ++i) {
    const I3 ep = sub(p[(i + 1) % 3], p[i]), eq = sub(q[(i + 1) % 3], q[i]);
    axes.push_back(cross(np, ep));
    axes.push_back(cross(nq, eq));
    for (int j = 0; j < 3; ++j) axes.push_back(cross(ep, sub(q[(j + 1) % 3], q[j])));
  }
  for (const I3& a : axes) {
    if (a[0] == 0 && a[1] == 0 && a[2] == 0) continue;
    int64_t pmin = INT64_MAX, pmax = INT64_MIN, qmin = INT64_MAX, qmax = INT64_MIN;
    for (int i = 0; i < 3; ++i) {
      pmin = std::min(pmin, dot(a, p[i]));
      pmax = std::max(pmax, dot(a, p[i]));
      qmin = std::min(qmin, dot(a, q[i]));
      qmax = std::max(qmax, dot(a, q[i]));
    }
    if (pmax < qmin || qmax < pmin) return false;
  }
  return true;
}

Vector3d toVec(const I3& a) { return Vector3d(double(a[0]), double(a[1]), double(a[2])); }

/// Faces a and b have a corner at the same position (the adjacency the check skips), by
/// comparing positions directly.
bool touchAtCorner(const sf::PolygonMesh& m, int a, int b) {
  for (int i = m.faceOffsets[a]; i < m.faceOffsets[a + 1]; ++i)
    for (int j = m.faceOffsets[b]; j < m.faceOffsets[b + 1]; ++j)
      if (m.positions[m.faceVertices[i]] == m.positions[m.faceVertices[j]]) return true;
  return false;
}

struct TriBox {
  Vector3d lo, hi;
};

std::vector<TriBox> triangleBoxes(const sf::MeshTriangles& t) {
  std::vector<TriBox> b(t.tri.size());
  for (size_t i = 0; i < t.tri.size(); ++i) {
    const Vector3d &p = t.points[t.tri[i][0]], &q = t.points[t.tri[i][1]], &r = t.points[t.tri[i][2]];
    b[i] = {p.cwiseMin(q).cwiseMin(r), p.cwiseMax(q).cwiseMax(r)};
  }
  return b;
}

/// Intersecting face pairs without the hierarchy: every triangle pair (boxes compared first) when
/// `allPairs`, else a sweep over the boxes sorted by their low x.
std::set<std::array<int, 2>> referencePairs(const sf::PolygonMesh& m, const sf::MeshTriangles& t, bool allPairs) {
  const std::vector<TriBox> box = triangleBoxes(t);
  const int n = static_cast<int>(t.tri.size());
  std::set<std::array<int, 2>> found;
  const auto test = [&](int i, int j) {
    const int fi = t.triFace[i], fj = t.triFace[j];
    if (fi == fj) return;
    for (int k = 0; k < 3; ++k)
      if (box[i].hi[k] < box[j].lo[k] || box[j].hi[k] < box[i].lo[k]) return;
    const std::array<int, 2> pair{std::min(fi, fj), std::max(fi, fj)};
    if (found.count(pair) || touchAtCorner(m, fi, fj)) return;
    const Vector3d p[3] = {t.points[t.tri[i][0]], t.points[t.tri[i][1]], t.points[t.tri[i][2]]};
    const Vector3d q[3] = {t.points[t.tri[j][0]], t.points[t.tri[j][1]], t.points[t.tri[j][2]]};
    if (sf::trianglesIntersect(p, q)) found.insert(pair);
  };
  if (allPairs) {
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) test(i, j);
    return found;
  }
  std::vector<int> order(n);
  for (int i = 0; i < n; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](int a, int b) { return box[a].lo.x() < box[b].lo.x(); });
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n && box[order[b]].lo.x() <= box[order[a]].hi.x(); ++b) test(order[a], order[b]);
  return found;
}

std::set<std::array<int, 2>> pairSet(const std::vector<sf::IntersectingPair>& pairs) {
  std::set<std::array<int, 2>> s;
  for (const auto& p : pairs) s.insert({p.a, p.b});
  return s;
}

}  // namespace

TEST(ExactPredicates, SignsOfNearlyDegenerateConfigurationsAreExact) {
  // points on the line y = x perturbed by one ulp: the naive determinant rounds to 0 or the wrong sign
  const double x = 0.5 + 0x1p-40, y = std::nextafter(x, 1.0);
  EXPECT_EQ(sf::orient2d({0.5, 0.5}, {12, 12}, {24, 24}), 0);
  EXPECT_EQ(sf::orient2d({0.5, 0.5}, {12, 12}, {x, y}), 1);  // above the line: counter-clockwise
  EXPECT_EQ(sf::orient2d({0.5, 0.5}, {12, 12}, {y, x}), -1);
  // the plane z = 0.1 x (0.1 not exact): a point built on it is on, above or below by the exact sign
  const Vector3d a(0, 0, 0), b(1, 0, 0.1), c(0, 1, 0);
  EXPECT_EQ(sf::orient3d(a, b, c, Vector3d(0, 0, 0)), 0);
  EXPECT_EQ(sf::orient3d(a, b, c, Vector3d(0, 0, 1e-300)), -1);  // above, with a, b, c counter-clockwise
  EXPECT_EQ(sf::orient3d(a, b, c, Vector3d(0, 0, -1e-300)), 1);
  // exact integers against random doubles: the sign of an exactly computable determinant
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<int> coord(-1 << 20, 1 << 20);
  int checked = 0;
  for (int i = 0; i < 20000; ++i) {
    I3 p[4];
    for (auto& v : p) v = {coord(rng), coord(rng), coord(rng)};
    if (i % 2) p[3] = {p[0][0] + p[1][0] - p[2][0], p[0][1] + p[1][1] - p[2][1], p[0][2] + p[1][2] - p[2][2]};
    // det[a-d; b-d; c-d] in __int128 (products of three 22-bit differences)
    const I3 ad = sub(p[0], p[3]), bd = sub(p[1], p[3]), cd = sub(p[2], p[3]);
    const __int128 det = (__int128)ad[0] * (bd[1] * cd[2] - bd[2] * cd[1]) -
                         (__int128)ad[1] * (bd[0] * cd[2] - bd[2] * cd[0]) +
                         (__int128)ad[2] * (bd[0] * cd[1] - bd[1] * cd[0]);
    const int sign = (det > 0) - (det < 0);
    ASSERT_EQ(sf::orient3d(toVec(p[0]), toVec(p[1]), toVec(p[2]), toVec(p[3])), sign) << i;
    ++checked;
  }
  EXPECT_EQ(checked, 20000);
}

// Random closed triangles on a 5 x 5 x 5 grid (half of the pairs in one plane: z = 0, or x = y):
// many touch, share an edge or a corner, overlap in their plane or cross; every answer equals the
// separating-axis test in integers, in every vertex order and both argument orders.
TEST(TrianglesIntersect, EqualsSeparatingAxesOnGridTriangles) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> coord(-2, 2);
  int plane = 0;  // 0: anywhere; 1: in z = 0; 2: in x = y (whose projection on z = 0 degenerates)
  const auto randomTriangle = [&] {
    for (;;) {
      std::array<I3, 3> t;
      for (auto& v : t) {
        v = {coord(rng), coord(rng), coord(rng)};
        if (plane == 1) v[2] = 0;
        if (plane == 2) v[1] = v[0];
      }
      const I3 n = cross(sub(t[1], t[0]), sub(t[2], t[0]));
      if (n[0] || n[1] || n[2]) return t;  // the test takes triangles of non-zero area
    }
  };
  int yes = 0, no = 0, coplanar = 0;
  for (int trial = 0; trial < 60000; ++trial) {
    plane = trial % 4 == 1 ? 1 : trial % 4 == 2 ? 2 : 0;
    const std::array<I3, 3> p = randomTriangle(), q = randomTriangle();
    const bool expected = separatingAxesIntersect(p, q);
    const I3 np = cross(sub(p[1], p[0]), sub(p[2], p[0]));
    coplanar += dot(np, sub(q[0], p[0])) == 0 && dot(np, sub(q[1], p[0])) == 0 && dot(np, sub(q[2], p[0])) == 0;
    (expected ? yes : no)++;
    for (int rot = 0; rot < 3; ++rot) {
      const Vector3d a[3] = {toVec(p[rot]), toVec(p[(rot + 1) % 3]), toVec(p[(rot + 2) % 3])};
      const Vector3d b[3] = {toVec(q[(rot + 2) % 3]), toVec(q[(rot + 1) % 3]), toVec(q[rot])};  // reversed too
      ASSERT_EQ(sf::trianglesIntersect(a, b), expected) << trial << " rot " << rot;
      ASSERT_EQ(sf::trianglesIntersect(b, a), expected) << trial << " rot " << rot;
    }
  }
  // both answers, and the coplanar branch, are exercised in numbers
  EXPECT_GT(yes, 10000);
  EXPECT_GT(no, 10000);
  EXPECT_GT(coplanar, 25000);
}

/// Shared meshes: intersecting pairs and self-crossing faces as found (file order, 0-based).
struct Expected {
  int pairs, selfCrossing;
};
const std::map<std::string, Expected> kExpected = {
    {"geomview/dodecahedron.off", {0, 0}},
    {"geomview/snub_dodecahedron.off", {0, 0}},
    {"keenan_crane/bob_tri.obj", {0, 0}},
    {"keenan_crane/semi2.obj", {0, 0}},
    {"keenan_crane/semi6.obj", {0, 0}},
    {"keenan_crane/spot_control_mesh.obj", {4, 2}},
    {"keenan_crane/spot_quadrangulated.obj", {0, 0}},
    {"keenan_crane/spot_triangulated.obj", {0, 0}},
    {"lagrange/catmark_fvar_bound1.obj", {0, 0}},
    {"lagrange/cube.obj", {0, 0}},
    {"odedstein/armadillo.obj", {0, 0}},
    {"odedstein/bunny.obj", {0, 0}},
    {"odedstein/bunny_hr.obj", {0, 0}},
    {"odedstein/sphere.obj", {0, 0}},
    {"odedstein/spot.obj", {0, 0}},
    {"odedstein/spot_low_resolution.obj", {0, 0}},
    {"odedstein/torus.obj", {0, 0}},
    {"pmp/L.off", {0, 0}},
    {"pmp/chamfer-cube.off", {0, 0}},
    {"pmp/hole_capsule.off", {0, 0}},
    {"polygon_laplacian/L-plane.obj", {0, 0}},
    {"polygon_laplacian/hexaSphere.off", {0, 0}},
    {"polygon_laplacian/quad-sphere.off", {0, 0}},
    {"polygon_laplacian/sphere2.off", {0, 0}},
    {"polygon_laplacian/tetris.obj", {0, 0}},
    {"stanford/bun_zipper.ply", {0, 0}},
    {"stanford/bun_zipper_res2.ply", {0, 0}},
    {"stanford/bun_zipper_res3.ply", {0, 0}},
    {"stanford/bun_zipper_res4.ply", {0, 0}},
};

// Every shared mesh: the hierarchy's pairs equal every triangle pair's (up to 6,000 triangles)
// or a sweep over x's (larger), and the counts are the catalogue's. Prints the times.
TEST(MeshIntersections, HierarchyEqualsReferenceOnEverySharedMesh) {
  int meshes = 0, bruteForce = 0;
  for (const std::string& path : sf::test::sharedMeshFiles(UINTMAX_MAX)) {
    const std::string rel = std::filesystem::relative(path, SF_SHARED_MESHES).string();
    SCOPED_TRACE(rel);
    const sf::PolygonMesh m = sf::readMesh(path);
    const auto t0 = std::chrono::steady_clock::now();
    const sf::MeshReport r = sf::checkMesh(m);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const sf::MeshTriangles t = sf::polygonTriangles(m);
    const bool allPairs = t.tri.size() <= 6000;
    bruteForce += allPairs;
    EXPECT_EQ(pairSet(r.intersectingPairs), referencePairs(m, t, allPairs));
    ASSERT_TRUE(kExpected.count(rel)) << rel << " is not in the table";
    EXPECT_EQ(static_cast<int>(r.intersectingPairs.size()), kExpected.at(rel).pairs);
    EXPECT_EQ(static_cast<int>(r.selfCrossingFaces.size()), kExpected.at(rel).selfCrossing);
    EXPECT_EQ(r.selfCrossingUnchecked, 0);
    std::printf("  %-40s %6d faces %7zu triangles: %zu intersecting pairs, %zu self-crossing; checkMesh %.3f s\n",
                rel.c_str(), m.numFaces(), t.tri.size(), r.intersectingPairs.size(), r.selfCrossingFaces.size(), secs);
    ++meshes;
  }
  EXPECT_EQ(meshes, static_cast<int>(kExpected.size()));
  EXPECT_GE(bruteForce, 15);
}

TEST(MeshIntersections, SpotCageBowTiesAre60And150AndItsEarsIntersect) {
  const sf::PolygonMesh m = sf::readMesh(sf::test::sharedMesh("keenan_crane/spot_control_mesh.obj"));
  EXPECT_EQ(sf::findSelfCrossingFaces(m), (std::vector<int>{60, 150}));
  const sf::MeshReport r = sf::checkMesh(m);
  EXPECT_EQ(r.selfCrossingFaces, (std::vector<int>{60, 150}));
  std::string all;
  for (const std::string& line : r.describe()) all += line + "\n";
  EXPECT_NE(all.find("self-crossing polygons: 2 (first: 60, 150)"), std::string::npos) << all;
  // the quads beside each bow-tie pass through each other (under either diagonal split too):
  // mirror images of each other across x = 0
  std::set<std::array<int, 2>> expected = {{70, 71}, {70, 72}, {160, 161}, {160, 162}};
  EXPECT_EQ(pairSet(r.intersectingPairs), expected);
  EXPECT_NE(all.find("intersecting polygons: 4 pairs (first: 70-71, 70-72, 160-161, 160-162) on 6 faces"),
            std::string::npos)
      << all;  // not an artefact of the centroid fans: under either diagonal split of each quad, some triangle
  // of one passes through some triangle of the other
  const auto split = [&](int f, int diagonal) {
    std::array<std::array<Vector3d, 3>, 2> t;
    for (int h = 0; h < 2; ++h)
      for (int k = 0; k < 3; ++k) t[h][k] = m.positions[m.faceVertex(f, diagonal + (h ? 2 : 0) + k)];
    return t;
  };
  for (const auto& [a, b] : expected)
    for (int da = 0; da < 2; ++da)
      for (int db = 0; db < 2; ++db) {
        bool meet = false;
        for (const auto& p : split(a, da))
          for (const auto& q : split(b, db)) meet = meet || sf::trianglesIntersect(p.data(), q.data());
        EXPECT_TRUE(meet) << a << "-" << b << " diagonals " << da << " " << db;
      }
}

/// Two axis-aligned cubes [0, 2]^3 and d + [0, 2]^3 in one mesh (faces 0-5 and 6-11, ordered
/// -x, +x, -y, +y, -z, +z).
sf::PolygonMesh twoCubes(const Vector3d& d) {
  std::vector<Vector3d> p;
  for (int c = 0; c < 2; ++c)
    for (int i = 0; i < 8; ++i)
      p.push_back(Vector3d(i & 1 ? 2 : 0, i & 2 ? 2 : 0, i & 4 ? 2 : 0) + (c ? d : Vector3d::Zero()));
  std::vector<std::vector<int32_t>> faces;
  for (int c = 0; c < 2; ++c) {
    const int o = 8 * c;
    for (const auto& f : std::vector<std::vector<int32_t>>{
             {0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}})
      faces.push_back({f[0] + o, f[1] + o, f[2] + o, f[3] + o});
  }
  return polygonMesh(p, faces);
}

// Face (axis i, low or high side) of the first cube meets face (axis j, side) of the second iff
// the planes cross inside both squares: i != j, the first face's coordinate within the second
// cube's range on i, the second's within the first's on j, the ranges on the third axis overlap
// (parallel faces, i == j, meet only when their planes coincide and the squares overlap).
TEST(MeshIntersections, InterpenetratingCubesGiveEveryExpectedPair) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-2.5, 2.5);
  int withPairs = 0, total = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Vector3d d(u(rng), u(rng), u(rng));
    if (trial < 8) d = Vector3d(trial & 1 ? 1 : -1, trial & 2 ? 1 : -1, trial & 4 ? 1 : -1);  // the hand example's
    if (trial == 8) d = Vector3d(1, 1, 0);  // coplanar faces (z = 0 and z = 2 planes shared)
    const sf::PolygonMesh m = twoCubes(d);
    std::set<std::array<int, 2>> expected;
    const auto within = [](double x, double lo) { return lo <= x && x <= lo + 2; };
    const auto overlap = [](double a, double b) { return a <= b + 2 && b <= a + 2; };  // [a, a+2] and [b, b+2]
    for (int fa = 0; fa < 6; ++fa)
      for (int fb = 0; fb < 6; ++fb) {
        const int i = fa / 2, j = fb / 2;
        const double a = fa % 2 ? 2 : 0, b = d[j] + (fb % 2 ? 2 : 0);
        bool meet;
        if (i != j) {
          const int k = 3 - i - j;
          meet = within(a, d[i]) && within(b, 0) && overlap(0, d[k]);
        } else {
          meet = a == b && overlap(0, d[(i + 1) % 3]) && overlap(0, d[(i + 2) % 3]);
        }
        if (meet) expected.insert({fa, 6 + fb});
      }
    const sf::MeshReport r = sf::checkMesh(m);
    ASSERT_EQ(pairSet(r.intersectingPairs), expected) << "d = " << d.transpose();
    withPairs += !expected.empty();
    total += static_cast<int>(expected.size());
    if (trial < 8) {
      EXPECT_EQ(expected.size(), 6u);  // each cube's three faces on the far side cross the other's three
    }
    for (const auto& p : r.intersectingPairs) {
      EXPECT_DOUBLE_EQ(p.areaA, 4);
      EXPECT_DOUBLE_EQ(p.areaB, 4);
    }
    EXPECT_DOUBLE_EQ(r.surfaceArea, 48);
    EXPECT_TRUE(r.selfCrossingFaces.empty());
  }
  EXPECT_GT(withPairs, 60);
  EXPECT_GT(total, 300);
}

TEST(MeshIntersections, BowTieConcaveAndNonPlanarOutlines) {
  // a bow-tie quad (edges 0 and 2 cross), slightly non-planar
  // (lobes of unequal area: a symmetric bow-tie has zero vector area and is a degenerate face)
  const sf::PolygonMesh bow = polygonMesh({{0, 0, 0}, {3, 2, 0.01}, {3, 0, 0}, {0, 1, 0.01}}, {{0, 1, 2, 3}});
  EXPECT_EQ(sf::findSelfCrossingFaces(bow), (std::vector<int>{0}));
  // an L (6 corners, concave) and a tetris T piece with corners on straight stretches (10 corners)
  const sf::PolygonMesh l =
      polygonMesh({{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}}, {{0, 1, 2, 3, 4, 5}});
  const sf::PolygonMesh tee = polygonMesh(
      {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {3, 1, 0}, {2, 1, 0}, {2, 2, 0}, {1, 2, 0}, {1, 1, 0}, {0, 1, 0}},
      {{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}});
  // a simple non-planar quad (a saddle) and a non-convex non-planar pentagon (an arrow, bent)
  const sf::PolygonMesh saddle = polygonMesh({{0, 0, 0}, {1, 0, 0.3}, {1, 1, 0}, {0, 1, 0.3}}, {{0, 1, 2, 3}});
  const sf::PolygonMesh arrow =
      polygonMesh({{0, 0, 0}, {2, 0, 0.2}, {2, 2, 0}, {1, 0.5, 0.1}, {0, 2, 0.2}}, {{0, 1, 2, 3, 4}});
  for (const sf::PolygonMesh* m : {&l, &tee, &saddle, &arrow}) {
    EXPECT_TRUE(sf::findSelfCrossingFaces(*m).empty());
    EXPECT_TRUE(sf::checkMesh(*m).selfCrossingFaces.empty());
  }
  // the triangulation stays inside a concave outline: the area is the polygon's
  EXPECT_NEAR(sf::polygonTriangles(l).faceArea[0], 3, 1e-15);
  EXPECT_NEAR(sf::polygonTriangles(tee).faceArea[0], 4, 1e-15);
  // a bow-tie in 2D whose crossing is a shared corner position (a figure eight touching itself)
  const sf::PolygonMesh eight =
      polygonMesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {2, 1, 0}, {2, 2, 0}, {1, 2, 0}, {1, 1, 0}, {0, 1, 0}},
                  {{0, 1, 2, 3, 4, 5, 6, 7}});
  EXPECT_EQ(sf::findSelfCrossingFaces(eight), (std::vector<int>{0}));
}

// A triangle lying in the notch of an L (same plane, not touching it) does not intersect it; one
// reaching into the L does. A fan from the L's centroid would cover the notch.
TEST(MeshIntersections, TriangleInTheNotchOfAnLIsClear) {
  std::vector<Vector3d> p = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
  p.insert(p.end(), {{1.9, 1.2, 0}, {1.2, 1.9, 0}, {1.9, 1.9, 0}});
  sf::PolygonMesh m = polygonMesh(p, {{0, 1, 2, 3, 4, 5}, {6, 8, 7}});
  EXPECT_TRUE(sf::checkMesh(m).intersectingPairs.empty());
  m.positions[6] = {0.9, 0.9, 0};  // now inside the L
  const sf::MeshReport r = sf::checkMesh(m);
  ASSERT_EQ(r.intersectingPairs.size(), 1u);
  EXPECT_EQ(r.intersectingPairs[0].a, 0);
  EXPECT_EQ(r.intersectingPairs[0].b, 1);
  EXPECT_NEAR(r.intersectingPairs[0].areaA, 3, 1e-15);  // the L's area, not its centroid fan's
}

// Faces that meet only at a corner written twice (not welded) are neighbours, not intersecting;
// degenerate faces, faces of 1-2 corners and a huge polygon end the check without a throw.
TEST(MeshIntersections, UnweldedNeighboursAndDegenerateInput) {
  const sf::PolygonMesh seam =
      polygonMesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {2, 0, 0}, {1, 1, 0}}, {{0, 1, 2}, {3, 4, 5}});
  EXPECT_TRUE(sf::checkMesh(seam).intersectingPairs.empty());
  sf::PolygonMesh bad = polygonMesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {0.5, 0, 0}},
                                    {{0, 1, 2}, {0, 1, 3}, {0, 0, 1}, {0, 1}, {4, 2, 2, 4}});
  const sf::MeshReport r = sf::checkMesh(bad);
  EXPECT_TRUE(r.intersectingPairs.empty());  // the only non-degenerate triangle has nothing to meet
  EXPECT_TRUE(r.selfCrossingFaces.empty());
  std::vector<Vector3d> ring;
  std::vector<int32_t> face;
  for (int k = 0; k < 3000; ++k) {
    ring.emplace_back(std::cos(2 * M_PI * k / 3000), std::sin(2 * M_PI * k / 3000), 0);
    face.push_back(k);
  }
  const sf::MeshReport big = sf::checkMesh(polygonMesh(ring, {face}));
  EXPECT_EQ(big.selfCrossingUnchecked, 1);
  EXPECT_NEAR(big.surfaceArea, M_PI, 1e-5);
}

TEST(MeshIntersections, NearIntersectionsAreThePairsAndTheirVertexNeighbours) {
  const sf::PolygonMesh m = twoCubes(Vector3d(1, 1, 1));
  const std::vector<sf::IntersectingPair> pairs = sf::findIntersectingFaces(m);
  ASSERT_EQ(pairs.size(), 6u);
  // every face of either cube shares a vertex with one of its three crossing faces
  EXPECT_EQ(sf::facesNearIntersections(m, pairs), std::vector<char>(12, 1));
  // one pair only: its two faces and their four neighbours each
  const std::vector<char> near = sf::facesNearIntersections(m, {pairs[0]});
  int count = 0;
  for (int f = 0; f < 12; ++f) {
    const bool expected =
        f == pairs[0].a || f == pairs[0].b || touchAtCorner(m, f, pairs[0].a) || touchAtCorner(m, f, pairs[0].b);
    EXPECT_EQ(near[f] != 0, expected) << f;
    count += near[f];
  }
  EXPECT_EQ(count, 10);
  EXPECT_EQ(sf::facesNearIntersections(m, {}), std::vector<char>(12, 0));
}

// A face written 20,000 times (each copy its own face) and a triangle through it: every copy
// intersects the triangle, none the other copies (they share its vertices). The copies are tested
// once; a pair-by-pair search would make 2 x 10^8 tests.
TEST(MeshIntersections, ManyCopiesOfOneFaceAreTestedOnce) {
  sf::PolygonMesh m =
      polygonMesh({{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0.5, 0.5, -1}, {0.5, 0.5, 1}, {1.5, 0.6, 0}}, {{3, 4, 5}});
  for (int i = 0; i < 20000; ++i) m.addFace({0, 1, 2});
  const auto t0 = std::chrono::steady_clock::now();
  const sf::MeshReport r = sf::checkMesh(m);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_EQ(r.intersectingPairs.size(), 20000u);
  for (int i = 0; i < 20000; ++i) {
    EXPECT_EQ(r.intersectingPairs[i].a, 0);
    EXPECT_EQ(r.intersectingPairs[i].b, i + 1);
  }
  EXPECT_EQ(r.duplicateFaces.size(), 19999u);
  EXPECT_LT(secs, 5.0);
}
